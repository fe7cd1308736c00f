"""Robust yoke phasing, one import away: positions, tolerances and tolerance bands.

* :func:`optimise_positions` (:mod:`sso.column.positions`): one yoke phasing for
  every tilt or telescope position, worst-case or weighted mean;
* :class:`Tolerances`, :func:`optimise_robust` (:mod:`sso.column.tolerances`,
  :mod:`sso.column.robust_phasing`): RE over a seeded sample of built columns;
* :func:`tolerance_band` (:mod:`sso.column.band`): the intervals and the box of
  phase errors a drawing needs; :func:`re_against_phase_error` for its figure;
* :func:`steering_feel`, :func:`optimise_on_centre` (:mod:`sso.column.feel`): the
  ratio fluctuation on-centre and at lock, and a phasing that keeps it off-centre.

Objectives, sampling, smoothing and the band's definition: ``docs/robust.md``.
"""

from sso.column.band import (
    Interval,
    ToleranceBand,
    re_against_phase_error,
    tolerance_band,
)
from sso.column.feel import (
    OnCentreResult,
    SteeringFeel,
    optimise_on_centre,
    steering_feel,
)
from sso.column.positions import (
    PositionsResult,
    SinglePositionOptimum,
    optimise_positions,
)
from sso.column.robust_phasing import RobustResult, optimise_robust
from sso.column.tolerances import SampleStudy, Tolerances, ToleranceSample

__all__ = ["Interval", "OnCentreResult", "PositionsResult", "RobustResult", "SampleStudy",
           "SinglePositionOptimum", "SteeringFeel", "ToleranceBand", "ToleranceSample",
           "Tolerances", "optimise_on_centre", "optimise_positions", "optimise_robust",
           "re_against_phase_error", "steering_feel", "tolerance_band"]
