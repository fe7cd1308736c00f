"""The ``"lm"`` solver's Gauss-Newton iterations for many designs at once, in numpy.

The rules of :mod:`sso._solvers.lm_rules` evaluated on numpy arrays with one entry
per design: every variable, residual and number of the loop is a column, every
branch an ``numpy.where``, so one pass of Python runs an iteration of every design
still under way. Designs that end leave the columns every few iterations (a
compaction costs about as much as an iteration), so the long tail of a batch costs
in proportion to its size.

A design ends as the single solve's Gauss-Newton mode does: with the same status,
the same iterate and the same counts up to round-off; a design whose steps turn to
Newton steps (a minimum above zero, or a start far from the zeros with more
variables than residuals, where the Hessian is often indefinite) ends with status
:data:`sso._solvers.lm_rules.NEWTON` for the caller to finish. Only real arithmetic
is used: numpy's complex products round differently with the length of the arrays,
which would make a design's answer depend on the batch it is in.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from sso._solvers.lm_rules import (
    RUNNING,
    SCALARS,
    Operations,
    fresh_state,
    gauss_newton_iteration,
)

NUMPY = Operations(select=np.where, both=np.logical_and, either=np.logical_or,
                   negate=np.logical_not, minimum=np.minimum, maximum=np.maximum,
                   absolute=np.abs, sqrt=np.sqrt, anywhere=np.any)
"""The rules' operations on numpy arrays (one entry per design)."""

ColumnResiduals = Callable[[list[np.ndarray], list[np.ndarray]],
                           tuple[np.ndarray, np.ndarray, list[np.ndarray], list[np.ndarray]]]
"""``(point, parameters) -> (r1, r2, J1, J2)``: columns of the designs in, columns out."""

COMPACT_SHARE = 0.25
"""Finished designs leave the columns once they are this share of those iterated."""


@dataclass(frozen=True)
class BatchRun:
    """Where each design of a batch ended, as arrays (one row per design).

    Attributes
    ----------
    x : numpy.ndarray of shape (m, n)
    fun : numpy.ndarray of shape (m,)
        ``r1^2 + r2^2`` at ``x``.
    gradient : numpy.ndarray of shape (m, n)
        ``2 J^T r`` at ``x``.
    nit, nfev, status : numpy.ndarray of shape (m,)
        Trial steps, residual evaluations and the stopping reason (a key of
        :data:`sso._solvers.lm.MESSAGES`, or :data:`sso._solvers.lm_rules.NEWTON`).
    """

    x: np.ndarray
    fun: np.ndarray
    gradient: np.ndarray
    nit: np.ndarray
    nfev: np.ndarray
    status: np.ndarray


def solve_batch(residuals: ColumnResiduals, start: np.ndarray, parameters: np.ndarray,
                lower: np.ndarray, upper: np.ndarray, tolerance: float,
                max_iterations: int) -> BatchRun:
    """Run the rules' Gauss-Newton iterations of every design from its start.

    Parameters
    ----------
    residuals : callable
        ``(point, parameters) -> (r1, r2, J1, J2)`` on lists of columns.
    start : numpy.ndarray of shape (m, n)
        Starts (moved onto the bounds first).
    parameters : numpy.ndarray of shape (m, k)
        Each design's fixed values, handed to ``residuals``.
    lower, upper : numpy.ndarray of shape (n,)
        Bounds shared by every design.
    tolerance : float
        Projected-gradient tolerance (infinity norm, per unit of ``x``).
    max_iterations : int
        Trial steps per design, at most.
    """
    count, size = start.shape
    lower_list, upper_list = lower.tolist(), upper.tolist()
    rows = np.arange(count)
    columns = list(np.asarray(parameters, dtype=float).T)
    out = {name: np.zeros(count) for name in SCALARS}
    out_x, out_gradient = np.zeros((count, size)), np.zeros((count, size))

    def evaluate(point: list[Any]) -> tuple[Any, Any, list[Any], list[Any]]:
        return residuals(point, columns)

    with np.errstate(all="ignore"):
        state = fresh_state(NUMPY, evaluate, list(start.T), lower_list, upper_list)
        state.update({name: np.broadcast_to(np.asarray(state[name], dtype=float), (count,))
                      for name in SCALARS})
        while rows.size:
            state = gauss_newton_iteration(NUMPY, evaluate, state, lower_list, upper_list,
                                           tolerance, max_iterations)
            going = state["status"] == RUNNING
            ended = rows.size - np.count_nonzero(going)
            if not ended or (ended < COMPACT_SHARE * rows.size and going.any()):
                continue
            done = ~going
            finished = rows[done]
            for name in SCALARS:
                out[name][finished] = state[name][done]
            out_x[finished] = np.column_stack(state["x"])[done]
            out_gradient[finished] = 2.0 * (
                np.column_stack(state["J1"])[done] * state["r1"][done, None]
                + np.column_stack(state["J2"])[done] * state["r2"][done, None])
            rows = rows[going]
            columns = [column[going] for column in columns]
            state = {name: ([entry[going] for entry in value] if isinstance(value, list)
                            else value[going]) for name, value in state.items()}
    return BatchRun(out_x, out["fun"], out_gradient, out["nit"].astype(int),
                    out["nfev"].astype(int), out["status"].astype(int))
