"""Robust yoke phasing, one import away: positions, tolerances and tolerance bands.

* :func:`optimise_positions` (:mod:`sso.column.positions`): one yoke phasing for
  every tilt or telescope position, worst-case or weighted mean;
* :class:`Tolerances`, :func:`optimise_robust` (:mod:`sso.column.tolerances`,
  :mod:`sso.column.robust_phasing`): RE over a seeded sample of built columns;
* :func:`tolerance_band` (:mod:`sso.column.band`): the intervals and the box of
  phase errors a drawing needs.

Objectives, sampling, smoothing and the band's definition: ``docs/robust.md``.
"""

from sso.column.band import Interval, ToleranceBand, tolerance_band
from sso.column.positions import (
           PositionsResult,
           SinglePositionOptimum,
           optimise_positions,
)
from sso.column.robust_phasing import RobustResult, optimise_robust
from sso.column.tolerances import SampleStudy, Tolerances, ToleranceSample

__all__ = ["Interval", "PositionsResult", "RobustResult", "SampleStudy",
           "SinglePositionOptimum", "ToleranceBand", "ToleranceSample", "Tolerances",
           "optimise_positions", "optimise_robust", "tolerance_band"]
