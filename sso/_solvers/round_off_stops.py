"""Whether a least-squares stop at round-off is a minimum: every variable moved a little.

A bounded Levenberg-Marquardt stops when its step or its decrease reaches round-off.
At a minimum no move helps. Where the residuals change by more than their size within a
rounding of ``x`` (a chain of joints near 90 deg: 12 joints at 89.9999999998 deg, where
the residual's slope in one phase is 1e15 times the residual per rad), the damping grows
until the steps vanish while other variables still lower the sum of squares by orders
of magnitude: such a stop was reported as converged with RE 7.7e100. Here each such stop
is tested by moving one variable at a time; a move that lowers the sum refutes it.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

ROUND_OFF_STOPS = (2, 3)
"""Statuses of ``"lm"`` and of the batched least squares that stop at round-off: the
actual and predicted reductions (2) or the step (3)."""

REFUTED = -4
"""Status of a round-off stop that a move of one variable improves on."""

REFUTED_MESSAGE = ("stopped at round-off, but a move of one variable lowers the sum of "
                   "squares (not a minimum: the problem is beyond floating point's "
                   "resolution there)")

PROBE_STEPS = (1e-9, 1e-6, 1e-3)
"""Moves of one variable (NLP units, rad for a shaft series) tried at a round-off stop."""

PROBE_DECREASE = 1e-6
"""A move that lowers the sum of squares by more than this fraction refutes the stop."""

SUSPECT_GRADIENT = 1e-6
"""The batched check tests only the stops whose gradient (infinity norm over the variables
off their bounds) is above this: a stop at a minimum above zero has one near 1e-9."""


def holds(sum_of_squares: Callable[[list[float]], float], x: list[float], fun: float,
          lower: list[float], upper: list[float]) -> tuple[bool, int]:
    """Whether no move of one variable by :data:`PROBE_STEPS` (either way, within the
    bounds) lowers ``fun`` by more than :data:`PROBE_DECREASE` of it; and the
    evaluations spent (the first improving move ends the search)."""
    evaluations = 0
    for index, value in enumerate(x):
        for size in PROBE_STEPS:
            for moved in (value - size, value + size):
                if not lower[index] <= moved <= upper[index]:
                    continue
                point = list(x)
                point[index] = moved
                evaluations += 1
                if sum_of_squares(point) < fun * (1.0 - PROBE_DECREASE):
                    return False, evaluations
    return True, evaluations


def refuted(sum_of_squares: Callable[[np.ndarray, np.ndarray], np.ndarray], x: np.ndarray,
            fun: np.ndarray, lower: np.ndarray, upper: np.ndarray,
            rows: np.ndarray) -> np.ndarray:
    """Which of ``rows`` (designs of a batch) a move of one variable improves on.

    Parameters
    ----------
    sum_of_squares : callable
        ``(points, rows) -> sums``: the sum of squares at ``points`` (shape
        ``(k, free)``) of the designs ``rows`` (shape ``(k,)``).
    x, fun : numpy.ndarray
        Every design's point (shape ``(m, free)``) and sum of squares.
    lower, upper : numpy.ndarray
        Bounds of the variables (shape ``(free,)``).
    rows : numpy.ndarray
        Indices of the designs to test.

    Returns
    -------
    numpy.ndarray of bool, shape like ``rows``
    """
    improved = np.zeros(len(rows), dtype=bool)
    for index in range(x.shape[1]):
        for size in PROBE_STEPS:
            for sign in (-1.0, 1.0):
                points = x[rows].copy()
                points[:, index] += sign * size
                inside = (points[:, index] >= lower[index]) & (points[:, index] <= upper[index])
                if not inside.any():
                    continue
                values = sum_of_squares(points[inside], rows[inside])
                improved[np.flatnonzero(inside)[values < fun[rows[inside]]
                                                * (1.0 - PROBE_DECREASE)]] = True
    return improved
