"""Yoke phasing with tolerances in the objective: the design production builds well.

The nominal optimum can sit in a narrow valley. Where the column can cancel (the
least RE is round-off zero on a set of phasings), the phasing is chosen within that
set as :func:`sso.optimise` chooses for a shaft series with tolerances: the exact
optimum of lowest p95 RE over a fixed, seeded sample of built columns
(:class:`sso._column.tolerances.Tolerances`), so no nominal RE is given up. Where it
cannot, the objective is RE over that sample: its mean, or for a percentile ``q``
the conditional value at risk (CVaR, the mean of the worst ``100 - q`` % of the
sample) in Rockafellar and Uryasev's epigraph form, the least convex upper bound of
the percentile; both smooth, with exact derivatives (:mod:`sso._column.scenarios`).
The result reports the empirical percentiles of the robust design and of the nominal
optimum on the same sample.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from sso._column.geometry import ColumnGeometry
from sso._column.phasing import PhasingResult, optimise_phasing
from sso._column.scenarios import (
    PhasingOutcome,
    ScenarioRun,
    cvar,
    outcome_fields,
    scenario_re,
    solve_scenarios,
)
from sso._column.tolerances import SampleStudy, Tolerances
from sso._limits import (
    CROSS_CHECK_SOLVERS,
    DEFAULT_COLUMN_SEED,
    DEFAULT_COLUMN_SOLVER_TOL,
    DEFAULT_COLUMN_STARTS,
    DEFAULT_MAX_ITERATIONS,
    MAX_ITERATIONS,
    MAX_STARTS,
)
from sso._shafts.exact_optima import is_exact
from sso._solvers.solution import Solution
from sso._validation import validate_count, validate_solver_tol, validate_solvers

PERCENTILE_PATTERN = re.compile(r"p(\d+(?:\.\d+)?)")
LOWEST_PERCENTILE = 50.0
ROWS_PER_BLOCK = 512
"""Assemblies evaluated over the whole sample at once when searching teeth (memory)."""


@dataclass(frozen=True, eq=False, repr=False)
class RobustResult(PhasingOutcome):
    """Outcome of :func:`optimise_robust`.

    Attributes
    ----------
    x, fun, nit, nfev, status, success, message, best, solutions, runs, crosscheck
        As :class:`sso._column.scenarios.PhasingOutcome`: ``x`` the robust yoke
        phasing (deg), ``fun`` the objective at ``x`` over the sample (mean RE or
        CVaR). Where the phasing was chosen within a set of exact optima
        (``exact_choice``), the solver fields are that phasing run's (``x`` in yoke
        phasing, deg; ``fun`` the nominal RE).
    robust_objective : str
        ``"mean"`` or ``"pNN"``.
    level : float
        ``NN / 100`` of a percentile objective; 0 for ``"mean"``.
    nominal_re : float
        RE of the robust phasing on the nominal column.
    nominal_optimum_re : float
        RE of the nominal optimum (:func:`sso.optimise`) there.
    nominal_re_given_up : float
        ``nominal_re - nominal_optimum_re``, or 0 where the robust phasing is no worse
        (both at round-off zero: an exact optimum chosen within the set).
    robust_study, nominal_study : SampleStudy
        p50 / p95 / max / mean / CVaR of RE over the sample, of the robust phasing
        and of the nominal optimum (the same built columns).
    validation_robust_study, validation_nominal_study : SampleStudy
        The same figures on a fresh sample (seed + 1, same size): the robust
        phasing's advantage out of sample.
    tolerances : Tolerances
    geometry : ColumnGeometry
    nominal : PhasingResult
        The nominal optimum (:func:`sso.optimise` of the geometry, no tolerances).
    exact_choice : PhasingResult or None
        Where the least RE is round-off zero: the phasing run that chose ``x`` within
        the set of exact optima by the lowest p95 RE over the sample (its
        ``optimisation.exact_optima`` holds the figures of the choice); None where
        the column cannot cancel and ``x`` minimises the objective over all phasings.
    """

    robust_objective: str
    level: float
    nominal_re: float
    nominal_optimum_re: float
    nominal_re_given_up: float
    robust_study: SampleStudy
    nominal_study: SampleStudy
    validation_robust_study: SampleStudy
    validation_nominal_study: SampleStudy
    tolerances: Tolerances
    geometry: ColumnGeometry
    nominal: PhasingResult
    exact_choice: PhasingResult | None = None

    @property
    def exact_optimum_criterion(self) -> str | None:
        """How ``x`` was chosen within the set of exact optima, or None (no such set)."""
        return None if self.exact_choice is None else self.exact_choice.exact_optimum_criterion

    @property
    def exact_optimum_extent_deg(self) -> tuple[tuple[float, float], ...] | None:
        """Per intermediate shaft, the arc of yoke phasings about ``x`` on which the set of
        exact optima was found, deg (as :attr:`PhasingResult.exact_optimum_extent_deg`),
        or None (no such set)."""
        return None if self.exact_choice is None else self.exact_choice.exact_optimum_extent_deg

    @property
    def design_label(self) -> str:
        """The robust phasing in words, as a report names it."""
        if self.exact_choice is None:
            return f"tolerance-aware (least {self.objective_short})"
        return "tolerance-aware (the exact optimum of lowest p95 RE)"

    @property
    def objective_short(self) -> str:
        """What ``fun`` measures, short: ``"mean RE"`` or ``"CVaR95 of RE"`` (never
        ``"p95"``, which names a 95th percentile wherever sso prints it)."""
        return objective_short_name(self.robust_objective, self.level)

    @property
    def objective_name(self) -> str:
        """What ``fun`` measures, in words."""
        if self.robust_objective == "mean":
            return "mean RE over the built columns"
        return (f"{self.objective_short} over the built columns (the mean of the worst "
                f"{100.0 * (1.0 - self.level):.3g} %)")

    def phasing_objective(self) -> Callable[[np.ndarray], np.ndarray]:
        """The robust objective over the same seeded built columns, as a function of
        yoke phasings (``(m, shafts)`` deg -> ``(m,)``)."""
        sample = self.tolerances.sample(self.geometry)
        count = len(sample.beta_rad)
        weights = np.full(count, 1.0 / count)

        def objective(yokes: np.ndarray) -> np.ndarray:
            values = np.concatenate([
                scenario_re(sample.beta_rad, sample.gamma_rad,
                            yokes[first:first + ROWS_PER_BLOCK, np.newaxis, :])
                for first in range(0, len(yokes), ROWS_PER_BLOCK)])
            if self.robust_objective == "mean":
                means: np.ndarray = values.mean(axis=1)
                return means
            return np.array([cvar(row, weights, self.level) for row in values])

        return objective


def optimise_robust(geometry: ColumnGeometry, tolerances: Tolerances, *,
                    robust_objective: str = "p95",
                    solvers: tuple[str, ...] = CROSS_CHECK_SOLVERS,
                    starts: int = DEFAULT_COLUMN_STARTS,
                    solver_tol: float = DEFAULT_COLUMN_SOLVER_TOL,
                    max_iterations: int = DEFAULT_MAX_ITERATIONS,
                    seed: int = DEFAULT_COLUMN_SEED) -> RobustResult:
    """Yoke phasing that minimises RE over a sample of built columns.

    Parameters
    ----------
    geometry : ColumnGeometry
        The nominal column, at least 2 joints.
    tolerances : Tolerances
        Tolerances and the sample (size, seed, distribution).
    robust_objective : str
        ``"mean"`` (mean RE over the sample) or ``"pNN"`` with ``50 <= NN < 100``
        (e.g. ``"p95"``): the CVaR at level ``NN / 100``, the mean of the worst
        ``100 - NN`` % of the sample, a smooth convex upper bound of the NN-th
        percentile. The sample must leave at least one column in that tail.
    solvers : tuple of {"ipopt", "slsqp"}
        With two they are cross-checked.
    starts : int
        Space-filling starts per solver, added to the nominal optimum and its
        equivalent phasings.
    solver_tol : float
        Solver tolerance on the scaled problem (objective divided by the nominal
        optimum's objective over the sample).
    max_iterations, seed
        As :func:`sso.optimise` (``seed`` for the starts; the sample has its own).

    Returns
    -------
    RobustResult
        Solver failures and disagreements are reported in it, not raised.

    Raises
    ------
    TypeError
        If ``geometry`` or ``tolerances`` has the wrong type.
    ValueError
        For a bad objective (``robust_objective``) or option, naming the field.
    """
    if not isinstance(geometry, ColumnGeometry):
        raise TypeError(f"geometry must be a ColumnGeometry, not {type(geometry).__name__}")
    if not isinstance(tolerances, Tolerances):
        raise TypeError(f"tolerances must be a Tolerances, not {type(tolerances).__name__}")
    objective, level = _objective(robust_objective, tolerances.samples)
    solver_names = validate_solvers(solvers)
    starts = validate_count("starts", starts, 0, MAX_STARTS)
    max_iterations = validate_count("max_iterations", max_iterations, 1, MAX_ITERATIONS)
    solver_tol = validate_solver_tol(solver_tol)

    nominal = optimise_phasing(geometry, solvers=solver_names, seed=seed)
    sample = tolerances.sample(geometry)
    weights = np.full(tolerances.samples, 1.0 / tolerances.samples)
    nominal_values = sample.residual_error(nominal.yoke_phase_deg)

    def objective_value(values: np.ndarray) -> float:
        return float(np.mean(values)) if objective == "mean" else cvar(values, weights, level)

    within = (optimise_phasing(geometry, solvers=solver_names, seed=seed, tolerances=tolerances)
              if is_exact(nominal.fun) else None)
    if within is not None and within.optimisation.exact_optima is not None:
        solved = _phasing_run(within)
    else:
        within = None
        reference = objective_value(nominal_values)
        solved = solve_scenarios(
            sample.beta_rad, sample.gamma_rad, objective=objective, weights=weights,
            scale=1.0 / reference if reference > 0 else 1.0, level=level,
            user_starts_deg=[nominal.yoke_phase_deg, *nominal.equivalent_yoke_phase_deg],
            starts=starts, solvers=solver_names, solver_tol=solver_tol,
            max_iterations=max_iterations, seed=seed)
    robust_values = sample.residual_error(solved.yoke_phase_deg)
    beta_rad = np.radians([geometry.beta_deg])
    gamma_rad = np.radians([geometry.plane_angle_deg])
    nominal_re = float(scenario_re(beta_rad, gamma_rad, solved.yoke_phase_deg)[0])
    fresh = Tolerances(tolerances.hardpoint_mm, tolerances.yoke_phase_deg,
                       tolerances.cross_angle_deg, tolerances.samples, tolerances.seed + 1,
                       tolerances.distribution).sample(geometry)
    robust_study = SampleStudy.of(nominal_re, robust_values)
    nominal_study = SampleStudy.of(nominal.fun, nominal_values)
    chosen_within = ("" if within is None else
                     f"{within.exact_optimum_criterion}, within the set of exact optima; ")
    message = (f"{solved.best.message}; {chosen_within}"
               f"{objective_short_name(robust_objective, level)} "
               f"{objective_value(robust_values):.6g} (nominal optimum "
               f"{objective_value(nominal_values):.6g}); p95 {robust_study.p95:.6g} against "
               f"{nominal_study.p95:.6g}; nominal RE {nominal_re:.6g} against {nominal.fun:.6g}")
    return RobustResult(
        **outcome_fields(solved, objective_value(robust_values), message),
        robust_objective=robust_objective, level=level, nominal_re=nominal_re,
        nominal_optimum_re=nominal.fun,
        nominal_re_given_up=max(0.0, nominal_re - nominal.fun),
        robust_study=robust_study, nominal_study=nominal_study,
        validation_robust_study=SampleStudy.of(nominal_re,
                                               fresh.residual_error(solved.yoke_phase_deg)),
        validation_nominal_study=SampleStudy.of(nominal.fun,
                                                fresh.residual_error(nominal.yoke_phase_deg)),
        tolerances=tolerances, geometry=geometry, nominal=nominal, exact_choice=within)


def _phasing_run(phasing: PhasingResult) -> ScenarioRun:
    """The solvers' answers of a phasing run (:func:`optimise_phasing`), their designs
    in yoke phasing (deg) as a shared-phasing result holds them."""
    geometry = phasing.geometry

    def in_yoke_terms(solution: Solution) -> Solution:
        return replace(solution, x=geometry.yoke_phase_deg_from_phase(solution.x))

    run = phasing.optimisation
    return ScenarioRun(yoke_phase_deg=phasing.yoke_phase_deg, best=in_yoke_terms(run.best),
                       solutions={name: in_yoke_terms(solution)
                                  for name, solution in run.solutions.items()},
                       runs=tuple(in_yoke_terms(solution) for solution in run.runs),
                       crosscheck=run.crosscheck)


def objective_short_name(robust_objective: str, level: float) -> str:
    """``"mean RE"``, or ``"CVaR95 of RE"`` for the objective ``"p95"`` at level 0.95
    (the mean of the worst 5 %, not the 95th percentile)."""
    return "mean RE" if robust_objective == "mean" else f"CVaR{100.0 * level:g} of RE"


def _objective(robust_objective: Any, samples: int) -> tuple[str, float]:
    """NLP objective (``"mean"`` or ``"cvar"``) and level, or raise naming the field."""
    if robust_objective == "mean":
        return "mean", 0.0
    match = PERCENTILE_PATTERN.fullmatch(robust_objective) if isinstance(robust_objective,
                                                                          str) else None
    if match is None:
        raise ValueError(f"robust_objective = {robust_objective!r} is not 'mean' or a percentile "
                         "'pNN' with 50 <= NN < 100 (e.g. 'p95')")
    percentile = float(match.group(1))
    if not LOWEST_PERCENTILE <= percentile < 100.0:
        raise ValueError(f"robust_objective = {robust_objective!r}: the percentile {percentile:g} "
                         "is outside the allowed range [50, 100)")
    level = percentile / 100.0
    if (1.0 - level) * samples < 1.0:
        raise ValueError(f"robust_objective = {robust_objective!r} needs at least "
                         f"{int(np.ceil(1.0 / (1.0 - level)))} samples to have one in its tail; "
                         f"tolerances.samples = {samples}")
    return "cvar", level
