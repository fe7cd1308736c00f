"""The one multi-start driver: each solver from each start, every answer measured on
the same graph, the best kept and the solvers cross-checked."""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, TypedDict

import numpy as np

from sso._limits import BATCH_SCREEN_STARTS
from sso._record import built, rebuilt
from sso._solvers import lm
from sso._solvers.crosscheck import crosscheck
from sso._solvers.kkt import constraint_violation, kkt_residual, projected_gradient_norm_floats
from sso._solvers.lm_kernel import kernels_of, problem_vector, solve_states
from sso._solvers.nlp import value_and_gradient_floats
from sso._solvers.run import Backend, RunLimits, RunOutcome
from sso._solvers.saddle import ZERO_OBJECTIVE, isolated_minimum, solve_with_second_order_care
from sso._solvers.solution import (
    ROLE_CONFIRMATION,
    ROLE_FROM_SCREEN,
    ROLE_SCREEN,
    ROLE_SOLVE,
    CrossCheck,
    SeriesDesign,
    Solution,
)
from sso._solvers.starts import start_points


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
        Stationarity error at ``outcome.x`` (see :func:`sso._solvers.kkt.kkt_residual`).
    violation : float
        Largest bound or constraint violation at ``outcome.x``.
    """

    solver: str
    start_index: int
    outcome: RunOutcome
    fun: float
    kkt: float
    violation: float


class SolverFields(TypedDict):
    """The solver part of a :class:`sso._solvers.result.DesignResult`."""

    best: Solution
    solutions: dict[str, Solution]
    runs: tuple[Solution, ...]
    crosscheck: CrossCheck | None
    local_minima: tuple[float, ...]
    confirmations: dict[str, Solution]


def solve_from_starts(
    nlp: Any, user_start: np.ndarray, limits: RunLimits, parameters: np.ndarray, *,
    solver_names: Sequence[str], starts: int, seed: int, solver_tol: float,
    max_iterations: int, to_solution: Callable[[MeasuredRun, list[MeasuredRun]], Solution],
    objective_rtol: float, objective_atol: float, kkt_tolerance: float,
    progress: Callable[[], None] | None = None, screen_starts: bool = False,
) -> SolverFields:
    """Solve one design problem from ``starts`` points with every solver.

    Parameters
    ----------
    nlp : sso._solvers.nlp.CompiledNLP
        The problem graph.
    user_start : numpy.ndarray
        The user's start (inside ``limits``); the other starts fill the bounds.
    limits : RunLimits
        Bounds of ``x`` and of the constraints.
    parameters : numpy.ndarray
        Fixed parameters of the graph.
    solver_names, starts, seed, solver_tol, max_iterations
        As in :func:`sso.optimise`.
    to_solution : callable
        ``(run, runs of its solver) -> Solution`` in the problem's own units.
    objective_rtol, objective_atol, kkt_tolerance : float
        Tolerances of the cross-check and of merging equal minima.
    progress : callable, optional
        Called once after each solver run (for a progress bar).
    screen_starts : bool
        For a least-squares problem (``nlp.residuals_and_jacobian``) with more
        than one start or more than one solver (a single solver from a single
        start always runs alone): solve the starts with ``"lm"`` first, stopping at the
        first that reaches a nonnegative objective's round-off zero (a global
        minimum); then each of ``solver_names`` solves from one common start (the
        user's, unless it is already at round-off zero) with its own iterations, and
        those answers are cross-checked; a solver whose own answer is worse than the
        screen's best also runs from that point (``confirmations``).
        When the user's start does not reach zero and at least
        :data:`sso._limits.BATCH_SCREEN_STARTS` starts remain (and the problem has
        ``nlp.residuals``), the rest are solved in one batch
        (:func:`sso._solvers.lm_kernel.solve_states`).
        The screening runs come first in ``runs``; each solver's own answer is in
        ``solutions``; the reported best is the lowest of every run.

    Returns
    -------
    SolverFields
        The fields every :class:`sso._solvers.result.DesignResult` carries.
    """
    if starts == 1 and len(solver_names) == 1:
        return _solve_alone(nlp, user_start, limits, parameters, solver_names[0], solver_tol,
                            max_iterations, to_solution, objective_rtol, objective_atol,
                            progress)
    points = start_points(user_start, limits.lower, limits.upper, starts, seed)
    if (screen_starts and nlp.residuals_and_jacobian is not None
            and (len(points) > 1 or len(solver_names) > 1)):
        return _screen_then_cross_check(
            nlp, points, parameters, limits, solver_names=solver_names, solver_tol=solver_tol,
            max_iterations=max_iterations, to_solution=to_solution,
            objective_rtol=objective_rtol, objective_atol=objective_atol,
            kkt_tolerance=kkt_tolerance, progress=progress)
    measured = run_starts(nlp, points, parameters, limits, solver_names, solver_tol,
                          max_iterations, progress)
    solver_runs = {name: [_with_role(to_solution(run, runs), ROLE_SOLVE) for run in runs]
                   for name, runs in measured.items()}
    solutions = {name: runs[0] if len(runs) == 1 else best_solution(runs)
                 for name, runs in solver_runs.items()}
    all_runs = [run for runs in solver_runs.values() for run in runs]
    crosscheck = None
    if len(solutions) > 1:
        chosen = {name: next(run for run, solution in zip(measured[name], solver_runs[name],
                                                          strict=True)
                             if solution is solutions[name]) for name in solutions}
        crosscheck = _cross_check(nlp, parameters, limits, chosen, solutions, objective_rtol,
                                  objective_atol, kkt_tolerance)
    return SolverFields(
        best=best_solution(solutions.values()),
        solutions=solutions,
        runs=tuple(all_runs),
        crosscheck=crosscheck,
        local_minima=distinct_minima(all_runs, objective_rtol, objective_atol),
        confirmations={},
    )


def _solve_alone(nlp: Any, start: np.ndarray, limits: RunLimits, parameters: np.ndarray,
                 solver_name: str, solver_tol: float, max_iterations: int,
                 to_solution: Callable[[MeasuredRun, list[MeasuredRun]], Solution],
                 objective_rtol: float, objective_atol: float,
                 progress: Callable[[], None] | None) -> SolverFields:
    """One solver from the user's start: the fields the multi-start path gives for one
    solver and one start (its run, measured, is its answer and the best; no screen, no
    cross-check), without laying out starts or grouping runs by solver."""
    run = _run_one(nlp, np.asarray(start, dtype=float), 0, parameters, limits,
                   _backend(solver_name), solver_name, solver_tol, max_iterations, True, True)
    if progress is not None:
        progress()
    solution = _with_role(to_solution(run, [run]), ROLE_SOLVE)
    return SolverFields(best=solution, solutions={solver_name: solution}, runs=(solution,),
                        crosscheck=None,
                        local_minima=distinct_minima((solution,), objective_rtol,
                                                     objective_atol),
                        confirmations={})


def _screen_then_cross_check(
    nlp: Any, points: np.ndarray, parameters: np.ndarray, limits: RunLimits, *,
    solver_names: Sequence[str], solver_tol: float, max_iterations: int,
    to_solution: Callable[[MeasuredRun, list[MeasuredRun]], Solution],
    objective_rtol: float, objective_atol: float, kkt_tolerance: float,
    progress: Callable[[], None] | None,
) -> SolverFields:
    """The "lm" screen of every start, each solver's own solve from one common start, and
    each solver's run from the screen's best point where its own answer is worse.

    The common start is the user's start, or the first start that is not already at
    round-off zero when the user's is: from there each solver does its own iterations
    and those answers are cross-checked, their objectives within the larger of
    ``objective_atol`` and the resolution of the solvers' stopping test (``solver_tol``
    times the objective at that start). The screen's best point, when it is lower than
    a solver's own answer, is given to that solver as a start (its run is a
    confirmation when it takes no iteration). A solver's answer, cross-checked, is the
    better of its runs that iterated. The reported optimum is the lowest of all;
    of equal ones (within the cross-check's objective tolerance) a solver's own answer
    first, then a run from the screen's point, then the screen's.
    """
    screened = _screen(nlp, points, parameters, limits, solver_tol, max_iterations)
    screening = [_with_role(to_solution(run, screened), ROLE_SCREEN) for run in screened]
    chosen = min(screened, key=lambda run: (not run.outcome.success, run.fun))
    common, start_value = _common_start(nlp, points, parameters)
    own = {name: [rebuilt(run, start_index=common) for run in runs]
           for name, runs in run_starts(nlp, points[common][np.newaxis, :], parameters, limits,
                                        solver_names, solver_tol, max_iterations,
                                        progress).items()}
    from_screen: dict[str, list[MeasuredRun]] = {}
    for name, (run,) in own.items():
        if _lower(chosen, run, objective_rtol, objective_atol):
            runs = run_starts(nlp, chosen.outcome.x[np.newaxis, :], parameters, limits, (name,),
                              solver_tol, max_iterations, check_start=False)[name]
            from_screen[name] = [rebuilt(runs[0], start_index=chosen.start_index)]
    own_solutions = {name: _with_role(to_solution(runs[0], runs + from_screen.get(name, [])),
                                      ROLE_SOLVE)
                     for name, runs in own.items()}
    confirmations = {name: _with_role(to_solution(runs[0], own[name] + runs),
                                      ROLE_CONFIRMATION if runs[0].outcome.nit == 0
                                      else ROLE_FROM_SCREEN)
                     for name, runs in from_screen.items()}
    # Each solver's answer is the better of its runs that iterated: its solve from the
    # common start, and its run from the screen's point when that moved (a run of no
    # iteration confirms a point; it is never a solver's answer).
    solutions, answered_from = {}, {}
    for name, solution in own_solutions.items():
        solutions[name], answered_from[name] = solution, own[name][0]
        other = confirmations.get(name)
        if (other is not None and other.role == ROLE_FROM_SCREEN
                and best_solution([solution, other]) is other):
            solutions[name], answered_from[name] = other, from_screen[name][0]
    all_runs = screening + list(own_solutions.values()) + list(confirmations.values())
    return SolverFields(
        best=_first_as_good(
            [list(own_solutions.values()), list(confirmations.values()), screening],
            objective_rtol, objective_atol),
        solutions=solutions,
        runs=tuple(all_runs),
        # Each solver's own answer is known to its stopping test: SLSQP stops when RE
        # changes by less than solver_tol times its value at the start.
        crosscheck=(_cross_check(nlp, parameters, limits, answered_from, solutions,
                                 objective_rtol, max(objective_atol, solver_tol * start_value),
                                 kkt_tolerance)
                    if len(solutions) > 1 else None),
        local_minima=distinct_minima(all_runs, objective_rtol, objective_atol),
        confirmations=confirmations,
    )


def _first_as_good(groups: Sequence[Sequence[Solution]], rtol: float,
                   atol: float) -> Solution:
    """The best of the first group whose best is as good as the best of all (within the
    cross-check's tolerance): a named solver's own answer before a run from the screen's
    point, and that before the screen's, when they tie."""
    lowest = best_solution([solution for group in groups for solution in group])
    for group in groups:
        if group:
            candidate = best_solution(group)
            if (candidate.success == lowest.success
                    and candidate.fun - lowest.fun <= atol + rtol * abs(lowest.fun)):
                return candidate
    return lowest


def _common_start(nlp: Any, points: np.ndarray, parameters: np.ndarray) -> tuple[int, float]:
    """Index and objective of the user's start, or of the first start above round-off zero
    when the user's is not."""
    for index, point in enumerate(points):
        value, _ = nlp.objective_and_gradient(point.tolist(), parameters)
        if float(value) > ZERO_OBJECTIVE:
            return index, float(value)
    return 0, 0.0


def _lower(candidate: MeasuredRun, run: MeasuredRun, rtol: float, atol: float) -> bool:
    """True when ``candidate`` succeeded with an objective below ``run``'s beyond tolerance."""
    if not candidate.outcome.success:
        return False
    if not run.outcome.success or not math.isfinite(run.fun):
        return True
    return run.fun - candidate.fun > atol + rtol * abs(run.fun)


def _with_role(solution: Solution, role: str) -> Solution:
    return solution if solution.role == role else rebuilt(solution, role=role)


def _cross_check(nlp: Any, parameters: np.ndarray, limits: RunLimits,
                 runs: Mapping[str, MeasuredRun], solutions: Mapping[str, Solution],
                 objective_rtol: float, objective_atol: float,
                 kkt_tolerance: float) -> CrossCheck:
    """The verdict on the solvers' answers, with their designs compared where each answer
    is an isolated minimum and the answers started from the same point."""
    same_start = len({run.start_index for run in runs.values()}) == 1
    isolated = same_start and all(isolated_minimum(nlp, run.outcome.x, parameters, limits)
                                  for run in runs.values())
    design_gap = None
    if isolated:
        designs = [run.outcome.x for run in runs.values()]
        design_gap = max(float(np.max(np.abs(first - second)))
                         for first in designs for second in designs)
    return crosscheck(solutions, objective_rtol, objective_atol, kkt_tolerance,
                      design_gap=design_gap)


def _screen(nlp: Any, points: np.ndarray, parameters: np.ndarray, limits: RunLimits,
            solver_tol: float, max_iterations: int) -> list[MeasuredRun]:
    """``"lm"`` from each start in turn, until one reaches a global minimum (round-off zero).

    When the first start does not reach zero and at least
    :data:`sso._limits.BATCH_SCREEN_STARTS` starts remain, the rest are solved in one
    batch instead (no zero to stop at is then likely, and the batch is the faster
    way through many starts). Without second-order checks: a run that stops on a
    saddle point is only a worse candidate, and the best candidate is checked when
    the solvers run from it.
    """
    screened: list[MeasuredRun] = []
    for index, point in enumerate(points):
        if (index == 1 and nlp.residuals is not None
                and len(points) - 1 >= BATCH_SCREEN_STARTS):
            batch = _screen_batch(nlp, points[1:], parameters, limits, solver_tol,
                                  max_iterations)
            return screened + [rebuilt(run, start_index=run.start_index + 1) for run in batch]
        run = run_starts(nlp, point[np.newaxis, :], parameters, limits, ("lm",), solver_tol,
                         max_iterations, second_order=False)["lm"][0]
        screened.append(rebuilt(run, start_index=index))
        if nlp.nonnegative_objective and run.outcome.success and run.fun <= ZERO_OBJECTIVE:
            break
    return screened


def _screen_batch(nlp: Any, points: np.ndarray, parameters: np.ndarray, limits: RunLimits,
                  solver_tol: float, max_iterations: int) -> list[MeasuredRun]:
    """Every start by the shape's ``"lm"`` functions mapped over the starts (each ends as
    it ends alone), each answer measured as any other.

    The batch runs together, so it does not stop at the first global minimum; each
    run's ``time_s`` is its share of the batch's wall time. Saddle points are left
    to the checks of the runs from the best start, as in the screening one by one.
    """
    started = time.perf_counter()
    kernels = kernels_of(nlp)
    assert kernels is not None, "screened in a batch for a residual expression only"
    fixed, lower, upper = parameters.tolist(), limits.lower.tolist(), limits.upper.tolist()
    problem = problem_vector(fixed, lower, upper, solver_tol, max_iterations)
    states = solve_states(kernels, points, np.tile(problem, (len(points), 1)))
    ends = [lm.end_of(nlp, fixed, state, lower, upper, solver_tol, max_iterations)
            for state in states]
    share = (time.perf_counter() - started) / len(points)
    return [measure_run("lm", index, RunOutcome(np.array(end.x), end.fun, end.nit, end.nfev,
                                                end.nfev, end.status, end.status > 0,
                                                lm.MESSAGES[end.status], share),
                        nlp, parameters, limits)
            for index, end in enumerate(ends)]


def run_starts(nlp: Any, points: np.ndarray, parameters: np.ndarray, limits: RunLimits,
               solver_names: Sequence[str], solver_tol: float, max_iterations: int,
               progress: Callable[[], None] | None = None, second_order: bool = True,
               check_start: bool = True) -> dict[str, list[MeasuredRun]]:
    """Every solver from every start, in order; failures are kept, never raised.

    With ``second_order``, each run skips the solver at a start that is already a
    minimum (unless the solver's own first step is that test, as ``"lm"``'s is) and
    restarts it off saddle points (:mod:`sso._solvers.saddle`).

    Parameters
    ----------
    nlp : sso._solvers.nlp.CompiledNLP
        The problem graph.
    points : numpy.ndarray
        Starts, shape ``(starts, len(x))``.
    parameters : numpy.ndarray
        Fixed parameters of the graph.
    limits : RunLimits
        Bounds of ``x`` and of the constraints.
    solver_names : sequence of {"ipopt", "slsqp", "lm"}
    solver_tol : float
        Solver tolerance.
    max_iterations : int
        Iteration limit of each run.
    progress : callable, optional
        Called with no arguments after each run (a progress bar's step).
    second_order : bool
        Check for minima and saddle points around each run (False: the solver
        alone, as the least-squares screening does; the runs from its best point
        are checked).
    check_start : bool
        With ``second_order``, look at the start first (False: the solver runs even
        from a start that is already a minimum, as when it confirms another
        method's answer itself).

    Returns
    -------
    dict of str to list of MeasuredRun
    """
    runs: dict[str, list[MeasuredRun]] = {}
    for name in solver_names:
        backend = _backend(name)
        runs[name] = []
        for index, point in enumerate(points):
            runs[name].append(_run_one(nlp, point, index, parameters, limits, backend, name,
                                       solver_tol, max_iterations, second_order, check_start))
            if progress is not None:
                progress()
    return runs


def _run_one(nlp: Any, point: np.ndarray, index: int, parameters: np.ndarray,
             limits: RunLimits, backend: Backend, name: str, solver_tol: float,
             max_iterations: int, second_order: bool, check_start: bool) -> MeasuredRun:
    """One run of :func:`run_starts`, measured."""
    def solve(start: np.ndarray) -> RunOutcome:
        return backend.solve(nlp, start, parameters, limits, solver_tol, max_iterations)

    outcome = (solve_with_second_order_care(solve, nlp, point, parameters, limits, solver_tol,
                                            check_start=(check_start and not
                                                         backend.TESTS_ITS_START))
               if second_order else solve(point))
    return measure_run(name, index, outcome, nlp, parameters, limits)


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


def solution_from_run(run: MeasuredRun, solver_runs: Sequence[MeasuredRun],
                      x: Sequence[float] | None = None, series: SeriesDesign | None = None,
                      role: str = ROLE_SOLVE) -> Solution:
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
    role : str
        What the run was (:attr:`sso.Solution.role`).
    """
    outcome = run.outcome
    return built(
        Solution,
        solver=run.solver,
        series=series,
        x=(tuple(x) if type(x) is list
           else tuple(np.asarray(outcome.x if x is None else x, dtype=float).tolist())),
        fun=run.fun,
        nit=outcome.nit,
        nfev=outcome.nfev,
        status=outcome.status,
        success=outcome.success,
        message=outcome.message,
        kkt=run.kkt,
        time_s=outcome.time_s,
        start_index=run.start_index,
        total_nfev=sum([other.outcome.nfev for other in solver_runs]),
        constraint_violation=run.violation,
        role=role,
    )


def _backend(name: str) -> Backend:
    """The solver module of ``name``. IPOPT's and SLSQP's are imported on first use: they
    load CasADi's IPOPT and SciPy, which a run of ``"lm"`` alone never needs (SciPy's
    import is about a third of a fresh process that solves with SLSQP)."""
    if name == "ipopt":
        from sso._solvers import ipopt
        return ipopt
    if name == "slsqp":
        from sso._solvers import slsqp
        return slsqp
    return lm


def measure_run(name: str, start_index: int, outcome: RunOutcome, nlp: Any,
                parameters: np.ndarray, limits: RunLimits) -> MeasuredRun:
    """``outcome`` re-measured on the problem's graph: objective, stationarity, violation."""
    lower, upper = limits.lower.tolist(), limits.upper.tolist()
    given = outcome.x.tolist() if type(outcome.x) is np.ndarray else np.asarray(
        outcome.x, dtype=float).tolist()
    if limits.constrained:
        point = _onto_bounds(given, lower, upper)
        x = np.array(point, dtype=float)
        value, gradient = nlp.objective_and_gradient(point, parameters)
        constraint_values, constraint_jacobian = nlp.constraints_and_jacobian(x, parameters)
        constraint_values = np.array(constraint_values, dtype=float).ravel()
        kkt = kkt_residual(x, gradient, limits, constraint_values,
                           np.array(constraint_jacobian, dtype=float))
        violation = constraint_violation(x, limits, constraint_values)
    else:
        point, value, kkt = measure_on_bounds(nlp, given, parameters, lower, upper)
        x = np.array(point, dtype=float)
        violation = 0.0  # x was just put onto the bounds: it violates nothing
    return built(MeasuredRun, solver=name, start_index=start_index,
                 outcome=rebuilt(outcome, x=x), fun=float(value), kkt=kkt,
                 violation=violation)


def measure_on_bounds(nlp: Any, given: list[float], parameters: Any, lower: list[float],
                      upper: list[float]) -> tuple[list[float], float, float]:
    """The measure of a point of a bound-only problem: the point put onto the bounds, the
    objective and the projected gradient's norm there (plain floats)."""
    point = _onto_bounds(given, lower, upper)
    value, slopes = value_and_gradient_floats(nlp, point, parameters)
    return point, value, projected_gradient_norm_floats(point, slopes, lower, upper)


def _onto_bounds(given: list[float], lower: list[float], upper: list[float]) -> list[float]:
    """NaN to 0, then onto the bounds (IPOPT relaxes them slightly); plain floats, as the
    vectors are short."""
    return [low if value < low else high if value > high else value if value == value else
            (0.0 if low <= 0.0 <= high else low if 0.0 < low else high)
            for value, low, high in zip(given, lower, upper, strict=True)]
