"""``sso.optimise``: the one entry point for optimising a shaft series."""

from __future__ import annotations

import functools
import math
import time
import warnings
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from sso._display import Part, TextTable, format_number, format_numbers
from sso._limits import (
    CROSS_CHECK_SOLVERS,
    DEFAULT_BETA_BOUNDS_DEG,
    DEFAULT_INPUT_SPEED_RPM,
    DEFAULT_KKT_TOLERANCE,
    DEFAULT_MAX_ITERATIONS,
    DEFAULT_OBJECTIVE_ATOL,
    DEFAULT_OBJECTIVE_RTOL,
    DEFAULT_OPTION,
    DEFAULT_PHASE_BOUNDS_DEG,
    DEFAULT_QUADRATURE_ATOL,
    DEFAULT_QUADRATURE_RTOL,
    DEFAULT_SEED,
    DEFAULT_SHAFT_SOLVER_TOL,
    DEFAULT_STARTS,
    MAX_ITERATIONS,
    MAX_STARTS,
    SOLVERS,
)
from sso._progress import ProgressBar, interactive
from sso._record import built_from
from sso._resources import check_multistart_memory
from sso._shafts.curves import ComparedDesign, compared_design
from sso._shafts.evaluation import Evaluation, validate_quadrature_tolerance
from sso._shafts.exact_optima import (
    ExactOptimumSet,
    SpreadMeasure,
    choose_exact_optimum,
    is_exact,
    selection_run,
    series_set_problem,
    tolerance_settings,
)
from sso._shafts.options import (
    OPTION_FIXED_PHASE_DEG,
    DesignProblem,
    build_problem,
    warn_moved_starts,
)
from sso._shafts.problem import compiled_nlp
from sso._shafts.quadrature import QuadratureRule, rule_for_bounds
from sso._shafts.series import ShaftSeries, checked_series
from sso._solvers import lm
from sso._solvers.multistart import (
    MeasuredRun,
    SolverFields,
    measure_on_bounds,
    solution_from_run,
    solve_from_starts,
)
from sso._solvers.result import DesignResult
from sso._solvers.run import RunLimits
from sso._solvers.saddle import ZERO_OBJECTIVE, saddle_direction
from sso._solvers.solution import ROLE_SELECTION, ROLE_SOLVE, Solution
from sso._validation import (
    validate_count,
    validate_solver_tol,
    validate_solvers,
    validate_speed,
)
from sso._warning_origin import user_stacklevel

PROGRESS_MIN_RUNS = 100
"""Runs (starts times solvers) from which an interactive terminal shows a progress bar."""

# The exact model's RE is a closed form: no quadrature angles, no quadrature error.
CLOSED_FORM_RULE = QuadratureRule(samples=0, error_estimate=0.0, converged=True)



UNRELIABLE_VERDICT = "optimum unreliable"
"""How the verdict of a run whose optimum's quadrature did not converge begins."""


@dataclass(frozen=True, kw_only=True, eq=False, repr=False)
class OptimisationResult(DesignResult):
    """Everything one optimisation found; reports are rendered from it alone.

    Attributes
    ----------
    option : int
        1 (phases), 2 (operating angles, phases at 90 deg) or 3 (both).
    option_name : str
        ``"phase"``, ``"angle"`` or ``"both"``.
    model : str
        ``"exact"`` or ``"paper"``.
    input_speed_rpm : float
    beta_bounds_deg, phase_bounds_deg : tuple of (float, float)
        Bounds per joint / per phase, deg.
    initial_series : sso.ShaftSeries
        The design as given, with the option's fixed values applied (option 2
        phases at 90 deg); not moved onto the bounds.
    start_series : sso.ShaftSeries
        The user's start after moving it onto the bounds.
    initial, optimum : sso.Evaluation
        Evaluations of ``initial_series`` and of the best design, at
        ``input_speed_rpm``; computed on first access (a caller that reads only
        RE and the design does not pay for them).
    compared : tuple of sso._shafts.curves.ComparedDesign
        The initial design and the optimum with their speed curves, as the report
        draws them; computed on first access.
    best, solutions, runs, crosscheck, local_minima
        As in :class:`sso._solvers.result.DesignResult`; ``fun`` is the residual
        error RE and ``x`` is in deg. With ``screen_starts`` (exact model, more
        than one start), ``runs`` holds the screening runs of ``"lm"`` from each
        start, then each solver's own solve from the common start, then its run
        from the screen's best point where it had one (``confirmations``); last,
        the choice within the exact optima when it moved the design (``best``,
        role ``"selection"``). ``found_by`` says who found ``best``.
    samples : int
        Quadrature angles of the NLP (chosen for the bounds); 0 for the exact
        model, whose RE is evaluated in closed form (no quadrature).
    quadrature_error : float
        Estimated RE error of that rule at the worst design in the bounds; 0 for
        the exact model (closed form, exact to round-off).
    starts : int
        Starts per solver.
    warnings : tuple of str
        Warnings raised while setting up: starts moved onto their bounds, and the
        paper model's quadrature notes.
    quadrature_rtol, quadrature_atol : float
        Quadrature tolerance of the evaluations (paper model).
    exact_optima : sso._shafts.exact_optima.ExactOptimumSet or None
        Where the least RE is round-off zero (exact model): the criterion the
        reported design was chosen by within the set of exact optima, its figures
        and the set's extent per variable; None otherwise.
    """

    option: int
    option_name: str
    model: str
    input_speed_rpm: float
    beta_bounds_deg: tuple[tuple[float, float], ...]
    phase_bounds_deg: tuple[tuple[float, float], ...]
    initial_series: ShaftSeries
    start_series: ShaftSeries
    samples: int
    quadrature_error: float
    starts: int
    warnings: tuple[str, ...]
    quadrature_rtol: float = DEFAULT_QUADRATURE_RTOL
    quadrature_atol: float = DEFAULT_QUADRATURE_ATOL
    exact_optima: ExactOptimumSet | None = None

    @functools.cached_property
    def initial(self) -> Evaluation:
        """Figures of ``initial_series`` at ``input_speed_rpm``."""
        return self.initial_series.evaluate(self.input_speed_rpm, **self._evaluation_options)

    @functools.cached_property
    def optimum(self) -> Evaluation:
        """Figures of the best design at ``input_speed_rpm``."""
        return self.best_series.evaluate(self.input_speed_rpm, **self._evaluation_options)

    @functools.cached_property
    def compared(self) -> tuple[ComparedDesign, ...]:
        """The initial design and the optimum as a report shows them, with speed curves."""
        return (compared_design("initial", "initial design (as given)", self.initial_series,
                                self.initial),
                compared_design("optimum", "optimum", self.best_series, self.optimum))

    @property
    def best_series(self) -> ShaftSeries:
        """The best design, ``best.series`` (always a shaft series here)."""
        series = self.best.series
        assert isinstance(series, ShaftSeries)
        return series

    @property
    def _evaluation_options(self) -> dict[str, float]:
        return {"quadrature_rtol": self.quadrature_rtol, "quadrature_atol": self.quadrature_atol}

    report_kind: ClassVar[str] = "optimisation"
    _record_derived: ClassVar[tuple[str, ...]] = ("initial", "optimum", "compared")

    @property
    def verdict(self) -> str:
        """What the solvers found, in words; an optimum whose quadrature did not
        converge is called unreliable (:data:`UNRELIABLE_VERDICT`)."""
        if self.best.success and not self.optimum.quadrature_converged:
            return (f"{UNRELIABLE_VERDICT}: operating angles this close to 90 deg put peaks in "
                    "the speed ratio that the residual-error quadrature cannot resolve")
        return super().verdict

    def _repr_text(self) -> str:
        verdict = "success" if self.success else "FAILED"
        return (f"option {self.option} ({self.option_name}), {self.model} model, "
                f"{verdict}: RE {format_number(self.initial.residual_error, 4)} -> "
                f"{format_number(self.fun, 4)} by {self.found_by}; "
                f"beta_deg [{format_numbers(self.best_series.beta_deg, 6)}], "
                f"phase_deg [{format_numbers(self.best_series.phase_deg, 6)}]")

    def _summary_parts(self) -> list[Part]:
        verdict = "success" if self.success else "FAILED"
        designs = TextTable(("design", "beta (deg)", "phase (deg)", "RE"), (
            ("initial", format_numbers(self.initial_series.beta_deg),
             format_numbers(self.initial_series.phase_deg),
             format_number(self.initial.residual_error)),
            ("optimum", format_numbers(self.best_series.beta_deg),
             format_numbers(self.best_series.phase_deg), format_number(self.fun))))
        title = (f"Optimisation, option {self.option} ({self.option_name}), {self.model} "
                 f"model, {format_number(self.input_speed_rpm)} rpm: {verdict}")
        exact = [] if self.exact_optima is None else self.exact_optima._summary_parts()
        return [title, designs, *exact, *self._solver_parts("RE", "KKT (1/rad)")]

    @property
    def success(self) -> bool:
        """True when the best answer converged, the solvers agree, and the optimum's
        residual error is reliable (its quadrature converged)."""
        return (self.best.success and (self.crosscheck is None or self.crosscheck.agree)
                and self.optimum.quadrature_converged)


def optimise(
    series: ShaftSeries,
    option: int | str = DEFAULT_OPTION,
    *,
    beta_bounds_deg: Any = DEFAULT_BETA_BOUNDS_DEG,
    phase_bounds_deg: Any = DEFAULT_PHASE_BOUNDS_DEG,
    solvers: Iterable[str] | str = CROSS_CHECK_SOLVERS,
    starts: int = DEFAULT_STARTS,
    input_speed_rpm: float = DEFAULT_INPUT_SPEED_RPM,
    solver_tol: float = DEFAULT_SHAFT_SOLVER_TOL,
    max_iterations: int = DEFAULT_MAX_ITERATIONS,
    seed: int = DEFAULT_SEED,
    quadrature_rtol: float = DEFAULT_QUADRATURE_RTOL,
    quadrature_atol: float = DEFAULT_QUADRATURE_ATOL,
    objective_rtol: float = DEFAULT_OBJECTIVE_RTOL,
    objective_atol: float = DEFAULT_OBJECTIVE_ATOL,
    kkt_tolerance: float = DEFAULT_KKT_TOLERANCE,
    memory_limit_mb: float | None = None,
    screen_starts: bool = True,
    beta_tolerance_deg: float | Sequence[float] | None = None,
    phase_tolerance_deg: float | Sequence[float] | None = None,
    distribution: str | None = None,
    samples: int | None = None,
    exact_set_tolerances: SpreadMeasure | None = None,
) -> OptimisationResult:
    """Choose operating angles and/or phases that make the output turn evenly.

    Minimises the residual error ``RE`` (mean square of ``w_out/w_in - 1`` over a
    revolution) under bounds, with IPOPT (exact Hessian) and SLSQP (exact
    gradient) on the same CasADi graph, from several starts, and cross-checks
    the solvers. The exact model's RE is the closed form of the chain matrix
    (:mod:`sso._kinematics.hooke_matrix`); the paper model's, a quadrature.

    Parameters
    ----------
    series : sso.ShaftSeries
        The start design and chain model. Option 1 keeps its operating angles;
        option 2 fixes every phase at 90 deg.
    option : {1, 2, 3, "phase", "angle", "both"}
        Which angles are design variables.
    beta_bounds_deg : (float, float) or sequence of pairs
        Bounds on the operating angles, deg, inside ``[0, 90)``; one pair for all
        joints or one per joint. An equal pair pins that joint.
    phase_bounds_deg : (float, float) or sequence of pairs
        Bounds on the relative phases, deg, inside ``[-360, 360]``.
    solvers : sequence of names in ``sso.SOLVERS``
        Solvers to run (``"ipopt"``, ``"slsqp"``; ``"lm"``, the least-squares
        solver, for the exact model only); with two or more, their answers are
        cross-checked with the same first-order measure for each.
    starts : int
        Starts per solver, ``1..10000``: the user's start plus space-filling points.
    input_speed_rpm : float
        Input speed, rpm (> 0); it scales the reported figures, not the optimum.
    solver_tol : float
        The solvers' stopping tolerance in ``(0, 1)``: IPOPT's ``tol``; SLSQP's
        ``ftol`` relative to the starting objective.
    max_iterations : int
        Iteration limit of each run, >= 1.
    seed : int
        Seed of the space-filling starts and, with tolerances, of their Monte Carlo
        samples (as :func:`sso.tolerance_study`'s ``seed``).
    quadrature_rtol, quadrature_atol : float
        Tolerance of the adaptive quadrature (relative, absolute floor).
    objective_rtol, objective_atol, kkt_tolerance : float
        Tolerances of the cross-check.
    memory_limit_mb : float, optional
        Refuse the run if its memory estimate (graph and exact Hessian, kept runs)
        exceeds this, MB (default ``SSO_MEMORY_LIMIT_MB`` or
        :data:`sso._limits.DEFAULT_MEMORY_LIMIT_MB`).
    screen_starts : bool
        Exact model with more than one start or more than one solver (one solver
        from one start always runs alone): solve the starts first with the
        least-squares solver ``"lm"`` (cheap: the closed form in plain floats),
        then run each of ``solvers`` once, from the lowest RE found, and
        cross-check them there. Screening stops at the first start that reaches
        RE <= 1e-20 (round-off zero): RE is never negative, so that is a global
        minimum and the other starts cannot improve on it. The search over
        starts is then the least-squares solver's; the verdict (objective
        agreement, the same first-order measure for every solver) is the
        requested solvers'. False runs every solver from every start, as the
        paper model always does.

    Returns
    -------
    OptimisationResult
        Solver failures and disagreements are reported in it, not raised.

    Raises
    ------
    ValueError
        For bad input, naming the field, the value and the allowed range; or if
        the run's memory estimate exceeds the limit (the message gives both).
    TypeError
        If ``series`` is not a :class:`sso.ShaftSeries` or a keyword is unknown.
    """
    if not isinstance(series, ShaftSeries):
        raise TypeError(f"series must be an sso.ShaftSeries, not {type(series).__name__}")
    solver_names = validate_solvers(solvers, SOLVERS)
    tolerances: SpreadMeasure | None = tolerance_settings(
        series.n_joints, beta_tolerance_deg, phase_tolerance_deg, distribution, samples, seed)
    if exact_set_tolerances is not None:
        if tolerances is not None:
            raise TypeError("give the tolerance keywords (beta_tolerance_deg, ...) or "
                            "exact_set_tolerances, not both")
        if not isinstance(exact_set_tolerances, SpreadMeasure):
            raise TypeError("exact_set_tolerances must measure the p95 RE of a design "
                            "(p95_residual_error, expected_residual_error), not a "
                            f"{type(exact_set_tolerances).__name__}")
        tolerances = exact_set_tolerances
    if tolerances is not None and series.model != "exact":
        raise ValueError("beta_tolerance_deg, phase_tolerance_deg, distribution and samples "
                         "choose the most robust of a set of exact optima (RE = 0), which "
                         f"only the exact model has; series.model = {series.model!r}")
    if "lm" in solver_names and series.model != "exact":
        raise ValueError(f"solvers = {list(solver_names)} includes 'lm', which needs the exact "
                         f"model's closed form; series.model = {series.model!r} allows "
                         "'ipopt' and 'slsqp'")
    starts = validate_count("starts", starts, 1, MAX_STARTS)
    max_iterations = validate_count("max_iterations", max_iterations, 1, MAX_ITERATIONS)
    speed_rpm = validate_speed("input_speed_rpm", input_speed_rpm)
    solver_tol = validate_solver_tol(solver_tol)
    quadrature_rtol, quadrature_atol = validate_quadrature_tolerance(quadrature_rtol,
                                                                     quadrature_atol)

    problem = build_problem(series.beta_deg, series.phase_deg, series.model, option,
                            beta_bounds_deg, phase_bounds_deg)
    warn_moved_starts(problem)
    setup_warnings = problem.moved_starts
    if series.model == "paper":
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            rule = rule_for_bounds(problem.beta_upper_rad, series.model, quadrature_rtol,
                                   quadrature_atol)
        for warning in caught:  # raised again at the user's line, not the package's
            warnings.warn(warning.message, warning.category, stacklevel=user_stacklevel())
        setup_warnings += tuple(str(warning.message) for warning in caught)
    else:
        rule = CLOSED_FORM_RULE
    check_multistart_memory(problem.n_joints, problem.n_free, rule.samples, starts,
                            len(solver_names),
                            _screened(series, solver_names, starts, screen_starts),
                            memory_limit_mb)
    if solver_names == ("lm",) and starts == 1 and tolerances is None:
        alone = _solve_alone(problem, series, speed_rpm, solver_tol, max_iterations,
                             quadrature_rtol, quadrature_atol, setup_warnings)
        if alone is not None:
            return alone
    return _solve(problem, rule, series, solver_names, starts, speed_rpm, solver_tol,
                  max_iterations, seed, quadrature_rtol, quadrature_atol, objective_rtol,
                  objective_atol, kkt_tolerance, screen_starts, setup_warnings, tolerances)


def _screened(series: ShaftSeries, solver_names: tuple[str, ...], starts: int,
              screen_starts: bool) -> bool:
    """Whether the starts are screened with "lm" first (the exact model's residuals)."""
    return screen_starts and series.model == "exact" and (starts > 1 or len(solver_names) > 1)


def _solve(problem: DesignProblem, rule: Any, series: ShaftSeries, solver_names: tuple[str, ...],
           starts: int, speed_rpm: float, solver_tol: float, max_iterations: int, seed: int,
           quadrature_rtol: float, quadrature_atol: float, objective_rtol: float,
           objective_atol: float, kkt_tolerance: float, screen_starts: bool,
           setup_warnings: tuple[str, ...],
           tolerances: SpreadMeasure | None) -> OptimisationResult:
    screened = _screened(series, solver_names, starts, screen_starts)
    # Screened starts run "lm" only; the bar counts the requested solvers' runs.
    runs = len(solver_names) if screened else starts * len(solver_names)
    bar = (ProgressBar(runs, "runs", True)
           if runs >= PROGRESS_MIN_RUNS and interactive() else None)
    nlp = compiled_nlp(problem, rule.samples)
    try:
        solved = solve_from_starts(
            nlp, problem.start_rad,
            RunLimits(problem.lower_rad, problem.upper_rad), problem.parameters_rad,
            solver_names=solver_names, starts=starts, seed=seed, solver_tol=solver_tol,
            max_iterations=max_iterations,
            to_solution=lambda run, runs: _to_solution(run, problem, series.model, runs),
            objective_rtol=objective_rtol, objective_atol=objective_atol,
            kkt_tolerance=kkt_tolerance, screen_starts=screen_starts,
            progress=None if bar is None else lambda: bar.advance(1))
    finally:
        if bar is not None:
            bar.close()

    exact_optima = None
    # The choice is made where solvers are cross-checked, or tolerances ask for it; one
    # solver's runs report what it reached, as optimise_batch and batched sweeps do.
    if (series.model == "exact" and problem.n_free and is_exact(solved["best"].fun)
            and solved["best"].success
            and (tolerances is not None or len(solver_names) > 1)):
        chosen, exact_optima = _most_robust(problem, nlp, solved, series.model, tolerances)
        if chosen is not solved["best"]:
            solved["best"], solved["runs"] = chosen, (*solved["runs"], chosen)
    return _result(problem, rule, series, starts, speed_rpm, quadrature_rtol, quadrature_atol,
                   setup_warnings, exact_optima, solved)


def _solve_alone(problem: DesignProblem, series: ShaftSeries, speed_rpm: float,
                 solver_tol: float, max_iterations: int, quadrature_rtol: float,
                 quadrature_atol: float, setup_warnings: tuple[str, ...]
                 ) -> OptimisationResult | None:
    """``"lm"`` alone from the user's start: the record :func:`solve_from_starts` gives for one
    solver and one start (the run, its look for a saddle point, its measure), made on
    plain floats without the multi-start layers. None where the run stopped on a saddle
    point: the general path leaves it (and makes the record) then.
    """
    nlp = compiled_nlp(problem, 0)
    started = time.perf_counter()
    # math.radians rounds as numpy's radians does (the problem's start_rad, parameters_rad).
    fixed = list(map(math.radians, problem.parameter_values_deg))
    lower, upper = problem.lower_rad.tolist(), problem.upper_rad.tolist()
    end = lm.solve_floats(nlp, list(map(math.radians, problem.start_values_deg)), fixed,
                          lower, upper, solver_tol, max_iterations)
    if on_saddle(nlp, end, fixed, problem.lower_rad, problem.upper_rad):
        return None
    x_deg, fun, kkt = measured_end(nlp, end, fixed, lower, upper, problem.bounds_deg)
    time_s = time.perf_counter() - started
    beta_deg, phase_deg = problem.design_deg(x_deg)
    success = end.status > 0
    solution = built_from(Solution, {
        "solver": "lm", "series": checked_series(beta_deg, phase_deg, series.model),
        "x": x_deg, "fun": fun, "nit": end.nit, "nfev": end.nfev, "status": end.status,
        "success": success, "message": lm.MESSAGES[end.status], "kkt": kkt,
        "time_s": time_s, "start_index": 0, "total_nfev": end.nfev,
        "constraint_violation": 0.0, "role": ROLE_SOLVE})
    return _result(problem, CLOSED_FORM_RULE, series, 1, speed_rpm, quadrature_rtol,
                   quadrature_atol, setup_warnings, None, {
                       "best": solution, "solutions": {"lm": solution}, "runs": (solution,),
                       "crosscheck": None,
                       # distinct_minima of one run: its value where it succeeded
                       "local_minima": (fun,) if success else (), "confirmations": {}})


def measured_end(nlp: Any, end: lm.End, fixed: list[float], lower: list[float],
                 upper: list[float], bounds_deg: tuple[tuple[float, ...], tuple[float, ...]]
                 ) -> tuple[tuple[float, ...], float, float]:
    """The design (deg), RE and projected gradient's norm of where ``"lm"`` ended, measured
    as the general path measures every run (:func:`sso._solvers.multistart.measure_on_bounds`):
    the one measure of the single solve and of :func:`sso.optimise_batch`."""
    point, fun, kkt = measure_on_bounds(nlp, end.x, fixed, lower, upper)
    # As _to_solution: a value on a bound is that bound exactly (math.degrees rounds as
    # numpy's degrees does).
    x_deg = tuple(high if value > high else low if value < low else value
                  for value, low, high in zip(map(math.degrees, point), *bounds_deg,
                                              strict=True))
    return x_deg, fun, kkt


def on_saddle(nlp: Any, end: lm.End, fixed: list[float], lower_rad: np.ndarray,
              upper_rad: np.ndarray) -> bool:
    """Whether a run of ``"lm"`` that succeeded stopped on a saddle point (above round-off
    zero), which the general path then leaves: the one test of the single solve and of
    :func:`sso.optimise_batch`."""
    return (end.status > 0 and end.fun > ZERO_OBJECTIVE
            and saddle_direction(nlp, True, end.fun, end.x, fixed,
                                 lambda: RunLimits(lower_rad, upper_rad)) is not None)


def _result(problem: DesignProblem, rule: Any, series: ShaftSeries, starts: int,
            speed_rpm: float, quadrature_rtol: float, quadrature_atol: float,
            setup_warnings: tuple[str, ...], exact_optima: ExactOptimumSet | None,
            solved: SolverFields) -> OptimisationResult:
    """The result of a run: the problem's layout, the designs as given and as started, and
    the solvers' fields."""
    initial_series, start_series = _given_series(problem, series)
    return built_from(OptimisationResult, {
        "option": problem.option, "option_name": problem.option_name, "model": series.model,
        "input_speed_rpm": speed_rpm, "beta_bounds_deg": problem.beta_bounds_deg,
        "phase_bounds_deg": problem.phase_bounds_deg, "initial_series": initial_series,
        "start_series": start_series, "samples": rule.samples,
        "quadrature_error": rule.error_estimate, "starts": starts,
        "warnings": setup_warnings, "quadrature_rtol": quadrature_rtol,
        "quadrature_atol": quadrature_atol, "exact_optima": exact_optima, **solved})


def _given_series(problem: DesignProblem, series: ShaftSeries
                  ) -> tuple[ShaftSeries, ShaftSeries]:
    """The design as given (option 2's phases at 90 deg) and as started (moved onto the
    bounds)."""
    initial_series = (checked_series(series.beta_deg,
                                     (OPTION_FIXED_PHASE_DEG,) * len(series.phase_deg),
                                     series.model)
                      if problem.option == 2 else series)
    # A start that was not moved onto the bounds is the initial design.
    start_series = (initial_series if not problem.moved_starts
                    else checked_series(*problem.design_deg(problem.start_values_deg),
                                        series.model))
    return initial_series, start_series


def _most_robust(problem: DesignProblem, nlp: Any, solved: SolverFields, model: str,
                 tolerances: SpreadMeasure | None) -> tuple[Solution, ExactOptimumSet]:
    """The chosen design of the set of exact optima, as the reported best."""
    fixed = problem.parameters_rad.tolist()
    found = [solved["best"], *(run for run in solved["runs"]
                                if run.success and is_exact(run.fun))]
    started = time.perf_counter()

    def solve_in_box(start: list[float], lower: list[float], upper: list[float],
                     max_iterations: int) -> tuple[list[float], float, int, int]:
        # Gauss-Newton steps only: a margin is feasible where they reach round-off zero.
        return lm.gauss_newton_end(nlp, start, fixed, lower, upper, DEFAULT_SHAFT_SOLVER_TOL,
                                   max_iterations)

    choice = choose_exact_optimum(series_set_problem(problem),
                                  lambda x: nlp.residuals_and_jacobian(x, fixed), solve_in_box,
                                  [np.radians(solution.x) for solution in found], tolerances)
    if choice.solver is None:
        return solved["best"], choice.exact_set
    run = selection_run(choice, solved["best"].start_index, nlp, problem.parameters_rad,
                        RunLimits(problem.lower_rad, problem.upper_rad), started)
    chosen = _to_solution(run, problem, model, [run], ROLE_SELECTION)
    return chosen, choice.exact_set


def _to_solution(run: MeasuredRun, problem: DesignProblem, model: str,
                 solver_runs: list[MeasuredRun], role: str = ROLE_SOLVE) -> Solution:
    # Back in degrees, a value on a bound is that bound exactly (not a round-trip ulp off).
    x_deg = np.clip(np.degrees(run.outcome.x), *problem.bounds_deg)
    beta_deg, phase_deg = problem.design_deg(x_deg)
    return solution_from_run(run, solver_runs, x_deg.tolist(),
                             checked_series(beta_deg, phase_deg, model), role)
