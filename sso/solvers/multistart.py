"""Run each solver from each start and measure every answer on the same graph."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Iterable, Sequence

import numpy as np

from sso.solvers.kkt import constraint_violation, kkt_residual
from sso.solvers.run import RunLimits, RunOutcome
from sso.solvers.saddle import solve_with_second_order_care
from sso.solvers.solution import SeriesDesign, Solution


@dataclass(frozen=True)
class MeasuredRun:
    """One run, re-measured independently of what the solver says of itself.

    Attributes
    ----------
    solver : str
    start_index : int
        Which start the run began from (0 is the user's start).
    outcome : RunOutcome
        The solver's report, with ``x`` clipped onto the bounds (IPOPT relaxes
        them slightly).
    fun : float
        Objective at ``outcome.x``, from the shared graph.
    kkt : float
        Stationarity error at ``outcome.x`` (see :func:`sso.solvers.kkt.kkt_residual`).
    violation : float
        Largest bound or constraint violation at ``outcome.x``.
    """

    solver: str
    start_index: int
    outcome: RunOutcome
    fun: float
    kkt: float
    violation: float


def run_starts(
    nlp: Any,
    points: np.ndarray,
    parameters: np.ndarray,
    limits: RunLimits,
    solver_names: Sequence[str],
    tolerance: float,
    max_iterations: int,
) -> dict[str, list[MeasuredRun]]:
    """Every solver from every start, in order; failures are kept, never raised.

    Each run skips the solver at a start that is already a minimum and restarts
    it off saddle points (:mod:`sso.solvers.saddle`).

    Parameters
    ----------
    nlp : sso.solvers.nlp.CompiledNLP
        The problem graph.
    points : numpy.ndarray
        Starts, shape ``(starts, len(x))``.
    parameters : numpy.ndarray
        Fixed parameters of the graph.
    limits : RunLimits
        Bounds of ``x`` and of the constraints.
    solver_names : sequence of {"ipopt", "slsqp", "lm"}
    tolerance : float
        Solver tolerance.
    max_iterations : int
        Iteration limit of each run.

    Returns
    -------
    dict of str to list of MeasuredRun
    """
    runs: dict[str, list[MeasuredRun]] = {}
    for name in solver_names:
        backend = _backend(name)

        def solve(start: np.ndarray) -> RunOutcome:
            return backend.solve(nlp, start, parameters, limits, tolerance, max_iterations)

        runs[name] = [
            _measure(name, index, solve_with_second_order_care(solve, nlp, point, parameters,
                                                               limits, tolerance),
                     nlp, parameters, limits)
            for index, point in enumerate(points)
        ]
    return runs


def best_solution(solutions: Iterable[Solution]) -> Solution:
    """Lowest objective among successful solutions (among all, if none succeeded)."""
    return min(solutions, key=lambda solution: (not solution.success, solution.fun))


def distinct_minima(solutions: Iterable[Solution], rtol: float, atol: float) -> tuple[float, ...]:
    """Objective values of the successful solutions, merged when within tolerance."""
    minima: list[float] = []
    for value in sorted(solution.fun for solution in solutions if solution.success):
        if not minima or value - minima[-1] > atol + rtol * abs(value):
            minima.append(value)
    return tuple(minima)


def solution_from_run(
    run: MeasuredRun,
    solver_runs: Sequence[MeasuredRun],
    x: Sequence[float] | None = None,
    series: SeriesDesign | None = None,
) -> Solution:
    """The :class:`sso.Solution` of one measured run.

    Parameters
    ----------
    run : MeasuredRun
    solver_runs : sequence of MeasuredRun
        Every run of the same solver (for ``total_nfev``).
    x : sequence of float, optional
        The design vector in the problem's user-facing units (default: the NLP's).
    series : sso.ShaftSeries, optional
        The shaft-series design, for shaft-series problems.
    """
    return Solution(
        solver=run.solver,
        series=series,
        x=tuple(float(value) for value in (run.outcome.x if x is None else x)),
        fun=run.fun,
        nit=run.outcome.nit,
        nfev=run.outcome.nfev,
        status=run.outcome.status,
        success=run.outcome.success,
        message=run.outcome.message,
        kkt=run.kkt,
        time_s=run.outcome.time_s,
        start_index=run.start_index,
        total_nfev=sum(other.outcome.nfev for other in solver_runs),
        constraint_violation=run.violation,
    )


def _backend(name: str) -> Any:
    if name == "ipopt":
        from sso.solvers import ipopt

        return ipopt
    if name == "lm":
        from sso.solvers import lm

        return lm
    from sso.solvers import slsqp

    return slsqp


def _measure(name: str, start_index: int, outcome: RunOutcome, nlp: Any,
             parameters: np.ndarray, limits: RunLimits) -> MeasuredRun:
    x = np.clip(np.nan_to_num(outcome.x, nan=0.0), limits.lower, limits.upper)
    value, gradient = nlp.objective_and_gradient(x, parameters)
    gradient = np.array(gradient, dtype=float).ravel()
    constraint_values = constraint_jacobian = None
    if limits.constrained:
        constraint_values, constraint_jacobian = nlp.constraints_and_jacobian(x, parameters)
        constraint_values = np.array(constraint_values, dtype=float).ravel()
        constraint_jacobian = np.array(constraint_jacobian, dtype=float)
    return MeasuredRun(
        solver=name,
        start_index=start_index,
        outcome=RunOutcome(x, outcome.fun, outcome.nit, outcome.nfev, outcome.njev,
                           outcome.status, outcome.success, outcome.message, outcome.time_s),
        fun=float(value),
        kkt=kkt_residual(x, gradient, limits, constraint_values, constraint_jacobian),
        violation=constraint_violation(x, limits, constraint_values),
    )
