"""The most robust of many exact optima.

Where the least residual error is round-off zero, the exact optima of an exact-model
shaft series usually form a set (more design variables than the two residuals they
must cancel): every point of it has RE = 0, and :func:`sso.optimise` would otherwise
return whichever point a solver reached. Within that set this module chooses by a
stated secondary criterion:

* by default, the **largest margin to the bounds**: the design whose free variable
  nearest to one of its bounds is furthest from it (deg), i.e. ``max t`` subject to
  ``RE = 0`` and ``lower + t <= x <= upper - t``;
* with manufacturing tolerances, the **lowest p95 RE**: the candidates are the
  designs of the set that minimise the first-order expected RE under the tolerances
  (``sum_j sigma_j^2 |d r / d angle_j|^2``, every operating angle and phase perturbed,
  as :func:`sso.tolerance_study` does), and the choice among them is by the p95 of a
  Monte Carlo study drawn exactly as :func:`sso.tolerance_study` draws it (same
  distribution, samples and seed).

Both are solved by SciPy's SLSQP with the residuals as equality constraints, from
every distinct exact optimum the solvers found; an answer is kept only when it is
back at round-off zero (a few minimum-norm Gauss-Newton steps put it there) and does
not worsen the criterion. The set's extent per free variable is the least and the
largest value SLSQP reaches for that variable along the set from the chosen design.
Each end is an exact optimum, but SLSQP can stop at a corner of the set inside the
bounds, so an end short of its bound is a lower estimate of the set's full extent,
not a proof that the set ends there.
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np

from sso._display import Part, Readable, TextTable, format_number
from sso._kinematics.hooke_matrix import residual_error as closed_form_residual_error
from sso._kinematics.hooke_matrix import residuals_and_jacobian_numpy
from sso._record import NOT_SAVED, register_record
from sso._shafts.options import DesignProblem
from sso._shafts.perturbed import (
    DEFAULT_TOLERANCES,
    DISTRIBUTIONS,
    MAX_SAMPLES,
    draw_samples,
    per_item_tolerances,
)
from sso._shafts.series import checked_series
from sso._solvers.saddle import ZERO_OBJECTIVE
from sso._solvers.starts import start_points
from sso._validation import check_choice, validate_count

MARGIN_CRITERION = "largest margin to the bounds"
P95_CRITERION = "lowest p95 RE under the given tolerances"
MARGIN_RESOLUTION_DEG = 0.1
"""Bracket (deg) at which the bisection for the largest margin stops."""
MARGIN_MAX_ITERATIONS = 50
"""Iterations of each feasibility solve of the bisection (it converges in a few where the
margin is feasible; where it is not, it would creep towards a nonzero minimum)."""
SPREAD_STARTS = 8
"""Starts (the middle of the bounds, then space-filling points) from which exact optima
are sought for the p95 criterion, besides those found."""
SLSQP_FTOL = 1e-12
SLSQP_MAX_ITERATIONS = 200
PROJECTION_STEPS = 8
# Two exact optima closer than this (rad, largest difference) are one start.
SAME_DESIGN_RAD = 1e-6
ON_BOUND_RAD = 1e-9
RANK_TOLERANCE = 1e-9
EXTENT_START_DECIMALS = 9
"""Decimals (rad) of the chosen design the extent's solves start from (see _extent)."""

Residuals = Callable[[list[float]], tuple[complex, list[complex]]]
BoxSolve = Callable[[list[float], list[float], list[float], int],
                    tuple[list[float], float, int, int]]
"""``(start, lower, upper, max_iterations) -> (x, RE, iterations, evaluations)``: the
least-squares solver in a box (rad; lists of floats in and out)."""


@register_record
@dataclass(frozen=True)
class ToleranceSettings:
    """Manufacturing tolerances of a robust choice, as :func:`sso.tolerance_study` takes them.

    Attributes
    ----------
    beta_tolerance_deg, phase_tolerance_deg : tuple of float
        Standard deviation (normal) or half-width (uniform), deg, per joint / phase.
    distribution : {"normal", "uniform"}
    samples : int
        Monte Carlo samples of the p95.
    seed : int
        Seed of the samples.
    """

    beta_tolerance_deg: tuple[float, ...]
    phase_tolerance_deg: tuple[float, ...]
    distribution: str
    samples: int
    seed: int

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary of every field."""
        return {"beta_tolerance_deg": list(self.beta_tolerance_deg),
                "phase_tolerance_deg": list(self.phase_tolerance_deg),
                "distribution": self.distribution, "samples": self.samples, "seed": self.seed}


def tolerance_settings(joints: int, beta_tolerance_deg: Any, phase_tolerance_deg: Any,
                       distribution: Any, samples: Any, seed: Any) -> ToleranceSettings | None:
    """The tolerances given to :func:`sso.optimise`, checked; None when none is given.

    Missing settings take :func:`sso.tolerance_study`'s defaults (0.5 deg, 1 deg,
    normal, 10,000 samples).

    Raises
    ------
    ValueError
        Naming the field and its allowed range.
    """
    if (beta_tolerance_deg is None and phase_tolerance_deg is None and distribution is None
            and samples is None):
        return None
    given = {"beta_tolerance_deg": beta_tolerance_deg, "phase_tolerance_deg": phase_tolerance_deg,
             "distribution": distribution, "samples": samples}
    settings = {**DEFAULT_TOLERANCES,
                **{name: value for name, value in given.items() if value is not None}}
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed = {seed!r} must be a whole number >= 0")
    return ToleranceSettings(
        beta_tolerance_deg=per_item_tolerances("beta_tolerance_deg",
                                               settings["beta_tolerance_deg"], joints),
        phase_tolerance_deg=per_item_tolerances("phase_tolerance_deg",
                                                settings["phase_tolerance_deg"], joints - 1),
        distribution=check_choice("distribution", settings["distribution"], DISTRIBUTIONS),
        samples=validate_count("samples", settings["samples"], 1, MAX_SAMPLES),
        seed=int(seed))


@register_record
@dataclass(frozen=True, repr=False)
class ExactOptimumSet(Readable):
    """The set of exact optima (RE at round-off zero) and the design chosen within it.

    Attributes
    ----------
    criterion : str
        :data:`MARGIN_CRITERION` or :data:`P95_CRITERION`.
    variables : tuple of str
        Names of the free design variables (``"beta_1"``, ``"phase_1"``, ...).
    dimension : int
        Dimension of the set at the chosen design, bounds aside: the free variables
        that the bounds do not pin, less the rank of the residuals' Jacobian over them
        (0: isolated exact optima, where the choice is among those found).
    starts : int
        Distinct exact optima the choice started from.
    chosen_deg, first_deg : tuple of float
        The chosen design and the exact optimum first found (the lowest RE of the
        solvers and the screen), free variables, deg.
    margin_deg, first_margin_deg : float
        Least distance of a free variable to its bounds, deg, at each.
    tolerances : ToleranceSettings or None
        The tolerances of the p95 criterion.
    p95_residual_error, first_p95_residual_error : float or None
        p95 RE of each under ``tolerances`` (None without).
    time_s : float
        Wall time of the choice, s.
    extent_of : callable or None
        Computes :attr:`extent_deg` (on first access: 2 solves per variable). Not
        saved: a reloaded set holds its saved ``extent_deg`` and no callable.
    """

    criterion: str
    variables: tuple[str, ...]
    dimension: int
    starts: int
    chosen_deg: tuple[float, ...]
    first_deg: tuple[float, ...]
    margin_deg: float
    first_margin_deg: float
    tolerances: ToleranceSettings | None
    p95_residual_error: float | None
    first_p95_residual_error: float | None
    time_s: float
    extent_of: Callable[[], tuple[tuple[float, float], ...]] | None = field(
        default=None, compare=False, metadata=NOT_SAVED)

    _record_derived: ClassVar[tuple[str, ...]] = ("extent_deg",)

    @functools.cached_property
    def extent_deg(self) -> tuple[tuple[float, float], ...]:
        """Least and largest value of each free variable on the set (the part connected
        to the chosen design), deg; found on first access.

        Raises
        ------
        ValueError
            If the set holds neither its extent nor ``extent_of`` to compute it.
        """
        if self.extent_of is None:
            raise ValueError("this set of exact optima holds no extent and no way to find it")
        return self.extent_of()

    def _repr_text(self) -> str:
        figure = (f"p95 RE {format_number(self.p95_residual_error, 4)}"
                  if self.p95_residual_error is not None
                  else f"margin {format_number(self.margin_deg, 4)} deg")
        return f"{self.criterion}: {figure}, set of dimension {self.dimension}"

    def _summary_parts(self) -> list[Part]:
        rows = tuple((name, format_number(low), format_number(high), format_number(chosen))
                     for name, (low, high), chosen in zip(self.variables, self.extent_deg,
                                                          self.chosen_deg, strict=True))
        lines: list[Part] = [
            f"exact optima (RE at round-off zero): a set of dimension {self.dimension}; chosen "
            f"by {self.criterion} from {self.starts} exact optimum(s) found",
            f"margin to the bounds: {format_number(self.margin_deg)} deg (first found "
            f"{format_number(self.first_margin_deg)} deg)"]
        if self.p95_residual_error is not None and self.first_p95_residual_error is not None:
            lines.append(f"p95 RE under the tolerances: {format_number(self.p95_residual_error)}"
                         f" (first found {format_number(self.first_p95_residual_error)})")
        return [*lines, TextTable(("variable", "set from (deg)", "set to (deg)", "chosen (deg)"),
                                  rows)]

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary of every field."""
        return {
            "criterion": self.criterion,
            "variables": list(self.variables),
            "dimension": self.dimension,
            "starts": self.starts,
            "chosen_deg": list(self.chosen_deg),
            "first_deg": list(self.first_deg),
            "margin_deg": self.margin_deg,
            "first_margin_deg": self.first_margin_deg,
            "tolerances": None if self.tolerances is None else self.tolerances.to_dict(),
            "p95_residual_error": self.p95_residual_error,
            "first_p95_residual_error": self.first_p95_residual_error,
            "extent_deg": [list(pair) for pair in self.extent_deg],
            "time_s": self.time_s,
        }


@dataclass(frozen=True)
class Choice:
    """What :func:`choose_exact_optimum` returns: the design (rad) and the set's record."""

    x_rad: np.ndarray
    exact_set: ExactOptimumSet
    solver: str | None
    """Who found the chosen design (``"lm"`` by the margin's bisection, ``"slsqp"`` by
    the least spread); None when it is the exact optimum first found."""
    nit: int
    nfev: int
    message: str


def choose_exact_optimum(problem: DesignProblem, residuals: Residuals, solve_in_box: BoxSolve,
                         exact_points: Sequence[np.ndarray],
                         tolerances: ToleranceSettings | None) -> Choice:
    """The most robust design of the set of exact optima, by the stated criterion.

    Parameters
    ----------
    problem : DesignProblem
        The exact-model problem (its bounds and fixed angles).
    residuals : callable
        ``x_rad (list) -> (rho, jacobian)``, the problem's two residuals as one complex
        number and one complex derivative per free variable.
    solve_in_box : callable
        ``(start, lower, upper, max_iterations) -> (x, RE, iterations, evaluations)``,
        the least-squares solver ``"lm"`` within other bounds (rad).
    exact_points : sequence of numpy.ndarray
        Exact optima found (rad, free variables), the first being the reported one.
    tolerances : ToleranceSettings, optional
        With them the criterion is the lowest p95 RE; without, the largest margin.
    """
    started = time.perf_counter()
    lower, upper = problem.lower_rad, problem.upper_rad
    starts = _distinct(exact_points)
    first = starts[0]
    counts = [0, 0]
    # (design, who found it): None for the exact optimum first found
    candidates: list[tuple[np.ndarray, str | None]] = [(first, None)]
    widest = max(starts, key=lambda point: _margin_deg(point, lower, upper))
    candidates.append((_largest_margin(solve_in_box, widest, lower, upper, counts), "lm"))
    if tolerances is not None:
        # from the exact optima found, the set's point of largest margin and the exact
        # optima the least-squares solver reaches from the middle of the bounds and from
        # space-filling starts (the set has branches no single start reaches)
        spread_starts = start_points(0.5 * (lower + upper), lower, upper, SPREAD_STARTS,
                                     tolerances.seed)
        for start in spread_starts:
            reached, fun, nit, nfev = solve_in_box(start.tolist(), lower.tolist(),
                                                   upper.tolist(), MARGIN_MAX_ITERATIONS)
            counts[0] += nit
            counts[1] += nfev
            if is_exact(fun):
                candidates.append((np.array(reached, dtype=float), "lm"))
        for start in _distinct([point for point, _ in candidates]):
            candidates.append((_least_spread(problem, residuals, start, tolerances, counts),
                               "slsqp"))
    exact = [(point, origin) for point, origin in
             ((_project(residuals, point, lower, upper), origin) for point, origin in candidates)
             if point is not None]
    if tolerances is None:
        chosen, solver = max(exact, key=lambda pair: _margin_deg(pair[0], lower, upper))
        p95 = first_p95 = None
    else:
        spreads = [_p95(problem, point, tolerances) for point, _ in exact]
        index = min(range(len(exact)), key=spreads.__getitem__)
        (chosen, solver), p95 = exact[index], spreads[index]
        first_p95 = _p95(problem, first, tolerances)
    exact_set = ExactOptimumSet(
        criterion=MARGIN_CRITERION if tolerances is None else P95_CRITERION,
        variables=_variable_names(problem),
        dimension=_dimension(residuals, chosen, lower, upper),
        starts=len(starts),
        chosen_deg=tuple(np.degrees(chosen).tolist()),
        first_deg=tuple(np.degrees(first).tolist()),
        margin_deg=_margin_deg(chosen, lower, upper),
        first_margin_deg=_margin_deg(first, lower, upper),
        tolerances=tolerances,
        p95_residual_error=p95,
        first_p95_residual_error=first_p95,
        time_s=time.perf_counter() - started,
        extent_of=functools.partial(_extent, residuals, chosen, lower, upper),
    )
    if solver is not None and float(np.max(np.abs(chosen - first))) <= SAME_DESIGN_RAD:
        solver = None
    message = (f"most robust exact optimum ({exact_set.criterion}) of a set of dimension "
               f"{exact_set.dimension}")
    return Choice(chosen, exact_set, solver, counts[0], counts[1], message)


def is_exact(fun: float) -> bool:
    """True when a residual error is round-off zero (a global minimum of RE >= 0)."""
    return math.isfinite(fun) and fun <= ZERO_OBJECTIVE


def _distinct(points: Sequence[np.ndarray]) -> list[np.ndarray]:
    kept: list[np.ndarray] = []
    kept_lists: list[list[float]] = []
    for point in points:
        point = np.asarray(point, dtype=float)
        values = point.tolist()
        if all(max(abs(value - previous) for value, previous in zip(values, other, strict=True))
               > SAME_DESIGN_RAD for other in kept_lists):
            kept.append(point)
            kept_lists.append(values)
    return kept


def _margin_deg(x_rad: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> float:
    """Least distance of a free variable (one that its bounds do not pin) to a bound, deg."""
    low, high = lower.tolist(), upper.tolist()
    if not any(top > bottom for bottom, top in zip(low, high, strict=True)):
        return 0.0
    return math.degrees(_margin_rad(np.asarray(x_rad, dtype=float).tolist(), low, high))


def _constraint(residuals: Residuals, extra: int) -> dict[str, Any]:
    """The two residuals as SLSQP equality constraints of ``y = (x, extra values)``."""
    size = -extra if extra else None

    def value(y: np.ndarray) -> np.ndarray:
        rho, _ = residuals(y[:size].tolist())
        return np.array([rho.real, rho.imag])

    def jacobian(y: np.ndarray) -> np.ndarray:
        _, derivative = residuals(y[:size].tolist())
        rows = np.array([[entry.real for entry in derivative],
                         [entry.imag for entry in derivative]])
        return np.hstack([rows, np.zeros((2, extra))]) if extra else rows

    return {"type": "eq", "fun": value, "jac": jacobian}


def _slsqp(objective: Callable[[np.ndarray], float], gradient: Any, start: np.ndarray,
           bounds: list[tuple[float | None, float | None]], constraints: list[dict[str, Any]],
           counts: list[int]) -> np.ndarray:
    from scipy.optimize import minimize

    answer = minimize(objective, start, jac=gradient, method="SLSQP", bounds=bounds,
                      constraints=constraints,
                      options={"ftol": SLSQP_FTOL, "maxiter": SLSQP_MAX_ITERATIONS})
    counts[0] += int(answer.nit)
    counts[1] += int(answer.nfev)
    solution: np.ndarray = np.asarray(answer.x, dtype=float)
    return solution


def _largest_margin(solve_in_box: BoxSolve, start: np.ndarray, lower: np.ndarray,
                    upper: np.ndarray, counts: list[int]) -> np.ndarray:
    """The exact optimum of largest margin to the bounds that bisection finds.

    A margin ``t`` is feasible when the least-squares solver, started from the best
    design so far moved into the bounds shrunk by ``t``, reaches round-off zero inside
    them within :data:`MARGIN_MAX_ITERATIONS`; ``t`` is bisected between the start's
    margin and half the narrowest free bound until the bracket is under
    :data:`MARGIN_RESOLUTION_DEG`. Plain floats: the vectors are short and the loop
    runs a handful of times per call, where each numpy call costs more than its
    arithmetic.
    """
    low_bounds, high_bounds = lower.tolist(), upper.tolist()
    free = [high > low for low, high in zip(low_bounds, high_bounds, strict=True)]
    if not any(free):
        return start
    best = start.tolist()
    low = math.radians(_margin_deg(start, lower, upper))
    high = 0.5 * min(top - bottom for top, bottom, moves
                     in zip(high_bounds, low_bounds, free, strict=True) if moves)
    while high - low > math.radians(MARGIN_RESOLUTION_DEG):
        margin = 0.5 * (low + high)
        shrunk_lower = [bottom + margin if moves else bottom
                        for bottom, moves in zip(low_bounds, free, strict=True)]
        shrunk_upper = [top - margin if moves else top
                        for top, moves in zip(high_bounds, free, strict=True)]
        moved = [min(max(value, bottom), top) for value, bottom, top
                 in zip(best, shrunk_lower, shrunk_upper, strict=True)]
        x, fun, nit, nfev = solve_in_box(moved, shrunk_lower, shrunk_upper,
                                         MARGIN_MAX_ITERATIONS)
        counts[0] += nit
        counts[1] += nfev
        if is_exact(fun):
            best, low = x, max(margin, math.radians(math.degrees(
                _margin_rad(x, low_bounds, high_bounds))))
        else:
            high = margin
    return np.array(best, dtype=float)


def _margin_rad(x_rad: list[float], lower: list[float], upper: list[float]) -> float:
    """:func:`_margin_deg` in rad, on lists of floats (at least one variable free)."""
    return min(min(value - bottom, top - value) for value, bottom, top
               in zip(x_rad, lower, upper, strict=True) if top > bottom)


def _sigma_rad(tolerances: ToleranceSettings) -> np.ndarray:
    """Standard deviation of every angle (every beta, then every phase), rad."""
    spread: np.ndarray = np.radians(np.array([*tolerances.beta_tolerance_deg,
                                  *tolerances.phase_tolerance_deg], dtype=float))
    return spread if tolerances.distribution == "normal" else spread / math.sqrt(3.0)


def _full_angles(problem: DesignProblem, x_rad: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    beta, phase = problem.split(list(x_rad), problem.parameters_rad.tolist())
    return np.asarray(beta, dtype=float), np.asarray(phase, dtype=float)


def _least_spread(problem: DesignProblem, residuals: Residuals, start: np.ndarray,
                  tolerances: ToleranceSettings, counts: list[int]) -> np.ndarray:
    """The exact optimum of least first-order expected RE under the tolerances."""
    sigma = _sigma_rad(tolerances)

    def expected(x: np.ndarray) -> float:
        _, jacobian = residuals_and_jacobian_numpy(*_full_angles(problem, x))
        return float(np.sum((jacobian * sigma) ** 2))

    bounds = list(zip(problem.lower_rad.tolist(), problem.upper_rad.tolist(), strict=True))
    return _slsqp(expected, None, start, bounds, [_constraint(residuals, 0)], counts)


@functools.lru_cache(maxsize=8)
def _offsets(joints: int, tolerances: ToleranceSettings) -> tuple[np.ndarray, np.ndarray]:
    """The tolerance study's draws about a design of zeros (deg), cached per setting."""
    zero = checked_series((0.0,) * joints, (0.0,) * (joints - 1), "exact")
    return draw_samples(zero, tolerances.beta_tolerance_deg, tolerances.phase_tolerance_deg,
                        tolerances.distribution, tolerances.samples, tolerances.seed)


def _p95(problem: DesignProblem, x_rad: np.ndarray, tolerances: ToleranceSettings) -> float:
    """p95 RE of the design under the tolerances, drawn as :func:`sso.tolerance_study` does."""
    beta, phase = _full_angles(problem, x_rad)
    beta_offsets, phase_offsets = _offsets(problem.n_joints, tolerances)
    beta_deg = np.abs(np.degrees(beta) + beta_offsets)
    phase_deg = np.degrees(phase) + phase_offsets
    values = closed_form_residual_error(np, list(np.radians(beta_deg).T),
                                        list(np.radians(phase_deg).T))
    return float(np.percentile(values, 95.0))


def _project(residuals: Residuals, x_rad: np.ndarray, lower: np.ndarray,
             upper: np.ndarray) -> np.ndarray | None:
    """The point back at round-off zero by minimum-norm Gauss-Newton steps inside the
    bounds, or None when it does not get there."""
    x: np.ndarray = np.clip(np.asarray(x_rad, dtype=float), lower, upper)
    for _ in range(PROJECTION_STEPS):
        rho, derivative = residuals(x.tolist())
        if abs(rho) ** 2 <= ZERO_OBJECTIVE:
            return x
        free = (upper > lower) & (x > lower + ON_BOUND_RAD) & (x < upper - ON_BOUND_RAD)
        jacobian = np.array([[entry.real for entry in derivative],
                             [entry.imag for entry in derivative]]) * free
        step, *_ = np.linalg.lstsq(jacobian, -np.array([rho.real, rho.imag]), rcond=None)
        x = np.clip(x + step, lower, upper)
    rho, _ = residuals(x.tolist())
    return x if abs(rho) ** 2 <= ZERO_OBJECTIVE else None


def _dimension(residuals: Residuals, x_rad: np.ndarray, lower: np.ndarray,
               upper: np.ndarray) -> int:
    moving = [top > bottom for bottom, top in zip(lower.tolist(), upper.tolist(), strict=True)]
    _, derivative = residuals(x_rad.tolist())
    columns = [entry for entry, moves in zip(derivative, moving, strict=True) if moves]
    return len(columns) - _rank_of_two_rows(columns)


def _rank_of_two_rows(columns: list[complex]) -> int:
    """Rank of the real 2-row matrix ``[Re; Im]`` of ``columns``: its singular values
    above :data:`RANK_TOLERANCE` times the largest.

    Closed form (no numpy call for a 2 by n matrix): the largest singular value from
    the rows' Gram matrix, the smallest as the rows' wedge product over it (Lagrange's
    identity, a sum of squares: accurate however small it is), on the columns scaled
    by their largest entry.
    """
    scale = max((max(abs(entry.real), abs(entry.imag)) for entry in columns), default=0.0)
    if not 0.0 < scale < math.inf:
        return 0 if scale == 0.0 else 2
    columns = [entry / scale for entry in columns]
    first = math.fsum(entry.real * entry.real for entry in columns)
    second = math.fsum(entry.imag * entry.imag for entry in columns)
    cross = math.fsum(entry.real * entry.imag for entry in columns)
    largest = math.sqrt(0.5 * (first + second + math.hypot(first - second, 2.0 * cross)))
    if largest == 0.0:
        return 0
    wedge = math.sqrt(math.fsum((one.real * other.imag - other.real * one.imag) ** 2
                                for index, one in enumerate(columns)
                                for other in columns[index + 1:]))
    floor = RANK_TOLERANCE * largest
    return int(largest > floor) + int(wedge / largest > floor)


def _extent(residuals: Residuals, x_rad: np.ndarray, lower: np.ndarray,
            upper: np.ndarray) -> tuple[tuple[float, float], ...]:
    """Least and largest value of each variable on the set, from ``x_rad`` (deg).

    SLSQP starts from ``x_rad`` rounded to :data:`EXTENT_START_DECIMALS` decimals (rad)
    and put back on the set: SLSQP can stop at a corner of the set inside the bounds,
    and which corner must not depend on the round-off the chosen design carries (the
    README example's beta_1 ended at 40 or at 38.93 deg with 1e-14 rad of difference
    in the design, which differs between solver paths and processes).
    """
    counts = [0, 0]
    bounds = list(zip(lower.tolist(), upper.tolist(), strict=True))
    constraint = [_constraint(residuals, 0)]
    start = _project(residuals, np.round(x_rad, EXTENT_START_DECIMALS), lower, upper)
    start = x_rad if start is None else start
    extent = []
    for index in range(len(x_rad)):
        ends = []
        for sign in (1.0, -1.0):
            if upper[index] <= lower[index]:
                ends.append(float(x_rad[index]))
                continue
            goal = np.zeros(len(x_rad))
            goal[index] = sign
            answer = _slsqp(functools.partial(_linear, goal), functools.partial(_constant, goal),
                            start, bounds, constraint, counts)
            projected = _project(residuals, answer, lower, upper)
            end = float(x_rad[index] if projected is None else projected[index])
            ends.append(_on_bound(end, float(lower[index]), float(upper[index])))
        low, high = min(ends[0], float(x_rad[index])), max(ends[1], float(x_rad[index]))
        extent.append((math.degrees(low), math.degrees(high)))
    return tuple(extent)


def _on_bound(value_rad: float, lower_rad: float, upper_rad: float) -> float:
    """``value_rad``, or the bound it lies within :data:`ON_BOUND_RAD` of: an end the
    solver stops a round-off step short of its bound is that bound."""
    for bound in (lower_rad, upper_rad):
        if abs(value_rad - bound) <= ON_BOUND_RAD:
            return bound
    return value_rad


def _linear(goal: np.ndarray, x: np.ndarray) -> float:
    return float(goal @ x)


def _constant(goal: np.ndarray, x: np.ndarray) -> np.ndarray:
    return goal


def _variable_names(problem: DesignProblem) -> tuple[str, ...]:
    names = []
    if problem.beta_free:
        names += [f"beta_{joint + 1}" for joint in range(problem.n_joints)]
    if problem.phase_free:
        names += [f"phase_{joint + 1}" for joint in range(problem.n_joints - 1)]
    return tuple(names)
