"""A column tolerance study judged against the case's limits: yields, sensitivity, halving.

From the study's own sample (:mod:`sso._studies.column_tolerance`):

* the yield of each limit and of all together, with its confidence interval and the
  verdict against the required yield (:mod:`sso._column.yields`);
* for each limited figure that some built column fails, the first-order sensitivity
  index of every tolerance (:mod:`sso._column.sensitivity`): each coordinate of each
  hardpoint (``P0 x`` .. ``P(n+1) z``, mm) and each yoke phasing's error
  (``delta_k``, deg: spline clearance and assembly), ranked;
* for the largest contributor of each such figure, the yields re-sampled with that
  one tolerance halved: the study's draws with that input's errors halved and every
  other error as drawn (common random numbers), each built column evaluated again,
  so the change is that tolerance's alone and no figure is extrapolated.

The draws are read through views and halved in place (each put back), so the judgement
holds no second copy of a study's samples.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from sso._column.sensitivity import (
    MIN_SAMPLES,
    FigureSensitivity,
    first_order_index,
    ranked,
)
from sso._column.yields import YieldJudgement, judge_yields
from sso._record import register_record

Evaluate = Callable[[np.ndarray, np.ndarray], dict[str, np.ndarray]]
"""Figures of built columns from their hardpoint errors ``(samples, n + 2, 3)`` mm and
yoke phase errors ``(samples, n - 1)`` deg."""


@register_record
@dataclass(frozen=True)
class HalvedTolerance:
    """The yields with one tolerance halved, re-sampled.

    Attributes
    ----------
    tolerance : str
        The input halved (as :class:`sso._column.sensitivity.Contribution` names it).
    tolerance_value, unit : float, str
        Its halved tolerance (standard deviation or half-width) and unit.
    largest_in : tuple of str
        The figures whose largest contributor it is.
    yields : YieldJudgement
        The yields of the re-sampled built columns.
    """

    tolerance: str
    tolerance_value: float
    unit: str
    largest_in: tuple[str, ...]
    yields: YieldJudgement


@dataclass(frozen=True)
class StudyJudgement:
    """What :func:`judge_study` gives the study's result."""

    yields: YieldJudgement
    sensitivity: tuple[FigureSensitivity, ...]
    halved: tuple[HalvedTolerance, ...]


def input_names(points: int, shafts: int) -> tuple[str, ...]:
    """Names of the tolerances, in the order of :func:`input_matrix`'s columns."""
    return (*(f"P{point} {axis}" for point in range(points) for axis in "xyz"),
            *(f"delta_{shaft + 1}" for shaft in range(shafts)))


def input_columns(offsets_mm: np.ndarray, phase_errors_deg: np.ndarray) -> list[np.ndarray]:
    """Every sample's error of each tolerance of :func:`input_names`: views into the
    draws, no copies (a study may hold millions of samples)."""
    return [*(offsets_mm[:, point, axis] for point in range(offsets_mm.shape[1])
              for axis in range(3)),
            *(phase_errors_deg[:, shaft] for shaft in range(phase_errors_deg.shape[1]))]


def judge_study(offsets_mm: np.ndarray, phase_errors_deg: np.ndarray,
                figures: dict[str, np.ndarray], limits: tuple[tuple[str, str, str, float], ...],
                required: float | None, hardpoint_mm: float, yoke_phase_deg: float,
                evaluate: Evaluate) -> StudyJudgement:
    """Yields, sensitivity indices and the halved largest contributors (module notes).

    Parameters
    ----------
    offsets_mm, phase_errors_deg : numpy.ndarray
        The study's draws, shapes ``(samples, n + 2, 3)`` and ``(samples, n - 1)``.
    figures : dict of str to numpy.ndarray
        Each figure per built column, including every limited one.
    limits, required
        As :func:`sso._column.yields.judge_yields`.
    hardpoint_mm, yoke_phase_deg : float
        The tolerances drawn from (for the halved values).
    evaluate : callable
        Figures of other draws (:data:`Evaluate`).
    """
    yields = judge_yields(figures, limits, required)
    names = input_names(offsets_mm.shape[1], phase_errors_deg.shape[1])
    columns = input_columns(offsets_mm, phase_errors_deg)
    sensitivity = []
    for item, (figure, label, unit, _) in zip(yields.limits, limits, strict=True):
        if item.passed == item.samples or item.samples < MIN_SAMPLES:
            continue
        indices = np.array([first_order_index(column, figures[figure])
                            if np.any(column != 0.0) else 0.0 for column in columns])
        sensitivity.append(FigureSensitivity(figure, label, unit, ranked(names, indices)))
    largest: dict[str, list[str]] = {}
    for found in sensitivity:
        largest.setdefault(found.contributions[0].tolerance, []).append(found.label)
    halved = []
    for name, figure_labels in largest.items():
        column = columns[names.index(name)]
        drawn = column.copy()
        # halved in place and put back: the draws are not copied whole
        column *= 0.5
        try:
            figures_halved = evaluate(offsets_mm, phase_errors_deg)
        finally:
            column[:] = drawn
        value, unit = ((hardpoint_mm / 2.0, "mm") if name.startswith("P")
                       else (yoke_phase_deg / 2.0, "deg"))
        halved.append(HalvedTolerance(name, value, unit, tuple(figure_labels),
                                      judge_yields(figures_halved, limits, required)))
    return StudyJudgement(yields, tuple(sensitivity), tuple(halved))
