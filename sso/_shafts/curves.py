"""The designs a report compares, each with the speed curve its plots draw.

A result carries what its report shows: each design with its evaluation and its
output speed over one input revolution, so no report rebuilds a design or
recomputes a figure.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from sso._record import register_record
from sso._shafts.evaluation import Evaluation
from sso._shafts.series import ShaftSeries

CURVE_STEP_DEG = 1.0
"""Input-angle step of the speed curves, deg (0 to 360 inclusive)."""
DESIGN_ROLES = ("initial", "optimum", "reference")
"""The roles a design plays in a report, in the order reports list them."""


@register_record
@dataclass(frozen=True, eq=False)
class ComparedDesign:
    """One design of a report, with its figures and its speed curve.

    Attributes
    ----------
    role : {"initial", "optimum", "reference"}
    label : str
        How the report names it.
    series : sso.ShaftSeries
    evaluation : sso.Evaluation
        Its figures at the report's input speed.
    input_angle_deg : numpy.ndarray
        Input shaft angles, deg, 0 to 360 by :data:`CURVE_STEP_DEG`.
    output_speed_rpm : numpy.ndarray
        Output speed at each input angle, rpm (input at ``evaluation.input_speed_rpm``).
    """

    role: str
    label: str
    series: ShaftSeries
    evaluation: Evaluation
    input_angle_deg: np.ndarray
    output_speed_rpm: np.ndarray

    def __post_init__(self) -> None:
        if self.role not in DESIGN_ROLES:
            raise ValueError(f"role = {self.role!r}; allowed: {', '.join(DESIGN_ROLES)}")
        if self.input_angle_deg.shape != self.output_speed_rpm.shape:
            raise ValueError("input_angle_deg and output_speed_rpm differ in length")


def compared_design(role: str, label: str, series: ShaftSeries,
                    evaluation: Evaluation) -> ComparedDesign:
    """``series`` as a report's design: its speed curve computed once, here."""
    count = int(round(360.0 / CURVE_STEP_DEG))
    angle_deg = np.linspace(0.0, 360.0, count + 1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        output = evaluation.input_speed_rpm * series.speed_ratio(angle_deg)
    return ComparedDesign(role, label, series, evaluation, angle_deg, np.asarray(output))
