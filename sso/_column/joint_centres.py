"""Joint centres as design variables: move them within boxes to even the output.

The design vector holds the joint centres ``P1 .. Pn`` (each free within its box,
mm) and, when the phasing is free, the yoke phasings ``delta_k``; ``P0`` and
``P(n+1)`` (the points on the input and output shaft axes) stay where they are.
Constraints bound every operating angle and every shaft length.

The exact model's RE is a smooth function of the points and the phasing:
``u_k`` from the points, ``cos beta_k = u_(k-1) . u_k``, and the model phase
``phi_k = 90 + delta_k - gamma_k`` enters the chain only through
``(cos phi_k, sin phi_k)``. With the unnormalised bend normals
``m_k = u_(k-1) x u_k``, ``C = m_k . m_(k+1)`` and ``S = (m_k x m_(k+1)) . u_k`` are
``|m_k| |m_(k+1)|`` times ``(cos gamma_k, sin gamma_k)``, so

    (cos phi_k, sin phi_k) ~ (S cos delta_k - C sin delta_k, C cos delta_k + S sin delta_k)

up to that positive factor, which RE ignores (:mod:`sso._column.chain_matrix`). No
``atan2`` or ``acos`` enters the graph. The chain itself is the numpy source of
:func:`sso._column.chain_matrix.chain_entries`, run on CasADi symbols.

Where RE = 0 is reachable the exact optima form a set (many coordinates, two
residuals ``r = (m11 - m22, m12 + m21) / sqrt(2 det M)``); the design is chosen within
it as a shaft series' is (:mod:`sso._shafts.exact_optima`): the joint centres furthest
inside their boxes, and the set's extent per coordinate is reported.

Straight-joint singularity: at ``beta_k = 0`` the bend plane is undefined, ``m_k``
vanishes and ``M`` degenerates to 0/0. The lower operating-angle bound must
therefore be positive (it is refused otherwise); the constraints keep every
joint at least that far from straight.
"""

from __future__ import annotations

import functools
import itertools
import math
import time
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from typing import Any, ClassVar

import numpy as np

from sso._column.cancel import can_cancel
from sso._column.chain_matrix import (
    chain_entries,
    entries_residual_error,
    residual_error,
)
from sso._column.geometry import ColumnGeometry, wrap_half_turn
from sso._column.phasing import PHASE_BOUNDS_DEG, optimise_phasing
from sso._display import Part, TextTable, format_number, format_numbers
from sso._limits import (
    BETA_LIMIT_DEG,
    CROSS_CHECK_SOLVERS,
    DEFAULT_COLUMN_SEED,
    DEFAULT_JOINT_BETA_BOUNDS_DEG,
    DEFAULT_KKT_TOLERANCE,
    DEFAULT_MAX_ITERATIONS,
    DEFAULT_OBJECTIVE_ATOL,
    DEFAULT_OBJECTIVE_RTOL,
    DEFAULT_SHAFT_SOLVER_TOL,
    DEFAULT_SHORTEST_SHAFT_FRACTION,
    DEFAULT_STARTS,
    MAX_ITERATIONS,
    MAX_STARTS,
)
from sso._record import NON_NEGATIVE, FieldRule
from sso._shafts.exact_optima import (
    ExactOptimumSet,
    SetProblem,
    choose_exact_optimum,
    is_exact,
    selection_run,
)
from sso._solvers.multistart import SolverFields, solution_from_run, solve_from_starts
from sso._solvers.result import DesignResult
from sso._solvers.run import RunLimits
from sso._solvers.solution import ROLE_SELECTION, Solution
from sso._validation import (
    as_float_tuple,
    check_chain_conditioning,
    finite_float,
    per_item_bounds,
    validate_count,
    validate_solver_tol,
    validate_solvers,
)

# The NLP works in metres and radians: RE changes by about as much per metre of
# joint travel as per radian of phasing, so neither set of variables is flat.
MM_PER_UNIT = 1000.0
JOINT_SET_CRITERION = "largest margin of the joint centres to their boxes"
"""How a design is chosen within a set of exact optima of joint centres (mm)."""
BOX_SOLVER = "least_squares"
"""SciPy's bounded least squares (``trf``): the box solves of that choice."""


@dataclass(frozen=True, kw_only=True, eq=False, repr=False)
class JointCentresResult(DesignResult):
    """The best joint positions (and phasing) within the boxes.

    The solver fields (``best``, ``solutions``, ``runs``, ``crosscheck``,
    ``local_minima``) and ``x`` (joint centres ``P1 .. Pn``, x, y, z each in mm, then
    the yoke phasings in deg when they are free), ``fun`` (RE), ``success`` (the best
    run converged, feasible, and the solvers agree) come from
    :class:`sso._solvers.result.DesignResult`.

    Attributes
    ----------
    initial : ColumnGeometry
        The column as given.
    geometry : ColumnGeometry
        The column at the optimum.
    points_mm : tuple of (float, float, float)
        ``P0 .. P(n+1)`` at the optimum, mm.
    yoke_phase_deg : tuple of float
        Yoke phasing at the optimum (the fixed one when not free), deg, in ``[-90, 90)``.
    phasing_free : bool
        Whether the yoke phasing was a design variable (else held as given).
    initial_re : float
        RE of the given points with the start phasing: the best phasing of those
        points when the phasing is free, else the fixed phasing.
    fixed_points_re : float
        Least RE over every phasing with the given points (closed form).
    beta_bounds_deg : tuple of (float, float)
        Operating-angle bounds per joint, deg.
    shaft_length_bounds_mm : tuple of (float, float)
        Length bounds per shaft, mm (``inf`` for none).
    joint_boxes_mm : tuple of ((float, float, float), (float, float, float))
        Lower and upper corner of each joint's box, mm.
    constraint_violation : float
        Largest violation of a box, angle or length bound at the optimum, in the
        NLP's units (m; cosine of an angle).
    exact_optima : sso._shafts.exact_optima.ExactOptimumSet or None
        Where RE is at round-off zero and the solvers are cross-checked: how the
        design was chosen within the set of exact optima (the joint centres furthest
        inside their boxes, margin in mm; the angle and length bounds kept), its
        figures and the set's extent per coordinate (mm) and free yoke phasing (deg);
        None otherwise.
    """

    _record_rules: ClassVar[dict[str, FieldRule]] = {"fun": NON_NEGATIVE}

    initial: ColumnGeometry
    geometry: ColumnGeometry
    points_mm: tuple[tuple[float, float, float], ...]
    yoke_phase_deg: tuple[float, ...]
    phasing_free: bool
    initial_re: float
    fixed_points_re: float
    beta_bounds_deg: tuple[tuple[float, float], ...]
    shaft_length_bounds_mm: tuple[tuple[float, float], ...]
    joint_boxes_mm: tuple[tuple[tuple[float, ...], tuple[float, ...]], ...]
    constraint_violation: float
    exact_optima: ExactOptimumSet | None = None

    @property
    def message(self) -> str:
        """The best run's message, the RE it reached against the given points, and the
        cross-check's verdict."""
        return (f"{self.best.solver}: {self.best.message}; RE {self.fun:.6g} (start "
                f"{self.initial_re:.6g}, best phasing of the given points "
                f"{self.fixed_points_re:.6g})"
                + ("" if self.crosscheck is None else f"; {self.crosscheck.message}"))

    def _repr_text(self) -> str:
        verdict = "success" if self.success else "FAILED"
        return (f"{verdict}: RE {format_number(self.initial_re, 4)} -> "
                f"{format_number(self.fun, 4)} by {self.best.solver}; yoke_phase_deg "
                f"[{format_numbers(self.yoke_phase_deg)}], {len(self.points_mm)} points")

    def _summary_parts(self) -> list[Part]:
        verdict = "success" if self.success else "FAILED"
        points = TextTable(("point", "x (mm)", "y (mm)", "z (mm)"),
                           tuple((f"P{index}", *(format_number(value) for value in point))
                                 for index, point in enumerate(self.points_mm)))
        solvers = TextTable(("solver", "converged", "RE", "iterations", "message"),
                            tuple((name, "yes" if solution.success else "no",
                                   format_number(solution.fun), str(solution.nit),
                                   solution.message)
                                  for name, solution in self.solutions.items()))
        exact = [] if self.exact_optima is None else self.exact_optima._summary_parts()
        return [f"Joint centres: {verdict}; RE {format_number(self.initial_re)} as given, "
                f"{format_number(self.fixed_points_re)} with the given points and the best "
                f"phasing, {format_number(self.fun)} at the optimum",
                points, f"yoke phasing (deg): {format_numbers(self.yoke_phase_deg)}", *exact,
                solvers]


def optimise_joint_centres(
    geometry: ColumnGeometry,
    *,
    joint_boxes_mm: Any,
    beta_bounds_deg: Any = DEFAULT_JOINT_BETA_BOUNDS_DEG,
    shaft_length_bounds_mm: Any = None,
    yoke_phase_deg: Sequence[float] | None = None,
    solvers: Iterable[str] | str = CROSS_CHECK_SOLVERS,
    starts: int = DEFAULT_STARTS,
    solver_tol: float = DEFAULT_SHAFT_SOLVER_TOL,
    max_iterations: int = DEFAULT_MAX_ITERATIONS,
    seed: int = DEFAULT_COLUMN_SEED,
) -> JointCentresResult:
    """Joint centres (and yoke phasing) that make the output turn most evenly.

    Parameters
    ----------
    geometry : ColumnGeometry
        The start column, at least 2 joints, none of them straight.
    joint_boxes_mm : sequence of ((x, y, z), (x, y, z))
        Lower and upper corner of the box of each joint centre ``P1 .. Pn``, mm;
        the start point must lie inside. Equal corners pin a coordinate.
    beta_bounds_deg : (float, float) or sequence of pairs
        Operating-angle bounds, deg, one pair for all joints or one per joint;
        lower bounds in ``(0, 90)`` (a straight joint has no bend plane).
    shaft_length_bounds_mm : (float, float) or sequence of pairs, optional
        Shaft-length bounds, mm, one pair for all or one per shaft (``n + 1``),
        lower bounds > 0, ``inf`` allowed as upper; default each shaft at least
        half its start length, no upper bound.
    yoke_phase_deg : sequence of float, optional
        Fixed yoke phasing (deg, one per intermediate shaft); default free.
    solvers, starts, solver_tol, max_iterations, seed
        As in :func:`sso.optimise`. The first start is the given points with the
        best phasing for them (free phasing) or the fixed phasing.

    Returns
    -------
    JointCentresResult
        Solver failures and disagreements are reported in it, not raised.

    Raises
    ------
    TypeError
        If ``geometry`` is not a :class:`ColumnGeometry`.
    ValueError
        For a straight joint at the given points, or a bad box, bound or option,
        naming the field, the value and the range.
    """
    if not isinstance(geometry, ColumnGeometry):
        raise TypeError(f"geometry must be a ColumnGeometry, not {type(geometry).__name__}")
    joints = geometry.joint_count
    if joints < 2:
        raise ValueError("geometry has 1 joint: joint positions need at least 2 joints "
                         "(an intermediate shaft)")
    straight = [joint for joint, flag in enumerate(geometry.straight_joints, start=1) if flag]
    if straight:
        raise ValueError(f"joint {straight[0]} (points_mm[{straight[0]}]) is straight at the "
                         "given points (beta = 0): its bend plane is undefined there, so the "
                         "joint-position design needs every joint bent; move that point off "
                         "the line through its neighbours")
    solver_names = validate_solvers(solvers)
    starts = validate_count("starts", starts, 1, MAX_STARTS)
    max_iterations = validate_count("max_iterations", max_iterations, 1, MAX_ITERATIONS)
    solver_tol = validate_solver_tol(solver_tol)
    boxes = _validated_boxes(joint_boxes_mm, geometry)
    beta_bounds = per_item_bounds("beta_bounds_deg", beta_bounds_deg, joints, 0.0,
                                  BETA_LIMIT_DEG, "deg", upper_open=True)
    for index, (least_deg, _) in enumerate(beta_bounds):
        if least_deg <= 0.0:
            raise ValueError(f"beta_bounds_deg[{index}] lower = {least_deg:g} is outside the "
                             f"allowed range (0, {BETA_LIMIT_DEG:g}) deg: a straight joint has no "
                             "bend plane, so every joint must stay bent")
    check_chain_conditioning("beta_bounds_deg (their upper bounds)",
                        [upper for _, upper in beta_bounds])
    length_bounds = _validated_lengths(shaft_length_bounds_mm, geometry)
    phasing_free = yoke_phase_deg is None
    if phasing_free:
        reference = optimise_phasing(geometry, solvers=solver_names, seed=seed)
        start_phase_deg = reference.yoke_phase_deg
        fixed_points_re = reference.minimum_residual_error
    else:
        start_phase_deg = geometry.yoke_phase_deg_from_phase(
            geometry.phase_deg_from_yoke(as_float_tuple("yoke_phase_deg", yoke_phase_deg or ())))
        fixed_points_re = can_cancel(geometry.beta_deg).minimum_residual_error
    initial_re = _residual_error(geometry, start_phase_deg)

    points: np.ndarray = np.asarray(geometry.points_mm) / MM_PER_UNIT
    box_lower: np.ndarray = np.array([box[0] for box in boxes]).ravel() / MM_PER_UNIT
    box_upper: np.ndarray = np.array([box[1] for box in boxes]).ravel() / MM_PER_UNIT
    phase_rad = np.radians(start_phase_deg)
    ends = np.concatenate([points[0], points[-1]])
    if phasing_free:
        lower = np.concatenate([box_lower, np.full(joints - 1, math.radians(PHASE_BOUNDS_DEG[0]))])
        upper = np.concatenate([box_upper, np.full(joints - 1, math.radians(PHASE_BOUNDS_DEG[1]))])
        user_start = np.concatenate([points[1:-1].ravel(), phase_rad])
        parameters = ends
    else:
        lower, upper = box_lower, box_upper
        user_start = points[1:-1].ravel()
        parameters = np.concatenate([ends, phase_rad])
    limits = RunLimits(
        lower, upper,
        constraint_lower=np.concatenate([np.cos(np.radians([pair[1] for pair in beta_bounds])),
                                         np.array([pair[0] for pair in length_bounds])
                                         / MM_PER_UNIT]),
        constraint_upper=np.concatenate([np.cos(np.radians([pair[0] for pair in beta_bounds])),
                                         np.array([pair[1] for pair in length_bounds])
                                         / MM_PER_UNIT]),
    )
    nlp = compiled_joint_nlp(joints, phasing_free)
    solved = solve_from_starts(
        nlp, user_start, limits, parameters, solver_names=solver_names, starts=starts,
        seed=seed, solver_tol=solver_tol, max_iterations=max_iterations,
        to_solution=lambda run, runs: solution_from_run(run, runs,
                                                        _user_units(run.outcome.x, joints)),
        objective_rtol=DEFAULT_OBJECTIVE_RTOL, objective_atol=DEFAULT_OBJECTIVE_ATOL,
        kkt_tolerance=DEFAULT_KKT_TOLERANCE)
    exact_optima = None
    # As for a shaft series: the choice is made where the solvers are cross-checked.
    if is_exact(solved["best"].fun) and solved["best"].success and len(solver_names) > 1:
        chosen, exact_optima = _most_robust(nlp, solved, parameters, limits, joints,
                                            phasing_free)
        if chosen is not solved["best"]:
            solved["best"], solved["runs"] = chosen, (*solved["runs"], chosen)
    best = solved["best"]
    optimum_points = np.vstack([geometry.points_mm[0],
                                np.asarray(best.x[:3 * joints]).reshape(joints, 3),
                                geometry.points_mm[-1]])
    optimum = ColumnGeometry(tuple((float(row[0]), float(row[1]), float(row[2]))
                                   for row in optimum_points))
    best_phase = (tuple(float(value) for value in wrap_half_turn(best.x[3 * joints:]))
                  if phasing_free else tuple(start_phase_deg))
    return JointCentresResult(
        initial=geometry,
        geometry=optimum,
        points_mm=optimum.points_mm,
        yoke_phase_deg=best_phase,
        phasing_free=phasing_free,
        initial_re=initial_re,
        fixed_points_re=fixed_points_re,
        beta_bounds_deg=beta_bounds,
        shaft_length_bounds_mm=length_bounds,
        joint_boxes_mm=boxes,
        constraint_violation=best.constraint_violation,
        exact_optima=exact_optima,
        **solved,
    )


def column_residual_error(xp: Any, points: Sequence[Any], yoke_phase_rad: Sequence[Any]) -> Any:
    """RE of the exact model from the points and yoke phasings, in ``xp`` (numpy or CasADi).

    Parameters
    ----------
    xp : module
        ``numpy`` or ``casadi``: supplies ``sqrt``, ``cos``, ``sin``, ``dot``, ``cross``.
    points : sequence of 3-vectors
        ``P0 .. P(n+1)`` (any length unit).
    yoke_phase_rad : sequence
        ``delta_k`` per intermediate shaft, rad.

    Every joint must be bent (see the module notes).
    """
    return entries_residual_error(*_chain_of_points(xp, points, yoke_phase_rad))


def column_residuals(xp: Any, points: Sequence[Any], yoke_phase_rad: Sequence[Any]
                     ) -> tuple[Any, Any]:
    """The two residuals ``r = (m11 - m22, m12 + m21) / sqrt(2 det M)`` with ``RE = |r|^2``,
    in ``xp``; parameters as :func:`column_residual_error`."""
    m11, m12, m21, m22 = _chain_of_points(xp, points, yoke_phase_rad)
    scale = 1.0 / xp.sqrt(2.0 * (m11 * m22 - m12 * m21))
    return (m11 - m22) * scale, (m12 + m21) * scale


def _chain_of_points(xp: Any, points: Sequence[Any], yoke_phase_rad: Sequence[Any]
                     ) -> tuple[Any, Any, Any, Any]:
    """The chain matrix's entries (phases scaled by positive factors, see the notes)."""
    directions = []
    for start, end in itertools.pairwise(points):
        difference = end - start
        directions.append(difference / xp.sqrt(xp.dot(difference, difference)))
    cos_beta = [xp.dot(before, after) for before, after in itertools.pairwise(directions)]
    normals = [xp.cross(before, after) for before, after in itertools.pairwise(directions)]
    cos_phase, sin_phase = [], []
    for k, delta in enumerate(yoke_phase_rad):
        cosine = xp.dot(normals[k], normals[k + 1])
        sine = xp.dot(xp.cross(normals[k], normals[k + 1]), directions[k + 1])
        cos_phase.append(sine * xp.cos(delta) - cosine * xp.sin(delta))
        sin_phase.append(cosine * xp.cos(delta) + sine * xp.sin(delta))
    entries: tuple[Any, Any, Any, Any] = chain_entries(cos_beta, cos_phase, sin_phase)
    return entries


def compiled_joint_nlp(joints: int, phasing_free: bool) -> Any:
    """The cached CasADi NLP of a column of ``joints`` joints (free or fixed phasing)."""
    from sso._solvers.nlp import cached_nlp

    return cached_nlp(("column_joint_positions", joints, phasing_free),
                      lambda: _build(joints, phasing_free))


def _symbols(joints: int, phasing_free: bool) -> tuple[Any, Any, list[Any], list[Any]]:
    """The NLP's variables ``x`` and parameters ``p``, the points ``P0 .. P(n+1)`` and the
    yoke phasings as CasADi symbols."""
    import casadi

    shafts = joints - 1
    x = casadi.SX.sym("x", 3 * joints + (shafts if phasing_free else 0))
    p = casadi.SX.sym("p", 6 + (0 if phasing_free else shafts))
    points = [p[0:3]] + [x[3 * j:3 * j + 3] for j in range(joints)] + [p[3:6]]
    phases = x[3 * joints:] if phasing_free else p[6:]
    return x, p, points, [phases[k] for k in range(shafts)]


def _build(joints: int, phasing_free: bool) -> Any:
    import casadi

    from sso._solvers.nlp import compile_nlp

    x, p, points, phases = _symbols(joints, phasing_free)
    objective = column_residual_error(casadi, points, phases)
    differences = [end - start for start, end in itertools.pairwise(points)]
    lengths = [casadi.sqrt(casadi.dot(d, d)) for d in differences]
    cos_beta = [casadi.dot(before, after) / (length_before * length_after)
                for before, after, length_before, length_after
                in zip(differences[:-1], differences[1:], lengths[:-1], lengths[1:], strict=True)]
    constraints = casadi.vertcat(*cos_beta, *lengths)
    return compile_nlp(f"sso_column_joints_{joints}_{'free' if phasing_free else 'fixed'}", x, p,
                       objective, constraints)


@functools.lru_cache(maxsize=8)
def _residual_graph(joints: int, phasing_free: bool) -> Any:
    """``(x, p) -> (r, dr/dx)``: the two residuals of the NLP's design and their Jacobian."""
    import casadi

    x, p, points, phases = _symbols(joints, phasing_free)
    residuals = casadi.vertcat(*column_residuals(casadi, points, phases))
    return casadi.Function(f"sso_column_joint_residuals_{joints}_{phasing_free}", [x, p],
                           [residuals, casadi.densify(casadi.jacobian(residuals, x))])


def _most_robust(nlp: Any, solved: SolverFields, parameters: np.ndarray, limits: RunLimits,
                 joints: int, phasing_free: bool) -> tuple[Solution, ExactOptimumSet]:
    """The design of the set of exact optima with the joint centres furthest inside their
    boxes, as the reported best (the shaft series' choice, :mod:`sso._shafts.exact_optima`)."""
    started = time.perf_counter()
    graph = _residual_graph(joints, phasing_free)

    def residuals_of(x: Sequence[float] | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        values, jacobian = graph(x, parameters)
        return np.asarray(values, dtype=float).ravel(), np.asarray(jacobian, dtype=float)

    def residuals(x: list[float]) -> tuple[complex, list[complex]]:
        values, jacobian = residuals_of(x)
        return (complex(values[0], values[1]),
                [complex(real, imaginary) for real, imaginary in zip(*jacobian, strict=True)])

    problem = _set_problem(nlp, parameters, limits, joints, phasing_free)

    def solve_in_box(start: list[float], low: list[float], high: list[float],
                     max_iterations: int) -> tuple[list[float], float, int, int]:
        from scipy.optimize import least_squares

        lower, upper = np.asarray(low, dtype=float), np.asarray(high, dtype=float)
        moving = upper > lower
        x = np.clip(np.asarray(start, dtype=float), lower, upper)
        evaluations = 0
        if moving.any():
            def placed(free: np.ndarray) -> np.ndarray:
                full: np.ndarray = x.copy()
                full[moving] = free
                return full

            answer = least_squares(lambda free: residuals_of(placed(free))[0], x[moving],
                                   jac=lambda free: residuals_of(placed(free))[1][:, moving],
                                   bounds=(lower[moving], upper[moving]), method="trf",
                                   xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=max_iterations)
            x, evaluations = placed(answer.x), int(answer.nfev)
        values, _ = residuals_of(x)
        fun = float(values @ values) if problem.feasible(x) else math.inf
        return x.tolist(), fun, evaluations, evaluations

    found = [solved["best"], *(run for run in solved["runs"] if run.success and is_exact(run.fun))]
    choice = choose_exact_optimum(problem, residuals, solve_in_box,
                                  [_nlp_units(solution.x, joints) for solution in found], None)
    if choice.solver is None:
        return solved["best"], choice.exact_set
    run = selection_run(choice, solved["best"].start_index, nlp, parameters, limits, started)
    chosen = replace(solution_from_run(run, [run], _user_units(run.outcome.x, joints)),
                     role=ROLE_SELECTION)
    return chosen, choice.exact_set


def _set_problem(nlp: Any, parameters: np.ndarray, limits: RunLimits, joints: int,
                 phasing_free: bool) -> SetProblem:
    """The joint-centre design as a :class:`SetProblem`: coordinates in m (reported in mm,
    the margin), yoke phasings in rad (reported in deg, period 180 deg), angle and length
    bounds kept."""
    shafts = joints - 1 if phasing_free else 0
    lower_finite = np.isfinite(limits.constraint_lower)
    upper_finite = np.isfinite(limits.constraint_upper)

    def constraint_values(x: np.ndarray) -> np.ndarray:
        values, _ = nlp.constraints_and_jacobian(np.asarray(x, dtype=float), parameters)
        values = np.asarray(values, dtype=float).ravel()
        return np.concatenate([(values - limits.constraint_lower)[lower_finite],
                               (limits.constraint_upper - values)[upper_finite]])

    def constraint_jacobian(x: np.ndarray) -> np.ndarray:
        _, jacobian = nlp.constraints_and_jacobian(np.asarray(x, dtype=float), parameters)
        jacobian = np.asarray(jacobian, dtype=float)
        return np.vstack([jacobian[lower_finite], -jacobian[upper_finite]])

    return SetProblem(
        lower=limits.lower, upper=limits.upper,
        variables=(*(f"P{joint} {axis}" for joint in range(1, joints + 1) for axis in "xyz"),
                   *(f"delta_{shaft}" for shaft in range(1, shafts + 1))),
        units=("mm",) * (3 * joints) + ("deg",) * shafts,
        scale=np.concatenate([np.full(3 * joints, MM_PER_UNIT), np.full(shafts, 180.0 / math.pi)]),
        in_margin=np.arange(3 * joints + shafts) < 3 * joints,
        margin_step=1.0 / MM_PER_UNIT, margin_unit="mm", margin_criterion=JOINT_SET_CRITERION,
        solver=BOX_SOLVER,
        constraints=({"type": "ineq", "fun": constraint_values, "jac": constraint_jacobian},),
        period=np.concatenate([np.zeros(3 * joints), np.full(shafts, math.pi)]))


def _nlp_units(x: Sequence[float], joints: int) -> np.ndarray:
    """The user's vector (mm, deg) in the NLP's units (m, rad)."""
    values = np.asarray(x, dtype=float)
    converted: np.ndarray = np.concatenate([values[:3 * joints] / MM_PER_UNIT,
                                            np.radians(values[3 * joints:])])
    return converted


def _user_units(x: np.ndarray, joints: int) -> tuple[float, ...]:
    """NLP vector (m, rad) as the user's (mm, deg)."""
    values = np.asarray(x, dtype=float)
    return tuple(float(v) for v in np.concatenate([values[:3 * joints] * MM_PER_UNIT,
                                                   np.degrees(values[3 * joints:])]))


def _residual_error(geometry: ColumnGeometry, yoke_phase_deg: Sequence[float]) -> float:
    return float(residual_error(np.radians(geometry.beta_deg),
                                np.radians(geometry.phase_deg_from_yoke(yoke_phase_deg))))


def _validated_boxes(joint_boxes_mm: Any, geometry: ColumnGeometry
                     ) -> tuple[tuple[tuple[float, ...], tuple[float, ...]], ...]:
    joints = geometry.joint_count
    try:
        boxes = [list(box) for box in joint_boxes_mm]
    except TypeError:
        raise ValueError(f"joint_boxes_mm = {joint_boxes_mm!r} must be one [[x, y, z] lower, "
                         f"[x, y, z] upper] box per joint ({joints})") from None
    if len(boxes) != joints:
        raise ValueError(f"joint_boxes_mm has {len(boxes)} boxes; the column has {joints} joints")
    checked = []
    for joint, box in enumerate(boxes, start=1):
        label = f"joint_boxes_mm[{joint - 1}]"
        if len(box) != 2:
            raise ValueError(f"{label} = {box!r} must be [[x, y, z] lower, [x, y, z] upper] in mm")
        corners = []
        for side, corner in zip(("lower", "upper"), box, strict=True):
            values = as_float_tuple(f"{label} {side}", corner)
            if len(values) != 3:
                raise ValueError(f"{label} {side} = {list(values)} must have 3 coordinates in mm")
            corners.append(tuple(finite_float(f"{label} {side}", value) for value in values))
        low, high = corners
        for axis in range(3):
            if low[axis] > high[axis]:
                raise ValueError(f"{label}: lower {'xyz'[axis]} = {low[axis]:g} mm exceeds upper "
                                 f"{high[axis]:g} mm")
            given = geometry.points_mm[joint][axis]
            if not low[axis] <= given <= high[axis]:
                raise ValueError(f"points_mm[{joint}] {'xyz'[axis]} = {given:g} mm lies outside "
                                 f"{label} [{low[axis]:g}, {high[axis]:g}] mm")
        checked.append((low, high))
    return tuple(checked)


def _validated_lengths(shaft_length_bounds_mm: Any, geometry: ColumnGeometry
                       ) -> tuple[tuple[float, float], ...]:
    shafts = geometry.joint_count + 1
    if shaft_length_bounds_mm is None:
        return tuple((DEFAULT_SHORTEST_SHAFT_FRACTION * length, math.inf)
                     for length in geometry.shaft_length_mm)
    bounds = per_item_bounds("shaft_length_bounds_mm", shaft_length_bounds_mm, shafts, 0.0,
                             math.inf, "mm")
    for index, (lower, _) in enumerate(bounds):
        if lower <= 0.0:
            raise ValueError(f"shaft_length_bounds_mm[{index}] lower = {lower:g} is outside the "
                             "allowed range (0, inf) mm: a shaft of zero length has no direction")
    return bounds
