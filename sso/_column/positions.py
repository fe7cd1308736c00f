"""One yoke phasing for every position of an adjustable column (tilt, telescope).

Tilt and telescope move the joints; the yokes stay where they were assembled on
their splines. So the positions share one yoke phasing ``delta`` (fitter's
convention, :mod:`sso._column.geometry`) while each has its own operating angles
and bend planes. The objective is the worst position's RE (an epigraph NLP) or a
weighted mean of the positions' RE (:mod:`sso._column.scenarios`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from sso._column.geometry import ColumnGeometry
from sso._column.phasing import PhasingResult, optimise_phasing
from sso._column.scenarios import PhasingOutcome, outcome_fields, scenario_re, solve_scenarios
from sso._limits import (
    CROSS_CHECK_SOLVERS,
    DEFAULT_COLUMN_SEED,
    DEFAULT_COLUMN_SOLVER_TOL,
    DEFAULT_COLUMN_STARTS,
    DEFAULT_MAX_ITERATIONS,
    MAX_ITERATIONS,
    MAX_STARTS,
)
from sso._record import register_record
from sso._validation import (
    check_choice,
    finite_float,
    validate_count,
    validate_solver_tol,
    validate_solvers,
)

POSITIONS_OBJECTIVES = ("worst", "mean")
# A position is active when its RE is within this fraction of the worst position's RE.
ACTIVE_RELATIVE = 1e-6


@register_record
@dataclass(frozen=True)
class SinglePositionOptimum:
    """The best phasing of one position alone, and what it does at the others.

    Attributes
    ----------
    yoke_phase_deg : tuple of float
        Its best yoke phasing, deg (:func:`sso.optimise`).
    position_re : dict of str to float
        RE of that phasing at every position.
    worst_re : float
        The largest of them.
    """

    yoke_phase_deg: tuple[float, ...]
    position_re: dict[str, float]
    worst_re: float


@dataclass(frozen=True, eq=False, repr=False)
class PositionsResult(PhasingOutcome):
    """Outcome of :func:`optimise_positions`.

    Attributes
    ----------
    x, fun, nit, nfev, status, success, message, best, solutions, runs, crosscheck
        As :class:`sso._column.scenarios.PhasingOutcome`: ``x`` the shared yoke
        phasing (deg), ``fun`` the worst position's RE (``"worst"``) or the
        weighted mean RE (``"mean"``), evaluated at ``x`` with the closed form.
    positions_objective : {"worst", "mean"}
    weights : dict of str to float
        Weight of each position (sum 1; equal unless given).
    position_re : dict of str to float
        RE of the shared phasing at each position.
    worst_re : float
        The largest of them.
    active_positions : tuple of str
        Positions whose RE is within ``1e-6`` relative of ``worst_re`` (the
        constraints that bind in the worst-case problem).
    single_position : dict of str to SinglePositionOptimum
        Each position's own optimum, for comparison: its worst-position RE is what
        a phasing chosen for that position alone gives over the range.
    single_position_runs : dict of str to PhasingResult
    geometries : dict of str to ColumnGeometry
    """

    positions_objective: str
    weights: dict[str, float]
    position_re: dict[str, float]
    worst_re: float
    active_positions: tuple[str, ...]
    single_position: dict[str, SinglePositionOptimum]
    single_position_runs: dict[str, PhasingResult]
    geometries: dict[str, ColumnGeometry]

    @property
    def objective_name(self) -> str:
        """What ``fun`` measures, in words."""
        return ("worst-position RE" if self.positions_objective == "worst"
                else "weighted mean RE over the positions")

    def phasing_objective(self) -> Callable[[np.ndarray], np.ndarray]:
        """The worst (or weighted mean) RE over the positions, as a function of yoke
        phasings (``(m, shafts)`` deg -> ``(m,)``)."""
        names = list(self.geometries)
        beta = np.radians([self.geometries[name].beta_deg for name in names])
        gamma = np.radians([self.geometries[name].plane_angle_deg for name in names])
        weights = np.array([self.weights[name] for name in names])

        def objective(yokes: np.ndarray) -> np.ndarray:
            values = scenario_re(beta, gamma, yokes[:, np.newaxis, :])
            result: np.ndarray = (values.max(axis=1) if self.positions_objective == "worst"
                                  else values @ weights)
            return result

        return objective


def optimise_positions(geometries: Mapping[str, ColumnGeometry], *,
                       positions_objective: str = "worst",
                       weights: Mapping[str, float] | None = None,
                       solvers: tuple[str, ...] = CROSS_CHECK_SOLVERS,
                       starts: int = DEFAULT_COLUMN_STARTS,
                       solver_tol: float = DEFAULT_COLUMN_SOLVER_TOL,
                       max_iterations: int = DEFAULT_MAX_ITERATIONS,
                       seed: int = DEFAULT_COLUMN_SEED) -> PositionsResult:
    """One yoke phasing for several positions of a column.

    Parameters
    ----------
    geometries : mapping of str to ColumnGeometry
        Named positions (e.g. ``{"up": ..., "mid": ..., "down": ...}``), all with
        the same joint count (at least 2).
    positions_objective : {"worst", "mean"}
        ``"worst"``: minimise the largest RE over the positions (epigraph form:
        ``min t`` s.t. ``RE_p <= t``); ``"mean"``: minimise the weighted mean RE.
    weights : mapping of str to float, optional
        Weight of each position for ``"mean"`` (non-negative, not all zero; scaled
        to sum 1); default equal. Not allowed with ``"worst"``.
    solvers : tuple of {"ipopt", "slsqp"}
        With two they are cross-checked.
    starts : int
        Space-filling starts per solver, added to each position's own optimum.
    solver_tol : float
        Solver tolerance on the scaled problem (RE divided by the best
        single-position optimum's worst-position RE).
    max_iterations, seed
        As :func:`sso.optimise`.

    Returns
    -------
    PositionsResult
        Solver failures and disagreements are reported in it, not raised.

    Raises
    ------
    TypeError
        If ``geometries`` is not a mapping of names to :class:`ColumnGeometry`.
    ValueError
        If there are no positions, the joint counts differ (``geometries``), a
        weight is bad (``weights``), or an option is bad.
    """
    names, columns = _validated_geometries(geometries)
    check_choice("positions_objective", positions_objective, POSITIONS_OBJECTIVES)
    weight_of = _validated_weights(weights, names, positions_objective)
    solver_names = validate_solvers(solvers)
    starts = validate_count("starts", starts, 0, MAX_STARTS)
    max_iterations = validate_count("max_iterations", max_iterations, 1, MAX_ITERATIONS)
    solver_tol = validate_solver_tol(solver_tol)

    beta_rad = np.radians([column.beta_deg for column in columns])
    gamma_rad = np.radians([column.plane_angle_deg for column in columns])
    singles_runs = {name: optimise_phasing(column, solvers=solver_names, seed=seed)
                    for name, column in zip(names, columns, strict=True)}
    singles = {}
    for name, run in singles_runs.items():
        values = scenario_re(beta_rad, gamma_rad, run.yoke_phase_deg)
        singles[name] = SinglePositionOptimum(run.yoke_phase_deg, _named(names, values),
                                              float(values.max()))
    reference = min(single.worst_re for single in singles.values())
    scale = 1.0 / reference if reference > 0 else 1.0
    weight_array = np.array([weight_of[name] for name in names])
    objective = "worst" if positions_objective == "worst" else "mean"
    solved = solve_scenarios(beta_rad, gamma_rad, objective=objective, weights=weight_array,
                             scale=scale,
                             user_starts_deg=[s.yoke_phase_deg for s in singles.values()],
                             starts=starts, solvers=solver_names, solver_tol=solver_tol,
                             max_iterations=max_iterations, seed=seed)
    values = scenario_re(beta_rad, gamma_rad, solved.yoke_phase_deg)
    worst = float(values.max())
    fun = worst if objective == "worst" else float(np.dot(weight_array, values))
    active = tuple(name for name, value in zip(names, values, strict=True)
                   if value >= worst * (1.0 - ACTIVE_RELATIVE))
    message = (f"{solved.best.message}; worst position RE {worst:.6g} ({', '.join(active)}); "
               f"best single-position optimum's worst RE {reference:.6g}")
    return PositionsResult(
        **outcome_fields(solved, fun, message), positions_objective=positions_objective,
        weights=weight_of, position_re=_named(names, values), worst_re=worst,
        active_positions=active, single_position=singles, single_position_runs=singles_runs,
        geometries=dict(zip(names, columns, strict=True)))


def _named(names: list[str], values: np.ndarray) -> dict[str, float]:
    return {name: float(value) for name, value in zip(names, values, strict=True)}


def _validated_geometries(geometries: Any) -> tuple[list[str], list[ColumnGeometry]]:
    if not isinstance(geometries, Mapping):
        raise TypeError("geometries must be a mapping of position names to ColumnGeometry, "
                        f"not {type(geometries).__name__}")
    if not geometries:
        raise ValueError("geometries is empty: give at least one named position")
    names, columns = [], []
    for name, column in geometries.items():
        if not isinstance(name, str) or not name:
            raise TypeError(f"geometries key {name!r} must be a non-empty position name (str)")
        if not isinstance(column, ColumnGeometry):
            raise TypeError(f"geometries[{name!r}] must be a ColumnGeometry, "
                            f"not {type(column).__name__}")
        names.append(name)
        columns.append(column)
    first = columns[0].joint_count
    for name, column in zip(names, columns, strict=True):
        if column.joint_count != first:
            raise ValueError(
                f"geometries[{name!r}] has {column.joint_count} joints but "
                f"geometries[{names[0]!r}] has {first}: every position of one column must "
                "have the same joint count")
    if first < 2:
        raise ValueError(f"geometries have {first} joint: yoke phasing needs at least 2 joints")
    return names, columns


def _validated_weights(weights: Any, names: list[str], objective: str) -> dict[str, float]:
    if weights is None:
        return {name: 1.0 / len(names) for name in names}
    if objective != "mean":
        raise ValueError(f"weights are for positions_objective = 'mean', not {objective!r}")
    if not isinstance(weights, Mapping):
        raise TypeError(f"weights must be a mapping of position names to numbers, "
                        f"not {type(weights).__name__}")
    if set(weights) != set(names):
        raise ValueError(f"weights name {sorted(weights)}; they must name exactly the "
                         f"positions {names}")
    values = {name: finite_float(f"weights[{name!r}]", weights[name]) for name in names}
    for name, value in values.items():
        if value < 0:
            raise ValueError(f"weights[{name!r}] = {value:g} is outside the allowed range "
                             "[0, inf)")
    total = math.fsum(values.values())
    if total <= 0:
        raise ValueError("weights are all zero: at least one position needs a positive weight")
    return {name: value / total for name, value in values.items()}
