"""One yoke phasing for many scenarios: the NLP behind positions and tolerances.

A scenario ``s`` is one column (operating angles ``beta_s``, bend-plane angles
``gamma_s``, both fixed): a tilt position, or one draw of manufacturing errors.
The design variables are the yoke phasings ``delta`` (one per intermediate shaft,
shared by every scenario); scenario ``s`` runs at the model phases
``phi_s = 90 + delta - gamma_s`` and its RE is the closed form of the chain matrix
(:mod:`sso._column.chain_matrix`) written as CasADi expressions, so IPOPT gets the
exact Hessian and SLSQP the exact gradient. Three objectives, all smooth:

* ``"mean"``: ``sum_s w_s RE_s`` (bounds only);
* ``"worst"``: the epigraph ``min t`` s.t. ``RE_s <= t`` for every ``s``;
* ``"cvar"``: the conditional value at risk at level ``alpha`` (the mean of the
  worst ``1 - alpha`` of the weighted sample) in Rockafellar and Uryasev's form
  ``min t + sum_s w_s z_s / (1 - alpha)`` s.t. ``z_s >= RE_s - t``, ``z_s >= 0``.

RE is multiplied by ``scale`` inside the NLP (so the objective is of order one
and the solvers' tolerances mean the same for RE 1e-4 and RE 1): the solutions
returned carry RE itself in ``fun``, and ``kkt`` of the scaled problem (per rad).
"""

from __future__ import annotations

import abc
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any, ClassVar

import numpy as np

from sso._column.chain_matrix import residual_error
from sso._column.geometry import wrap_half_turn
from sso._column.splines import SplineResult, best_teeth_for_objective
from sso._display import Readable
from sso._limits import (
    DEFAULT_KKT_TOLERANCE,
    DEFAULT_OBJECTIVE_ATOL,
    DEFAULT_OBJECTIVE_RTOL,
    DEFAULT_SPLINE_TEETH,
)
from sso._record import NON_NEGATIVE, FieldRule, Record, register_record
from sso._solvers.crosscheck import crosscheck
from sso._solvers.multistart import best_solution, run_starts, solution_from_run
from sso._solvers.nlp import cached_nlp, compile_nlp
from sso._solvers.run import RunLimits
from sso._solvers.solution import CrossCheck, Solution
from sso._solvers.starts import start_points

# Yoke phasing bounds of the NLP, deg: two periods (RE has period 180 deg in each
# phasing), so every minimum lies strictly inside them and no start stalls on a bound.
YOKE_BOUNDS_DEG = (-180.0, 180.0)


@register_record
@dataclass(frozen=True)
class ScenarioRun:
    """The solvers' answers to one phasing problem, before a result is made of them.

    ``yoke_phase_deg`` (deg, in ``[-90, 90)``), ``best``, ``solutions``, ``runs`` and
    ``crosscheck`` mean what they mean in :class:`PhasingOutcome`.
    """

    yoke_phase_deg: tuple[float, ...]
    best: Solution
    solutions: dict[str, Solution]
    runs: tuple[Solution, ...]
    crosscheck: CrossCheck | None

    @property
    def success(self) -> bool:
        """The best run converged and the solvers agree."""
        return self.best.success and (self.crosscheck is None or self.crosscheck.agree)


@dataclass(frozen=True, eq=False, repr=False)
class PhasingOutcome(Record, Readable, abc.ABC):
    """What every shared-phasing result has, named after ``scipy.optimize.OptimizeResult``.

    Attributes
    ----------
    x : tuple of float
        The yoke phasing per intermediate shaft, deg, in ``[-90, 90)`` (fitter's
        convention; same as ``yoke_phase_deg``).
    fun : float
        The objective at ``x`` (RE units).
    nit, nfev, status : int
        Of the best run.
    success : bool
        The best run converged and the solvers agree.
    message : str
    best : sso.Solution
        Best answer (``x`` the phasing in deg, ``fun`` in RE units).
    solutions : dict of str to Solution
        Best answer of each solver.
    runs : tuple of Solution
        Every run of every solver.
    crosscheck : sso.CrossCheck or None
        Verdict on the solvers (None with one solver).
    """

    _record_rules: ClassVar[dict[str, FieldRule]] = {"fun": NON_NEGATIVE}

    x: tuple[float, ...]
    fun: float
    nit: int
    nfev: int
    status: int
    success: bool
    message: str
    best: Solution
    solutions: dict[str, Solution]
    runs: tuple[Solution, ...]
    crosscheck: CrossCheck | None

    @property
    def yoke_phase_deg(self) -> tuple[float, ...]:
        """The yoke phasing, deg (same as ``x``)."""
        return self.x

    @property
    @abc.abstractmethod
    def objective_name(self) -> str:
        """What ``fun`` measures, in words."""

    @abc.abstractmethod
    def phasing_objective(self) -> Callable[[np.ndarray], np.ndarray]:
        """The objective ``fun`` as a function of yoke phasings: an array of shape
        ``(m, shafts)`` (deg, fitter's convention) -> ``(m,)`` values, lower is better."""

    def on_splines(self, teeth: int | Sequence[int] = DEFAULT_SPLINE_TEETH) -> SplineResult:
        """Whole teeth (``teeth`` per intermediate shaft, each in ``[1, 1000]``) searched
        for this result's own objective (:meth:`phasing_objective`), as
        :func:`~sso._column.splines.best_teeth_for_objective` returns them:
        ``residual_error`` is the objective at the teeth, ``continuous_residual_error``
        at ``x``.

        Raises
        ------
        ValueError
            If a tooth count is not a whole number in range.
        """
        return best_teeth_for_objective(len(self.x), teeth, self.phasing_objective(),
                                        continuous_yoke_phase_deg=self.x,
                                        objective_name=self.objective_name)


def outcome_fields(solved: ScenarioRun, fun: float, message: str) -> dict[str, Any]:
    """The :class:`PhasingOutcome` fields of a solved problem, as keywords."""
    check = solved.crosscheck
    return {"x": solved.yoke_phase_deg, "fun": fun, "nit": solved.best.nit,
            "nfev": solved.best.nfev, "status": solved.best.status, "success": solved.success,
            "message": message + ("" if check is None else f"; {check.message}"),
            "best": solved.best, "solutions": solved.solutions, "runs": solved.runs,
            "crosscheck": check}


def scenario_re(beta_rad: np.ndarray, gamma_rad: np.ndarray, yoke_phase_deg: Any) -> np.ndarray:
    """RE of every scenario at one yoke phasing (or at rows of phasings).

    Parameters
    ----------
    beta_rad : numpy.ndarray, shape (S, n)
        Operating angles of each scenario, rad.
    gamma_rad : numpy.ndarray, shape (S, n - 1)
        Bend-plane angles of each scenario, rad (minus any yoke phase error).
    yoke_phase_deg : array_like, shape (n - 1,) or (..., 1, n - 1)
        Yoke phasing, deg.

    Returns
    -------
    numpy.ndarray, shape (S,) or (..., S)
    """
    phase = np.pi / 2 + np.radians(np.asarray(yoke_phase_deg, dtype=float)) - gamma_rad
    return residual_error(beta_rad, phase)


def solve_scenarios(beta_rad: np.ndarray, gamma_rad: np.ndarray, *, objective: str,
                    weights: np.ndarray, scale: float, level: float = 0.0,
                    user_starts_deg: Sequence[Sequence[float]], starts: int,
                    solvers: tuple[str, ...], solver_tol: float, max_iterations: int,
                    seed: int) -> ScenarioRun:
    """Best shared yoke phasing of the scenarios under one objective.

    Parameters
    ----------
    beta_rad, gamma_rad : numpy.ndarray
        As :func:`scenario_re`.
    objective : {"mean", "worst", "cvar"}
    weights : numpy.ndarray, shape (S,)
        Non-negative weights summing to 1 (``"mean"`` and ``"cvar"``).
    scale : float
        RE is multiplied by this inside the NLP (> 0).
    level : float
        ``alpha`` of ``"cvar"``, in ``[0, 1)``.
    user_starts_deg : sequence of sequence of float
        Starts given by the caller (yoke phasing, deg), tried first.
    starts : int
        Space-filling starts added to them.
    solvers, solver_tol, max_iterations, seed
        As :func:`sso.optimise`.
    """
    count, joints = beta_rad.shape
    nlp = cached_nlp(("column_scenarios", objective, count, joints),
                     lambda: _build(objective, count, joints))
    parameters = np.concatenate([np.cos(beta_rad).ravel(), gamma_rad.ravel(), weights,
                                 [scale, level]])
    shafts = joints - 1
    delta_starts, lower_delta, upper_delta = yoke_starts(user_starts_deg, shafts, starts, seed)
    points, limits = _epigraph_starts(objective, delta_starts, beta_rad, gamma_rad, weights,
                                      scale, level, lower_delta, upper_delta)
    return solve_phasing_nlp(nlp, parameters, points, limits, shafts, scale, solvers,
                             solver_tol, max_iterations)


def yoke_starts(user_starts_deg: Sequence[Sequence[float]], shafts: int, starts: int,
                seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Starts of the yoke phasing (rad): the caller's, then ``starts`` Halton points;
    and the bounds ``YOKE_BOUNDS_DEG`` (rad)."""
    lower_delta = np.full(shafts, np.radians(YOKE_BOUNDS_DEG[0]))
    upper_delta = np.full(shafts, np.radians(YOKE_BOUNDS_DEG[1]))
    given = np.radians(np.asarray(user_starts_deg, dtype=float).reshape(-1, shafts))
    spread = start_points(given[0], lower_delta, upper_delta, starts + 1, seed)[1:]
    return np.vstack([given, spread]), lower_delta, upper_delta


def solve_phasing_nlp(nlp: Any, parameters: np.ndarray, points: np.ndarray, limits: RunLimits,
                      shafts: int, scale: float, solvers: tuple[str, ...], solver_tol: float,
                      max_iterations: int) -> ScenarioRun:
    """Every solver from every start on an NLP whose first ``shafts`` variables are the
    yoke phasing (rad) and whose objective is RE-like times ``scale``; cross-checked."""
    measured = run_starts(nlp, points, parameters, limits, solvers, solver_tol, max_iterations)

    def yoke(x: np.ndarray) -> tuple[float, ...]:
        return tuple(float(value) for value in wrap_half_turn(np.degrees(x[:shafts])))

    solver_runs = {name: [replace(solution_from_run(run, runs, x=yoke(run.outcome.x)),
                                  fun=run.fun / scale) for run in runs]
                   for name, runs in measured.items()}
    solutions = {name: best_solution(runs) for name, runs in solver_runs.items()}
    best = best_solution(solutions.values())
    check = (crosscheck(solutions, DEFAULT_OBJECTIVE_RTOL, DEFAULT_OBJECTIVE_ATOL,
                        DEFAULT_KKT_TOLERANCE) if len(solutions) > 1 else None)
    return ScenarioRun(yoke_phase_deg=best.x, best=best, solutions=solutions,
                       runs=tuple(run for runs in solver_runs.values() for run in runs),
                       crosscheck=check)


def cvar(values: np.ndarray, weights: np.ndarray, level: float) -> float:
    """Conditional value at risk of a weighted sample: the mean of its worst ``1 - level``.

    The value the ``"cvar"`` NLP minimises, computed by sorting (``min_t t + sum
    w (v - t)+ / (1 - level)`` is attained at the weighted ``level``-quantile).
    """
    threshold = _weighted_quantile(values, weights, level)
    tail = np.maximum(values - threshold, 0.0)
    return threshold + float(np.dot(weights, tail)) / (1.0 - level)


def _epigraph_starts(objective: str, delta_starts: np.ndarray, beta_rad: np.ndarray,
                     gamma_rad: np.ndarray, weights: np.ndarray, scale: float, level: float,
                     lower_delta: np.ndarray, upper_delta: np.ndarray
                     ) -> tuple[np.ndarray, RunLimits]:
    """Full NLP starts (phasing plus feasible epigraph variables) and the bounds."""
    count = len(beta_rad)
    if objective == "mean":
        return delta_starts, RunLimits(lower_delta, upper_delta)
    values = scale * scenario_re(beta_rad, gamma_rad,
                                 np.degrees(delta_starts)[:, None, :])  # (starts, S)
    if objective == "worst":
        epigraph = values.max(axis=1)[:, None]
        lower = np.concatenate([lower_delta, [0.0]])
        upper = np.concatenate([upper_delta, [np.inf]])
    else:
        thresholds = np.array([_weighted_quantile(row, weights, level) for row in values])
        epigraph = np.hstack([thresholds[:, None],
                              np.maximum(values - thresholds[:, None], 0.0)])
        lower = np.concatenate([lower_delta, [0.0], np.zeros(count)])
        upper = np.concatenate([upper_delta, [np.inf], np.full(count, np.inf)])
    limits = RunLimits(lower, upper, constraint_lower=np.full(count, -np.inf),
                       constraint_upper=np.zeros(count))
    return np.hstack([delta_starts, epigraph]), limits


def _weighted_quantile(values: np.ndarray, weights: np.ndarray, level: float) -> float:
    order = np.argsort(values)
    cumulative = np.cumsum(weights[order])
    index = min(int(np.searchsorted(cumulative, level, side="left")), len(values) - 1)
    return float(values[order][index])


def _build(objective: str, count: int, joints: int) -> Any:
    import casadi

    shafts = joints - 1
    p = casadi.SX.sym("p", count * joints + count * shafts + count + 2)
    cos_beta = casadi.reshape(p[:count * joints], joints, count).T
    offset = count * joints
    gamma = casadi.reshape(p[offset:offset + count * shafts], shafts, count).T
    offset += count * shafts
    weights = p[offset:offset + count]
    scale, level = p[offset + count], p[offset + count + 1]
    size = {"mean": shafts, "worst": shafts + 1, "cvar": shafts + 1 + count}[objective]
    x = casadi.SX.sym("x", size)
    delta = x[:shafts]
    values = casadi.vertcat(*[
        scale * residual_error_expression(
            [cos_beta[s, k] for k in range(joints)],
            [np.pi / 2 + delta[k] - gamma[s, k] for k in range(shafts)])
        for s in range(count)])
    name = f"sso_column_{objective}_{count}_{joints}"
    if objective == "mean":
        return compile_nlp(name, x, p, casadi.dot(weights, values))
    bound = x[shafts]
    if objective == "worst":
        return compile_nlp(name, x, p, bound, values - bound)
    excess = x[shafts + 1:]
    return compile_nlp(name, x, p, bound + casadi.dot(weights, excess) / (1.0 - level),
                       values - bound - excess)


def residual_error_expression(cos_beta: Sequence[Any], phase_rad: Sequence[Any]) -> Any:
    """RE of the exact chain as one expression (CasADi symbols or floats).

    ``RE = ((m11 - m22)^2 + (m12 + m21)^2) / (2 det M)`` of :func:`chain_matrix_expression`.
    """
    m11, m12, m21, m22 = chain_matrix_expression(cos_beta, phase_rad)
    return ((m11 - m22) ** 2 + (m12 + m21) ** 2) / (2.0 * (m11 * m22 - m12 * m21))


def chain_matrix_expression(cos_beta: Sequence[Any], phase_rad: Sequence[Any]
                            ) -> tuple[Any, Any, Any, Any]:
    """Entries ``m11, m12, m21, m22`` of ``M = D_n R(phi_(n-1)) ... R(phi_1) D_1``.

    ``D_k = diag(1, cos beta_k)``; CasADi expressions (the numpy twin is
    :func:`sso._column.chain_matrix.chain_matrix`).
    """
    import casadi

    m11: Any = 1.0
    m12: Any = 0.0
    m21: Any = 0.0
    m22: Any = cos_beta[0]
    for k in range(1, len(cos_beta)):
        cosine, sine = casadi.cos(phase_rad[k - 1]), casadi.sin(phase_rad[k - 1])
        top = (cosine * m11 - sine * m21, cosine * m12 - sine * m22)
        bottom = (sine * m11 + cosine * m21, sine * m12 + cosine * m22)
        m11, m12 = top
        m21, m22 = cos_beta[k] * bottom[0], cos_beta[k] * bottom[1]
    return m11, m12, m21, m22
