"""The most robust of many exact optima.

Where the least residual error is round-off zero, the exact optima of an exact-model
shaft series usually form a set (more design variables than the two residuals they
must cancel): every point of it has RE = 0, and :func:`sso.optimise` would otherwise
return whichever point a solver reached. So do a column's yoke phasings and its joint
centres moved within their boxes. Within that set this module chooses by a stated
secondary criterion:

* by default, the **largest margin to the bounds**: the design whose free variable
  nearest to one of its bounds is furthest from it (deg; mm for joint centres), i.e.
  ``max t`` subject to ``RE = 0`` and ``lower + t <= x <= upper - t``;
* with manufacturing tolerances, the **lowest p95 RE**: the candidates are the
  designs of the set that minimise a smooth measure of the expected RE under the
  tolerances, and the choice among them is by the p95 of a Monte Carlo study. The
  tolerances are a :class:`SpreadMeasure`: a shaft series' (:class:`ToleranceSettings`:
  the first-order expected RE ``sum_j sigma_j^2 |d r / d angle_j|^2``, every operating
  angle and phase perturbed, and the p95 drawn exactly as :func:`sso.tolerance_study`
  draws it, same distribution, samples and seed) or a steering column's (hardpoint and
  yoke-phasing errors, :mod:`sso._column.tolerances`).

Both are solved by SciPy's SLSQP with the residuals as equality constraints (and the
problem's other constraints, :class:`SetProblem`), from every distinct exact optimum
the solvers found; an answer is kept only when it is back at round-off zero (a few
minimum-norm Gauss-Newton steps put it there), within every constraint, and does not
worsen the criterion.

The set's extent per free variable is the least and the largest value of that variable
over the WHOLE set within the bounds, as a bounded search finds it (:func:`set_extent`):
for each variable and each side, the variable is pinned at its bound and the problem's
least-squares solver projects onto RE = 0 over the other variables, from the chosen
design and then from :data:`EXTENT_PROBES` seeded random probes of them; the first
that lands is the end's witness (an exact optimum with the variable at the bound, so
that end is exact). Where none lands, the pinned value is bisected
(:data:`EXTENT_HALVINGS` halvings) between the chosen design and the bound, and the end
is the furthest value at which an exact optimum was found: a lower estimate of the
set's extent. A variable whose bounds span two periods or more (a column's model
phases, period 180 deg) has no bound the set could end on: its extent is sought modulo
the period about the chosen value, walking a grid of :data:`EXTENT_GRID` values per
period outward and bisecting at the first value where no exact optimum is found; every
such end is a lower estimate. Each end carries its witness.
"""

from __future__ import annotations

import functools
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar, Protocol, runtime_checkable

import numpy as np

from sso._display import Part, Readable, TextTable, format_number
from sso._kinematics.hooke_matrix import residual_error as closed_form_residual_error
from sso._kinematics.hooke_matrix import residuals_and_jacobian_numpy
from sso._limits import DEFAULT_SHAFT_SOLVER_TOL
from sso._record import NOT_SAVED, encode, register_record
from sso._shafts.options import DesignProblem
from sso._shafts.perturbed import (
    DEFAULT_TOLERANCES,
    DISTRIBUTIONS,
    MAX_SAMPLES,
    draw_samples,
    per_item_tolerances,
)
from sso._shafts.series import checked_series
from sso._solvers.lm import minimise
from sso._solvers.multistart import MeasuredRun, measure_run
from sso._solvers.run import RunLimits, RunOutcome
from sso._solvers.saddle import ZERO_OBJECTIVE
from sso._solvers.starts import start_points
from sso._validation import check_choice, validate_count

MARGIN_CRITERION = "largest margin to the bounds"
P95_CRITERION = "lowest p95 RE under the given tolerances"
EXTENT_ENDS = ("bound: an exact optimum lies on the bound, the end is exact; reached: the "
               "furthest value found, a lower estimate")
EXTENT_METHOD = ("each variable pinned at each bound and projected onto RE = 0 from the "
                 "chosen design and seeded random probes, else bisected towards the chosen "
                 f"design; {EXTENT_ENDS}")
MARGIN_RESOLUTION = 0.1
"""Bracket (in the margin's unit: deg, mm) at which the bisection for the largest margin
stops."""
CONSTRAINT_SLACK = 1e-12
"""A design violating a constraint of :class:`SetProblem` by more than this (its units)
is no candidate."""
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
EXTENT_PROBES = 32
"""Seeded random probes of the other variables from which an end is sought at a bound."""
EXTENT_HALVINGS = 12
"""Halvings of the pinned value's bracket where no probe lands at the bound."""
EXTENT_GRID = 36
"""Values per period at which a periodic variable's extent is walked (5 deg for 180)."""
EXTENT_SEED = 0
"""Seed of the probes (one draw per search: the extent is the same in every process)."""
EXTENT_MAX_ITERATIONS = MARGIN_MAX_ITERATIONS
"""Iterations of each least-squares solve of the extent's search."""
EXTENT_SOLVER = "lm"
"""The solver of the extent's pinned solves (see :func:`set_extent`)."""
EXTENT_TOLERANCE = DEFAULT_SHAFT_SOLVER_TOL
"""Projected-gradient tolerance of each of those solves (they stop sooner at round-off
zero)."""

Residuals = Callable[[list[float]], tuple[complex, list[complex]]]
BoxSolve = Callable[[list[float], list[float], list[float], int],
                    tuple[list[float], float, int, int]]
"""``(start, lower, upper, max_iterations) -> (x, RE, iterations, evaluations)``: the
least-squares solver in a box (the solver's units; lists of floats in and out)."""


@dataclass(frozen=True)
class SetProblem:
    """What the choice within a set of exact optima needs of a design problem.

    Attributes
    ----------
    lower, upper : numpy.ndarray
        Bounds of the free variables, in the solver's units (rad; m).
    variables : tuple of str
        Their names.
    units : tuple of str
        The unit each is reported in (``"deg"``, ``"mm"``).
    scale : numpy.ndarray
        Reported units per solver unit, per variable.
    in_margin : numpy.ndarray of bool
        The variables whose distance to their bounds is the margin (all reported in
        ``margin_unit``).
    margin_step : float
        One ``margin_unit`` in the solver's units (``pi / 180`` rad; 0.001 m).
    margin_unit : str
    margin_criterion : str
        The margin criterion in the problem's words.
    solver : str
        Who solves the least-squares problems in a box (``solve_in_box``).
    constraints : tuple of dict
        SLSQP inequality constraints (``fun(x) >= 0``, with ``jac``) beyond the bounds.
    design : object
        What a :class:`SpreadMeasure` measures (a shaft series' ``DesignProblem``).
    period : numpy.ndarray, optional
        Period of each variable in the solver's units (0: not periodic; a phase's is
        ``pi``). A variable whose bounds span two periods or more has its extent sought
        modulo its period (see :func:`set_extent`).
    """

    lower: np.ndarray
    upper: np.ndarray
    variables: tuple[str, ...]
    units: tuple[str, ...]
    scale: np.ndarray
    in_margin: np.ndarray
    margin_step: float = math.pi / 180.0
    margin_unit: str = "deg"
    margin_criterion: str = MARGIN_CRITERION
    solver: str = "lm"
    constraints: tuple[dict[str, Any], ...] = ()
    design: Any = None
    period: np.ndarray | None = None

    def margin(self, x: np.ndarray | list[float]) -> float:
        """Least distance of a margin variable (one its bounds do not pin) to a bound, in
        ``margin_unit``."""
        bounds = self._margin_bounds
        if not bounds:
            return 0.0
        values = x.tolist() if isinstance(x, np.ndarray) else x
        return _margin_of(values, bounds) * bounds[0][3]

    @functools.cached_property
    def _margin_bounds(self) -> list[tuple[int, float, float, float]]:
        """``(index, lower, upper, scale)`` of each margin variable its bounds do not pin,
        in plain floats (the bisection runs on lists)."""
        return [(index, bottom, top, scale) for index, (bottom, top, scale, counted)
                in enumerate(zip(self.lower.tolist(), self.upper.tolist(), self.scale.tolist(),
                                 self.in_margin.tolist(), strict=True))
                if counted and top > bottom]

    def feasible(self, x: np.ndarray) -> bool:
        """Whether ``x`` meets every constraint (within :data:`CONSTRAINT_SLACK`)."""
        return all(float(np.min(constraint["fun"](x), initial=0.0)) >= -CONSTRAINT_SLACK
                   for constraint in self.constraints)

    def reported(self, x: np.ndarray) -> tuple[float, ...]:
        """``x`` in the reported units."""
        return tuple((np.asarray(x, dtype=float) * self.scale).tolist())

    def wrapping_period(self, index: int) -> float:
        """The period of variable ``index`` where its bounds span two periods or more
        (the solver's units), else 0: its extent is then sought modulo the period."""
        if self.period is None:
            return 0.0
        period = float(self.period[index])
        span = float(self.upper[index] - self.lower[index])
        return period if period > 0.0 and span >= 2.0 * period * (1.0 - 1e-12) else 0.0


def series_set_problem(problem: DesignProblem) -> SetProblem:
    """The :class:`SetProblem` of a shaft series' design problem (every variable an angle)."""
    names = _variable_names(problem)
    scale, in_margin, period = _series_set_arrays(names)
    return SetProblem(lower=problem.lower_rad, upper=problem.upper_rad, variables=names,
                      units=("deg",) * len(names), scale=scale, in_margin=in_margin,
                      design=problem, period=period)


@functools.lru_cache(maxsize=64)
def _series_set_arrays(names: tuple[str, ...]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The scale (deg per rad), margin flags and periods (rad: a phase's is pi) of a shaft
    series' free variables, read-only and kept per layout (every call of a shape builds
    its set problem)."""
    arrays = (np.full(len(names), 180.0 / math.pi), np.ones(len(names), dtype=bool),
              np.array([math.pi if name.startswith("phase") else 0.0 for name in names]))
    for array in arrays:
        array.flags.writeable = False
    return arrays


@runtime_checkable
class SpreadMeasure(Protocol):
    """Manufacturing tolerances by which a design is chosen within a set of exact optima.

    A registered record (the set saves it as its ``tolerances``) that measures a
    design of a :class:`DesignProblem` (its free variables ``x_rad``, rad).
    """

    @property
    def seed(self) -> int:
        """Seed of the spread starts (and of the measure's own samples)."""

    def p95_residual_error(self, problem: DesignProblem, x_rad: np.ndarray) -> float:
        """p95 RE of the design under the tolerances: the criterion of the choice."""

    def expected_residual_error(self, problem: DesignProblem, x_rad: np.ndarray) -> float:
        """A smooth measure of the RE the tolerances add (minimised on the set)."""

    @property
    def description(self) -> str:
        """The tolerances in words, as a report states them."""

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary of the settings."""


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

    @property
    def description(self) -> str:
        """The tolerances in words, as a report states them."""
        return (f"{self.distribution}, beta {list(self.beta_tolerance_deg)} deg, phase "
                f"{list(self.phase_tolerance_deg)} deg, {self.samples} samples, seed {self.seed}")

    def p95_residual_error(self, problem: DesignProblem, x_rad: np.ndarray) -> float:
        """p95 RE of the design, drawn as :func:`sso.tolerance_study` draws it."""
        beta, phase = _full_angles(problem, x_rad)
        beta_offsets, phase_offsets = _offsets(problem.n_joints, self)
        beta_deg = np.abs(np.degrees(beta) + beta_offsets)
        phase_deg = np.degrees(phase) + phase_offsets
        values = closed_form_residual_error(np, list(np.radians(beta_deg).T),
                                            list(np.radians(phase_deg).T))
        return float(np.percentile(values, 95.0))

    def expected_residual_error(self, problem: DesignProblem, x_rad: np.ndarray) -> float:
        """First-order expected RE: ``sum_j sigma_j^2 |d r / d angle_j|^2``."""
        _, jacobian = residuals_and_jacobian_numpy(*_full_angles(problem, x_rad))
        return float(np.sum((jacobian * self._sigma_rad()) ** 2))

    def _sigma_rad(self) -> np.ndarray:
        """Standard deviation of every angle (every beta, then every phase), rad."""
        spread: np.ndarray = np.radians(np.array([*self.beta_tolerance_deg,
                                                  *self.phase_tolerance_deg], dtype=float))
        return spread if self.distribution == "normal" else spread / math.sqrt(3.0)


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
@dataclass(frozen=True)
class ExtentEnd:
    """One end of the extent of a set of exact optima along one free variable.

    Attributes
    ----------
    value : float
        The end, in the variable's unit.
    at_bound : bool
        True where ``value`` is the variable's bound and the witness lies on it: the set
        reaches the bound, the end is exact. False where ``value`` is the furthest value
        at which the search found an exact optimum: a lower estimate, the set may reach
        further.
    witness : tuple of float
        An exact optimum with the variable at ``value``: every free variable, in the
        set's ``units`` (build it to check it).
    witness_residual_error : float
        RE of the witness, as the least-squares solver left it (round-off zero).
    """

    value: float
    at_bound: bool
    witness: tuple[float, ...]
    witness_residual_error: float


@register_record
@dataclass(frozen=True)
class SetExtent:
    """The extent of a set of exact optima per free variable, as :func:`set_extent` found it.

    Attributes
    ----------
    ends : tuple of (ExtentEnd, ExtentEnd)
        Per free variable, its least and its largest value on the set within the bounds.
    probes : int
        Seeded random probes of the other variables tried at each bound
        (:data:`EXTENT_PROBES`).
    solves : int
        Least-squares solves the search made (at most ``2 * variables *
        (1 + probes + 2 * halvings)`` for bounded variables).
    time_s : float
        Wall time of the search, s.
    """

    ends: tuple[tuple[ExtentEnd, ExtentEnd], ...]
    probes: int
    solves: int
    time_s: float


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
    units : tuple of str
        The unit of each (``"deg"``; ``"mm"`` for a joint centre's coordinate).
    dimension : int
        Dimension of the set at the chosen design, bounds aside: the free variables
        that the bounds do not pin, less the rank of the residuals' Jacobian over them
        (0: isolated exact optima, where the choice is among those found).
    starts : int
        Distinct exact optima the choice started from.
    chosen, first_found : tuple of float
        The chosen design and the exact optimum first found (the lowest RE of the
        solvers and the screen), free variables, in ``units``.
    margin, first_margin : float
        Least distance of a free variable counted in the margin to its bounds, in
        ``margin_unit``, at each.
    margin_unit : str
    tolerances : SpreadMeasure or None
        The tolerances of the p95 criterion: a shaft series' :class:`ToleranceSettings`
        or a column's (``sso._column.tolerances.BuiltColumnSpread``).
    p95_residual_error, first_p95_residual_error : float or None
        p95 RE of each under ``tolerances`` (None without).
    time_s : float
        Wall time of the choice, s.
    extent_of : callable or None
        Computes :attr:`extent_search` (on first access; :func:`set_extent`). Not
        saved: a reloaded set holds its saved ``extent_search`` and no callable.
    """

    criterion: str
    variables: tuple[str, ...]
    units: tuple[str, ...]
    dimension: int
    starts: int
    chosen: tuple[float, ...]
    first_found: tuple[float, ...]
    margin: float
    first_margin: float
    margin_unit: str
    tolerances: SpreadMeasure | None
    p95_residual_error: float | None
    first_p95_residual_error: float | None
    time_s: float
    extent_of: Callable[[], SetExtent] | None = field(
        default=None, compare=False, metadata=NOT_SAVED)

    _record_derived: ClassVar[tuple[str, ...]] = ("extent_search",)

    @functools.cached_property
    def extent_search(self) -> SetExtent:
        """The extent of the whole set within the bounds per free variable, each end with
        its witness and whether it is exact (at a bound) or a lower estimate; found on
        first access (:func:`set_extent`).

        Raises
        ------
        ValueError
            If the set holds neither its extent nor ``extent_of`` to compute it.
        """
        if self.extent_of is None:
            raise ValueError("this set of exact optima holds no extent and no way to find it")
        return self.extent_of()

    @property
    def extent(self) -> tuple[tuple[float, float], ...]:
        """Least and largest value of each free variable on the set, in ``units`` (the
        values of :attr:`extent_search`'s ends)."""
        return tuple((low.value, high.value) for low, high in self.extent_search.ends)

    def _repr_text(self) -> str:
        figure = (f"p95 RE {format_number(self.p95_residual_error, 4)}"
                  if self.p95_residual_error is not None
                  else f"margin {format_number(self.margin, 4)} {self.margin_unit}")
        return f"{self.criterion}: {figure}, set of dimension {self.dimension}"

    def _summary_parts(self) -> list[Part]:
        rows = tuple((name, unit, format_number(low.value), format_number(high.value),
                      format_number(chosen), f"{end_kind(low)} / {end_kind(high)}")
                     for name, unit, (low, high), chosen in zip(
                         self.variables, self.units, self.extent_search.ends, self.chosen,
                         strict=True))
        lines: list[Part] = [
            f"exact optima (RE at round-off zero): a set of dimension {self.dimension}; chosen "
            f"by {self.criterion} from {self.starts} exact optimum(s) found",
            f"margin to the bounds: {format_number(self.margin)} {self.margin_unit} (first "
            f"found {format_number(self.first_margin)} {self.margin_unit})"]
        if self.p95_residual_error is not None and self.first_p95_residual_error is not None:
            lines.append(f"p95 RE under the tolerances: {format_number(self.p95_residual_error)}"
                         f" (first found {format_number(self.first_p95_residual_error)})")
        lines.append(f"extent of the whole set within the bounds ({EXTENT_ENDS})")
        return [*lines, TextTable(("variable", "unit", "set from", "set to", "chosen", "ends"),
                                  rows)]

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary of every field (the extent's search included)."""
        saved: dict[str, Any] = encode(self)
        del saved["type"]
        return saved


def end_kind(end: ExtentEnd) -> str:
    """How an end of the extent was found, in a report's words."""
    return "bound" if end.at_bound else "reached"


@dataclass(frozen=True)
class Choice:
    """What :func:`choose_exact_optimum` returns: the design (the solver's units) and the
    set's record."""

    x: np.ndarray
    exact_set: ExactOptimumSet
    solver: str | None
    """Who found the chosen design (the problem's least-squares solver by the margin's
    bisection, ``"slsqp"`` by the least spread); None when it is the exact optimum first
    found."""
    nit: int
    nfev: int
    message: str


def choose_exact_optimum(problem: SetProblem, residuals: Residuals, solve_in_box: BoxSolve,
                         exact_points: Sequence[np.ndarray],
                         tolerances: SpreadMeasure | None) -> Choice:
    """The most robust design of the set of exact optima, by the stated criterion.

    Parameters
    ----------
    problem : SetProblem
        The bounds, names, units and constraints of the free variables
        (:func:`series_set_problem` for a shaft series).
    residuals : callable
        ``x (list) -> (rho, jacobian)``, the problem's two residuals as one complex
        number and one complex derivative per free variable.
    solve_in_box : callable
        ``(start, lower, upper, max_iterations) -> (x, RE, iterations, evaluations)``,
        the least-squares solver ``problem.solver`` within other bounds; an answer
        outside the problem's constraints has RE ``inf``.
    exact_points : sequence of numpy.ndarray
        Exact optima found (free variables, the solver's units), the first being the
        reported one.
    tolerances : SpreadMeasure, optional
        With them the criterion is the lowest p95 RE; without, the largest margin.
    """
    started = time.perf_counter()
    lower, upper = problem.lower, problem.upper
    starts = _distinct(exact_points)
    first = starts[0]
    counts = [0, 0]
    # (design, who found it): None for the exact optimum first found
    candidates: list[tuple[np.ndarray, str | None]] = [(first, None)]
    widest = max(starts, key=problem.margin)
    candidates.append((_largest_margin(problem, solve_in_box, widest, counts), problem.solver))
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
                candidates.append((np.array(reached, dtype=float), problem.solver))
        for start in _distinct([point for point, _ in candidates]):
            candidates.append((_least_spread(problem, residuals, start, tolerances, counts),
                               "slsqp"))
    exact = [(point, origin) for point, origin in
             ((_project(residuals, point, lower, upper), origin) for point, origin in candidates)
             if point is not None and problem.feasible(point)]
    if tolerances is None:
        chosen, solver = max(exact, key=lambda pair: problem.margin(pair[0]))
        p95 = first_p95 = None
    else:
        spreads = [tolerances.p95_residual_error(problem.design, point) for point, _ in exact]
        index = min(range(len(exact)), key=spreads.__getitem__)
        (chosen, solver), p95 = exact[index], spreads[index]
        first_p95 = tolerances.p95_residual_error(problem.design, first)
    exact_set = ExactOptimumSet(
        criterion=problem.margin_criterion if tolerances is None else P95_CRITERION,
        variables=problem.variables,
        units=problem.units,
        dimension=_dimension(residuals, chosen, lower, upper),
        starts=len(starts),
        chosen=problem.reported(chosen),
        first_found=problem.reported(first),
        margin=problem.margin(chosen),
        first_margin=problem.margin(first),
        margin_unit=problem.margin_unit,
        tolerances=tolerances,
        p95_residual_error=p95,
        first_p95_residual_error=first_p95,
        time_s=time.perf_counter() - started,
        extent_of=functools.partial(set_extent, problem, residuals, solve_in_box, chosen),
    )
    if solver is not None and max(abs(value - other) for value, other in zip(
            chosen.tolist(), first.tolist(), strict=True)) <= SAME_DESIGN_RAD:
        solver = None
    message = (f"most robust exact optimum ({exact_set.criterion}) of a set of dimension "
               f"{exact_set.dimension}")
    return Choice(chosen, exact_set, solver, counts[0], counts[1], message)


def selection_run(choice: Choice, start_index: int, nlp: Any, parameters: np.ndarray,
                  limits: RunLimits, started: float) -> MeasuredRun:
    """The chosen design as a run of its solver on the problem's graph, measured there (a
    :class:`sso.Solution` of role ``"selection"`` is made of it).

    Parameters
    ----------
    choice : Choice
        A choice that moved the design (``choice.solver`` not None).
    start_index : int
        The start of the exact optimum first found.
    nlp, parameters, limits
        The problem's graph, its parameters and its bounds.
    started : float
        ``time.perf_counter()`` when the choice began.
    """
    assert choice.solver is not None
    outcome = RunOutcome(choice.x, float("nan"), choice.nit, choice.nfev, choice.nfev, 0, True,
                         choice.message, time.perf_counter() - started)
    return measure_run(choice.solver, start_index, outcome, nlp, parameters, limits)


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


def _largest_margin(problem: SetProblem, solve_in_box: BoxSolve, start: np.ndarray,
                    counts: list[int]) -> np.ndarray:
    """The exact optimum of largest margin to the bounds that bisection finds.

    A margin ``t`` is feasible when the least-squares solver, started from the best
    design so far moved into the bounds shrunk by ``t`` (the margin's variables only),
    reaches round-off zero inside them within :data:`MARGIN_MAX_ITERATIONS`; ``t`` is
    bisected, in the solver's units, between the start's margin and half the narrowest
    counted bound until the bracket is under :data:`MARGIN_RESOLUTION`. Plain floats: the
    vectors are short and the loop runs a handful of times per call, where each numpy
    call costs more than its arithmetic.
    """
    bounds = problem._margin_bounds
    if not bounds:
        return start
    low_bounds, high_bounds = problem.lower.tolist(), problem.upper.tolist()
    counted = [False] * len(low_bounds)
    for index, *_ in bounds:
        counted[index] = True
    step = problem.margin_step
    best = start.tolist()
    low = problem.margin(best) * step
    high = 0.5 * min(top - bottom for _, bottom, top, _ in bounds)
    while high - low > MARGIN_RESOLUTION * step:
        margin = 0.5 * (low + high)
        shrunk_lower = [bottom + margin if moves else bottom
                        for bottom, moves in zip(low_bounds, counted, strict=True)]
        shrunk_upper = [top - margin if moves else top
                        for top, moves in zip(high_bounds, counted, strict=True)]
        moved = [bottom if value < bottom else top if value > top else value
                 for value, bottom, top in zip(best, shrunk_lower, shrunk_upper, strict=True)]
        x, fun, nit, nfev = solve_in_box(moved, shrunk_lower, shrunk_upper,
                                         MARGIN_MAX_ITERATIONS)
        counts[0] += nit
        counts[1] += nfev
        if is_exact(fun):
            best, low = x, max(margin, problem.margin(x) * step)
        else:
            high = margin
    return np.array(best, dtype=float)


def _margin_of(x: list[float], bounds: list[tuple[int, float, float, float]]) -> float:
    """Least distance of the ``bounds``' variables of ``x`` to a bound, the solver's units."""
    return min([x[index] - bottom for index, bottom, _, _ in bounds]
               + [top - x[index] for index, _, top, _ in bounds])


def _full_angles(problem: DesignProblem, x_rad: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    beta, phase = problem.split(list(x_rad), problem.parameters_rad.tolist())
    return np.asarray(beta, dtype=float), np.asarray(phase, dtype=float)


def _least_spread(problem: SetProblem, residuals: Residuals, start: np.ndarray,
                  tolerances: SpreadMeasure, counts: list[int]) -> np.ndarray:
    """The exact optimum of least expected RE under the tolerances."""
    bounds = list(zip(problem.lower.tolist(), problem.upper.tolist(), strict=True))
    return _slsqp(functools.partial(tolerances.expected_residual_error, problem.design), None,
                  start, bounds, [_constraint(residuals, 0), *problem.constraints], counts)


@functools.lru_cache(maxsize=8)
def _offsets(joints: int, tolerances: ToleranceSettings) -> tuple[np.ndarray, np.ndarray]:
    """The tolerance study's draws about a design of zeros (deg), cached per setting."""
    zero = checked_series((0.0,) * joints, (0.0,) * (joints - 1), "exact")
    return draw_samples(zero, tolerances.beta_tolerance_deg, tolerances.phase_tolerance_deg,
                        tolerances.distribution, tolerances.samples, tolerances.seed)


def _project(residuals: Residuals, start: np.ndarray, lower: np.ndarray,
             upper: np.ndarray) -> np.ndarray | None:
    """The point back at round-off zero by minimum-norm Gauss-Newton steps inside the
    bounds, or None when it does not get there."""
    x = np.array([bottom if value < bottom else top if value > top else value
                  for value, bottom, top in zip(np.asarray(start, dtype=float).tolist(),
                                                lower.tolist(), upper.tolist(), strict=True)])
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


def _dimension(residuals: Residuals, x: np.ndarray, lower: np.ndarray,
               upper: np.ndarray) -> int:
    moving = [top > bottom for bottom, top in zip(lower.tolist(), upper.tolist(), strict=True)]
    _, derivative = residuals(x.tolist())
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


def set_extent(problem: SetProblem, residuals: Residuals, solve_in_box: BoxSolve,
               chosen: np.ndarray) -> SetExtent:
    """The extent of the whole set of exact optima within the bounds, per free variable.

    For each variable and each side: the variable is pinned at its bound and the others are
    solved for RE = 0 by a bounded Levenberg-Marquardt on the two residuals (see
    ``solve_in_box``) from the chosen design and then from :data:`EXTENT_PROBES` random
    probes within the bounds (seed :data:`EXTENT_SEED`), stopping at the first that lands
    at round-off zero within the problem's constraints: the end is that bound, exactly.
    Where none lands, the pinned value is bisected :data:`EXTENT_HALVINGS` times between
    the chosen value and the bound (each value tried from the furthest witness so far,
    then the chosen design): the end is the furthest value that landed, a lower estimate
    (the set can reach further, from a part of it no probe found). At most
    ``1 + EXTENT_PROBES + 2 * EXTENT_HALVINGS`` solves per variable and side, each of at
    most :data:`EXTENT_MAX_ITERATIONS` iterations; most ends land at their bound within a
    few.

    A variable whose bounds span two periods or more (:meth:`SetProblem.wrapping_period`)
    is taken about its chosen value moved by whole periods to lie at least half a period
    inside the bounds, and walked outward on both sides in steps of a period over
    :data:`EXTENT_GRID` (each step tried as a bisection's value is, then from the
    probes), to the first step that does not land, then bisected: the ends are lower
    estimates of the arc of values about the chosen one (half a period each way where
    every step lands: the set then holds an exact optimum at every step of the period).
    Such a variable is pinned at each value modulo its period within its bounds: its
    witnesses hold the end modulo the period.

    Parameters
    ----------
    problem : SetProblem
    residuals : callable
        The problem's two residuals (as :func:`choose_exact_optimum` takes them).
    solve_in_box : callable
        The problem's least-squares solver in a box, used where it is ``"lm"`` (a shaft
        series': compiled); any other problem's pinned solves run
        :func:`sso._solvers.lm.minimise` on ``residuals`` (a few evaluations where a
        start lands, against some tens for SciPy's trust-region least squares).
    chosen : numpy.ndarray
        The chosen design, an exact optimum (the solver's units).

    Returns
    -------
    SetExtent
        Values and witnesses in the reported units.
    """
    started = time.perf_counter()
    solve = solve_in_box if problem.solver == EXTENT_SOLVER else functools.partial(
        _minimised, residuals)
    search = _ExtentSearch(problem, residuals, solve, np.asarray(chosen, dtype=float))
    ends = []
    for index in range(len(search.chosen)):
        period = problem.wrapping_period(index)
        low, high = (search.periodic_ends(index, period) if period
                     else (search.bounded_end(index, -1), search.bounded_end(index, 1)))
        ends.append((search.reported(index, low), search.reported(index, high)))
    return SetExtent(ends=tuple(ends), probes=EXTENT_PROBES, solves=search.solves,
                     time_s=time.perf_counter() - started)


_Found = tuple[float, bool, list[float], float]
"""An end in the solver's units: value, at a bound, witness, the witness's RE."""


def _minimised(residuals: Residuals, start: list[float], lower: list[float], upper: list[float],
               max_iterations: int) -> tuple[list[float], float, int, int]:
    """:func:`sso._solvers.lm.minimise` as a :data:`BoxSolve`."""
    x, fun, nit, nfev, _ = minimise(residuals, start, lower, upper, EXTENT_TOLERANCE,
                                    max_iterations)
    return x, fun, nit, nfev


class _ExtentSearch:
    """The pinned-variable solves of :func:`set_extent` (plain float lists: the vectors
    are short and each solve is cheap)."""

    def __init__(self, problem: SetProblem, residuals: Residuals, solve_in_box: BoxSolve,
                 chosen: np.ndarray) -> None:
        self.problem = problem
        self.residuals = residuals
        self.solve_in_box = solve_in_box
        self.chosen: list[float] = chosen.tolist()
        self.chosen_residual_error = abs(residuals(self.chosen)[0]) ** 2
        self.lower: list[float] = problem.lower.tolist()
        self.upper: list[float] = problem.upper.tolist()
        self.walk: list[tuple[float, list[float], float]] = []
        """Each step a walk landed at: value, witness, its RE."""
        rng = np.random.default_rng(EXTENT_SEED)
        self.probes: list[list[float]] = rng.uniform(
            problem.lower, problem.upper, (EXTENT_PROBES, len(self.chosen))).tolist()
        self.solves = 0

    def reported(self, index: int, found: _Found) -> ExtentEnd:
        """An end in the reported units."""
        value, at_bound, witness, fun = found
        return ExtentEnd(value=value * float(self.problem.scale[index]), at_bound=at_bound,
                         witness=self.problem.reported(np.asarray(witness)),
                         witness_residual_error=fun)

    def landed(self, index: int, value: float, starts: Sequence[list[float]]
               ) -> tuple[list[float], float] | None:
        """An exact optimum with variable ``index`` pinned at ``value`` (modulo its period,
        within its bounds, for a periodic variable), and its RE, from the first of
        ``starts`` that lands at round-off zero; None if none does."""
        period = self.problem.wrapping_period(index)
        if period and not self.lower[index] <= value <= self.upper[index]:
            # the same value modulo the period, within the bounds
            value = self.lower[index] + (value - self.lower[index]) % period
        lower, upper = list(self.lower), list(self.upper)
        lower[index] = upper[index] = value
        for start in starts:
            moved = [min(max(entry, bottom), top)
                     for entry, bottom, top in zip(start, lower, upper, strict=True)]
            self.solves += 1
            x, fun, _, _ = self.solve_in_box(moved, lower, upper, EXTENT_MAX_ITERATIONS)
            if is_exact(fun) and x[index] == value and self.problem.feasible(np.asarray(x)):
                return list(x), fun
        return None

    def bounded_end(self, index: int, side: int) -> _Found:
        """The end of variable ``index`` towards its lower (``side`` -1) or upper bound."""
        bound = self.lower[index] if side < 0 else self.upper[index]
        if bound == self.chosen[index]:
            return bound, True, self.chosen, self.chosen_residual_error
        found = self.landed(index, bound, [self.chosen, *self.probes])
        if found is not None:
            return bound, True, *found
        return self.bisected(index, (self.chosen[index], self.chosen,
                                     self.chosen_residual_error), bound)

    def bisected(self, index: int, inside: tuple[float, list[float], float],
                 outside: float) -> _Found:
        """The furthest value found by bisection between ``inside`` (a value, the exact
        optimum found there and its RE) and ``outside`` (where none was found)."""
        value, witness, fun = inside
        for _ in range(EXTENT_HALVINGS):
            middle = 0.5 * (value + outside)
            found = self.landed(index, middle, self._nearby(witness))
            if found is None:
                outside = middle
            else:
                value, (witness, fun) = middle, found
        return value, False, witness, fun

    def _nearby(self, witness: list[float]) -> list[list[float]]:
        """The starts of a value tried next to ``witness``'s."""
        return [witness, self.chosen]

    def periodic_ends(self, index: int, period: float) -> tuple[_Found, _Found]:
        """Both ends of a variable sought modulo its ``period`` (see :func:`set_extent`)."""
        centre = self.lower[index] + 0.5 * period + (
            (self.chosen[index] - self.lower[index] - 0.5 * period) % period)
        start = list(self.chosen)
        start[index] = centre
        step = period / EXTENT_GRID
        high, failed_at = self._walked(index, (centre, start, self.chosen_residual_error),
                                       step, EXTENT_GRID)
        if high is None:  # every step of the period lands: half a period each way
            value, witness, fun = self.walk[EXTENT_GRID // 2 - 1]
            shifted = list(witness)
            shifted[index] -= period  # within the bounds, as the centre is
            return ((value - period, False, shifted, abs(self.residuals(shifted)[0]) ** 2),
                    (value, False, witness, fun))
        low, _ = self._walked(index, (centre, start, self.chosen_residual_error), -step,
                              EXTENT_GRID - failed_at, closes=False)
        assert low is not None
        return low, high

    def _walked(self, index: int, inside: tuple[float, list[float], float], step: float,
                last: int, closes: bool = True) -> tuple[_Found | None, int]:
        """The end reached walking from ``inside`` by ``step`` for ``last - 1`` steps,
        bisected at the first step that does not land (at step ``last`` unless it
        ``closes`` the period, where the walk gives None: every step landed)."""
        centre = inside[0]
        self.walk = []
        for count in range(1, last):
            value = centre + count * step
            found = (self.landed(index, value, self._nearby(inside[1]))
                     or self.landed(index, value, self.probes))
            if found is None:
                return self.bisected(index, inside, value), count
            inside = (value, *found)
            self.walk.append(inside)
        if closes:
            return None, last
        return self.bisected(index, inside, centre + last * step), last


def _variable_names(problem: DesignProblem) -> tuple[str, ...]:
    names = []
    if problem.beta_free:
        names += [f"beta_{joint + 1}" for joint in range(problem.n_joints)]
    if problem.phase_free:
        names += [f"phase_{joint + 1}" for joint in range(problem.n_joints - 1)]
    return tuple(names)
