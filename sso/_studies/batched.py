"""Sweep points of one shape solved together by the least-squares solver, as array work.

A sweep point whose case is a shaft series of the exact model with ``"lm"`` alone
(``solver.solvers = ["lm"]``) and more than one start is, start by start, a problem of
:func:`sso.optimise_batch`: the closed form's two residuals under box bounds. The
points of a chunk that share a shape (joints, option, bounds, solver tolerance and
iteration limit: ``optimise_batch`` takes one set of bounds and settings for all its
rows) are solved by one ``optimise_batch`` call over all their starts, instead of
one :func:`sso.optimise` call each.

Each point's starts are the ones :func:`sso.optimise` uses:
:func:`sso._solvers.starts.start_points` of the point's own start, bounds, start
count and seed, in the NLP's units (rad), handed over in degrees (the user's start
exactly, the space-filling ones within a rounding of the rad value). Each point keeps
its best start, a converged one first, then the lowest RE. Its row has the columns
of the point-by-point path (:func:`sso._studies.worker.run_point`): the optimum's
figures from :meth:`sso.ShaftSeries.evaluate`, the design, ``success``,
``best_solver`` (``"lm"``) and the ``lm_*`` columns, whose status and message are
the batched solver's (:data:`sso._solvers.lm.MESSAGES`) and whose
time is the point's share of the call, in proportion to its starts.

``sso.optimise`` with ``"lm"`` alone screens the starts in turn, stops at the first
that reaches round-off zero (a global minimum: RE is never negative) and runs
``"lm"`` once more, with second-order checks, from the best. The batch does the same
in two calls: every point's own start first, then the other starts of only those
points whose own start stopped above zero (each batch with its own saddle checks).
Where a start reaches zero both answers are zero; elsewhere both keep the lowest
minimum the starts reach (tests/studies/test_batched.py checks a sample against
``sso.optimise`` to 1e-12 in RE).
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np

from sso._shafts.batch import BatchResult, optimise_batch
from sso._shafts.options import DesignProblem, build_problem, warn_moved_starts
from sso._shafts.series import ShaftSeries
from sso._solvers.saddle import ZERO_OBJECTIVE
from sso._solvers.starts import start_points
from sso._studies.point_row import PointRow, design_columns, solver_columns

BATCHED_SOLVERS = ("lm",)
"""The solver list of a point solved in a batch: the least-squares solver alone."""


def batchable(case: Any) -> bool:
    """Whether :func:`sso.optimise_batch` solves the point's case: a shaft series of the
    exact model whose only solver is ``"lm"``, from more than one start.

    A point with one start is one solve, which :func:`sso.optimise` does faster than
    a share of a batch call (``benchmarks/sweep_throughput.py --lm-only`` measured the
    batch at 0.66x point by point with one start, 0.99x with 4 and 0.97x with 8 on a
    grid whose points cancel, with the iterations in CasADi's virtual machine for the
    single solve and on numpy columns for the batch); both run the same functions of
    the shape now (:mod:`sso._solvers.lm_kernel`).
    """
    return (getattr(case, "kind", None) == "shaft_series" and case.model == "exact"
            and tuple(case.solvers) == BATCHED_SOLVERS and case.starts > 1)


@dataclass(frozen=True)
class _Member:
    """A point waiting for its group: its row, case, problem and starts (deg)."""

    row: PointRow
    case: Any
    problem: DesignProblem
    beta_deg: np.ndarray
    phase_deg: np.ndarray

    @property
    def shape(self) -> tuple[Any, ...]:
        """What one ``optimise_batch`` call must share."""
        return (self.problem.n_joints, self.problem.option, self.problem.beta_bounds_deg,
                self.problem.phase_bounds_deg, self.case.solver_tol, self.case.max_iterations)


class BatchedPoints:
    """The batchable points of a chunk, grouped by shape until they are solved.

    Parameters
    ----------
    fallback : callable
        ``case -> result cells`` of the point-by-point path, for the points of a
        group whose batch call itself raised (each point then fails alone, if at all).
    """

    def __init__(self, fallback: Callable[[Any], dict[str, Any]]) -> None:
        self._fallback = fallback
        self._groups: dict[tuple[Any, ...], list[_Member]] = {}

    def add(self, row: PointRow, case: Any) -> None:
        """Lay out the point's problem and starts and keep it for its group.

        A point whose problem cannot be laid out becomes an error row here.
        """
        member = row.attempt(lambda: _member(row, case))
        if member is not None:
            self._groups.setdefault(member.shape, []).append(member)

    def solve(self) -> None:
        """Solve each group with one ``optimise_batch`` call and fill its points' rows."""
        for members in self._groups.values():
            self._solve_group(members)
        self._groups.clear()

    def _solve_group(self, members: list[_Member]) -> None:
        """Two batch calls: every point's own start, then the other starts of the points
        whose own start stopped above round-off zero (as ``sso.optimise`` stops there)."""
        first = members[0]
        started = time.perf_counter()
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                own = self._optimise(first, [member.beta_deg[:1] for member in members],
                                     [member.phase_deg[:1] for member in members])
                rest = [index for index, member in enumerate(members)
                        if len(member.beta_deg) > 1
                        and not (own.success[index] and own.fun[index] <= ZERO_OBJECTIVE)]
                others = (self._optimise(first, [members[index].beta_deg[1:] for index in rest],
                                         [members[index].phase_deg[1:] for index in rest])
                          if rest else None)
        except Exception:  # noqa: BLE001 - a setting the batch refuses: solve the points
            # apart, so that each fails (or not) on its own and no row is lost
            for member in members:
                member.row.fill(partial(self._fallback, member.case))
            return
        starts_solved = len(members) + sum(len(members[index].beta_deg) - 1 for index in rest)
        per_start_s = (time.perf_counter() - started) / starts_solved
        shared = [str(warning.message) for warning in caught]
        candidates: list[list[tuple[BatchResult, int]]] = [[(own, index)]
                                                            for index in range(len(members))]
        end = 0
        for index in rest:
            count = len(members[index].beta_deg) - 1
            begin, end = end, end + count
            assert others is not None
            candidates[index] += [(others, row) for row in range(begin, end)]
        for member, choices in zip(members, candidates, strict=True):
            solved, best = min(choices, key=lambda choice: (not choice[0].success[choice[1]],
                                                             choice[0].fun[choice[1]]))
            time_s = per_start_s * len(choices)
            member.row.busy_s += time_s
            member.row.notes.extend(shared)
            member.row.fill(partial(_row, member.case, solved, solved.message, best, time_s))

    @staticmethod
    def _optimise(first: _Member, beta_deg: list[np.ndarray],
                  phase_deg: list[np.ndarray]) -> BatchResult:
        """One ``optimise_batch`` call over the given starts with the group's settings."""
        return optimise_batch(np.vstack(beta_deg), np.vstack(phase_deg),
                              option=first.problem.option,
                              beta_bounds_deg=first.problem.beta_bounds_deg,
                              phase_bounds_deg=first.problem.phase_bounds_deg,
                              solver_tol=first.case.solver_tol,
                              max_iterations=first.case.max_iterations)


def _member(row: PointRow, case: Any) -> _Member:
    """The point's problem (as :func:`sso.optimise` lays it out) and its starts, deg."""
    series = case.series()
    problem = build_problem(series.beta_deg, series.phase_deg, series.model, case.option,
                            case.beta_bounds_deg, case.phase_bounds_deg)
    warn_moved_starts(problem)  # the row's notes, as sso.optimise reports them
    points_rad = start_points(problem.start_rad, problem.lower_rad, problem.upper_rad,
                              case.starts, case.seed)
    free_bounds = [*(problem.beta_bounds_deg if problem.beta_free else ()),
                   *(problem.phase_bounds_deg if problem.phase_free else ())]
    lower, upper = np.array(free_bounds, dtype=float).reshape(-1, 2).T
    x_deg = np.clip(np.degrees(points_rad), lower, upper)
    x_deg[0] = problem.start_deg  # the user's start, exactly as given (moved onto its bounds)
    # The problem's own layout of free and fixed angles, every start at once.
    beta, phase = problem.split(list(x_deg.T), list(problem.parameters_deg))
    return _Member(row, case, problem, _columns(beta, len(x_deg)), _columns(phase, len(x_deg)))


def _columns(angles: Sequence[Any], rows: int) -> np.ndarray:
    """Angles (each one per start, or one fixed value) as an array of shape (rows, angles)."""
    return np.array([np.broadcast_to(angle, (rows,)) for angle in angles],
                    dtype=float).T.reshape(rows, len(angles))


def _row(case: Any, solved: BatchResult, messages: tuple[str, ...], best: int,
         time_s: float) -> dict[str, Any]:
    """The result cells of a point from its best start, as the point-by-point path gives them."""
    series = ShaftSeries([float(value) for value in solved.beta_deg[best]],
                         [float(value) for value in solved.phase_deg[best]], case.model)
    evaluation = series.evaluate(case.input_speed_rpm, quadrature_rtol=case.quadrature_rtol,
                                 quadrature_atol=case.quadrature_atol)
    converged = bool(solved.success[best])
    return {
        **design_columns(evaluation, series.beta_deg, series.phase_deg),
        "success": converged and evaluation.quadrature_converged,
        "best_solver": BATCHED_SOLVERS[0],
        **solver_columns(BATCHED_SOLVERS[0], float(solved.fun[best]), int(solved.status[best]),
                         converged, messages[best], float(solved.kkt[best]), time_s),
    }
