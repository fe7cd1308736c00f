"""The outcome of one solver run from one start, before it becomes a Solution."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class RunOutcome:
    """Raw result of one run, design vector in rad.

    Attributes mirror :class:`sso.Solution`; ``njev`` counts gradient evaluations.
    """

    x_rad: np.ndarray
    fun: float
    nit: int
    nfev: int
    njev: int
    status: int
    success: bool
    message: str
    time_s: float
