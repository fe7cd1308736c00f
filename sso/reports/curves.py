"""Speed curves of the designs in a result document, recomputed with NumPy only."""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from sso.run.document import DESIGN_ROLES
from sso.shafts.series import ShaftSeries

CURVE_STEP_DEG = 1.0


@dataclass(frozen=True)
class SpeedCurves:
    """Input and output speeds of each design over one input revolution.

    Attributes
    ----------
    input_angle_deg : numpy.ndarray
        Input shaft angles, deg, from 0 to 360 inclusive.
    input_speed_rpm : float
        Constant input speed, rpm.
    output_speed_rpm : dict of str to numpy.ndarray
        Output speed (rpm) of each design role present (``initial``, ``optimum``,
        ``reference``), in that order.
    labels : dict of str to str
        Each role's label as the document names it.
    """

    input_angle_deg: np.ndarray
    input_speed_rpm: float
    output_speed_rpm: dict[str, np.ndarray]
    labels: dict[str, str]


def speed_curves(document: Mapping[str, Any], step_deg: float = CURVE_STEP_DEG) -> SpeedCurves:
    """Recompute the speed curves of every design in ``document``.

    Parameters
    ----------
    document : mapping
        A result document (:mod:`sso.run.document`), e.g. read from ``result.json``.
    step_deg : float
        Input-angle step, deg.

    Returns
    -------
    SpeedCurves
    """
    count = int(round(360.0 / step_deg))
    angle_deg = np.linspace(0.0, 360.0, count + 1)
    speed_rpm = float(document["input_speed_rpm"])
    designs = document["designs"]
    output: dict[str, np.ndarray] = {}
    labels: dict[str, str] = {}
    for role in DESIGN_ROLES:
        if role not in designs:
            continue
        design = designs[role]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            series = ShaftSeries(design["beta_deg"], design["phase_deg"], document["model"])
        output[role] = speed_rpm * series.speed_ratio(angle_deg)
        labels[role] = design["label"]
    return SpeedCurves(angle_deg, speed_rpm, output, labels)
