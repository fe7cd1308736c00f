"""Four-bar design: the largest rocker swing under transmission-angle and Grashof limits.

The same solver stack as the shaft series (CasADi graph, IPOPT with the exact
Hessian, SLSQP with exact gradients, multi-start, cross-check) on a problem with
real equality and inequality constraints:

* maximise the rocker swing ``psi = phi_extended - phi_folded``, the angles at
  the rocker pivot between the ground line and the rocker at the two limit
  positions (crank and coupler in line, ``|O_A B| = coupler +- crank``). The two
  angles are design variables tied to the lengths by the law of cosines as
  equality constraints, so the graph has no ``acos`` and stays finite at starts
  that do not assemble;
* the transmission angle ``mu`` stays in ``[mu_min, mu_max]`` over the whole
  revolution. ``cos mu = (b^2 + c^2 - a^2 - d^2 + 2 a d cos theta) / (2 b c)``
  is monotonic in ``cos theta``, so its extremes are at ``theta = 0`` and
  ``180`` deg and two constraints cover every crank angle exactly;
* the linkage stays a crank-rocker: the crank is the shortest link and
  Grashof's ``s + l <= p + q`` holds, written without ``max`` as three sums.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from sso._display import Part, TextTable, format_number
from sso._limits import (
    CROSS_CHECK_SOLVERS,
    DEFAULT_FOURBAR_SOLVER_TOL,
    DEFAULT_KKT_TOLERANCE,
    DEFAULT_MAX_ITERATIONS,
    DEFAULT_OBJECTIVE_ATOL,
    DEFAULT_OBJECTIVE_RTOL,
    DEFAULT_SEED,
    DEFAULT_STARTS,
    MAX_ITERATIONS,
    MAX_STARTS,
    TRANSMISSION_BAND_DEG,
)
from sso._linkages.mechanisms import FourBar
from sso._solvers.multistart import solution_from_run, solve_from_starts
from sso._solvers.nlp import cached_nlp, compile_nlp
from sso._solvers.result import DesignResult
from sso._solvers.run import RunLimits
from sso._validation import (
    per_item_bounds,
    validate_count,
    validate_solver_tol,
    validate_solvers,
)

if TYPE_CHECKING:
    from sso._linkages.mechanisms import FourBar

LINKS = ("crank", "coupler", "rocker", "ground")


@dataclass(frozen=True, kw_only=True, eq=False, repr=False)
class FourBarDesignResult(DesignResult):
    """Outcome of :func:`design_fourbar`.

    Attributes
    ----------
    initial, optimum : sso._linkages.mechanisms.FourBar
        The start linkage and the best one found.
    initial_swing_deg, optimum_swing_deg : float or None
        Rocker swing of each, deg (None when the start is not a crank-rocker).
    optimum_transmission_angle_deg : (float, float)
        Smallest and largest transmission angle of the optimum over a revolution, deg.
    transmission_angle_bounds_deg : (float, float)
        The limits imposed, deg.
    link_bounds : dict of str to (float, float)
        Bounds of each link length (length units).
    best, solutions, runs, crosscheck, local_minima
        As in :class:`sso._solvers.result.DesignResult`: ``x`` = (crank, coupler,
        rocker, ground, extended and folded rocker angles at the pivot in rad);
        ``fun`` = minus the swing, rad.
    """

    initial: FourBar
    optimum: FourBar
    initial_swing_deg: float | None
    optimum_swing_deg: float
    optimum_transmission_angle_deg: tuple[float, float]
    transmission_angle_bounds_deg: tuple[float, float]
    link_bounds: dict[str, tuple[float, float]]

    report_kind: ClassVar[str] = "fourbar_design"

    def _repr_text(self) -> str:
        verdict = "success" if self.success else "FAILED"
        lengths = ", ".join(f"{name} {format_number(getattr(self.optimum, name))}"
                            for name in LINKS)
        return (f"{verdict}: swing {format_number(self.initial_swing_deg, 4)} -> "
                f"{format_number(self.optimum_swing_deg, 4)} deg by {self.best.solver}; "
                f"{lengths}")

    def _summary_parts(self) -> list[Part]:
        verdict = "success" if self.success else "FAILED"
        low, high = self.optimum_transmission_angle_deg
        designs = TextTable(("linkage", *LINKS, "swing (deg)"), (
            ("initial", *(format_number(getattr(self.initial, name)) for name in LINKS),
             format_number(self.initial_swing_deg)),
            (f"optimum ({self.best.solver})",
             *(format_number(getattr(self.optimum, name)) for name in LINKS),
             format_number(self.optimum_swing_deg))))
        band = (f"transmission angle of the optimum: {format_number(low)} .. "
                f"{format_number(high)} deg (allowed "
                f"{format_number(self.transmission_angle_bounds_deg[0])} .. "
                f"{format_number(self.transmission_angle_bounds_deg[1])})")
        return [f"Four-bar design, largest rocker swing: {verdict}", designs, band,
                *self._solver_parts("-swing (rad)", "KKT")]


def design_fourbar(
    start: FourBar,
    *,
    crank_bounds: tuple[float, float],
    coupler_bounds: tuple[float, float],
    rocker_bounds: tuple[float, float],
    ground_bounds: tuple[float, float] | None = None,
    transmission_angle_bounds_deg: tuple[float, float] = TRANSMISSION_BAND_DEG,
    solvers: Iterable[str] | str = CROSS_CHECK_SOLVERS,
    starts: int = DEFAULT_STARTS,
    solver_tol: float = DEFAULT_FOURBAR_SOLVER_TOL,
    max_iterations: int = DEFAULT_MAX_ITERATIONS,
    seed: int = DEFAULT_SEED,
) -> FourBarDesignResult:
    """Link lengths of the crank-rocker with the largest rocker swing.

    Parameters
    ----------
    start : sso._linkages.mechanisms.FourBar
        Start linkage (its branch is kept; the swing does not depend on it).
    crank_bounds, coupler_bounds, rocker_bounds : (float, float)
        Bounds of each length (length units, finite, > 0; an equal pair pins it).
    ground_bounds : (float, float), optional
        Bounds of the ground length; default pins it at the start's value (swing
        and transmission angle do not change with scale, so one length must be held).
    transmission_angle_bounds_deg : (float, float)
        Allowed transmission angle over the whole revolution, deg, inside (0, 180).
    solvers, starts, solver_tol, max_iterations, seed
        As in :func:`sso.optimise`.

    Returns
    -------
    FourBarDesignResult
        Solver failures and disagreements are reported in it, not raised.

    Raises
    ------
    ValueError
        For bad bounds or options, naming the field, the value and the range.
    """
    solver_names = validate_solvers(solvers)
    starts = validate_count("starts", starts, 1, MAX_STARTS)
    max_iterations = validate_count("max_iterations", max_iterations, 1, MAX_ITERATIONS)
    solver_tol = validate_solver_tol(solver_tol)
    if ground_bounds is None:
        ground_bounds = (start.ground, start.ground)
    link_bounds = {
        name: per_item_bounds(f"{name}_bounds", pair, 1, 0.0, math.inf, "length units")[0]
        for name, pair in zip(LINKS, (crank_bounds, coupler_bounds, rocker_bounds, ground_bounds),
                               strict=True)
    }
    for name, (lower_length, _) in link_bounds.items():
        if lower_length <= 0:
            raise ValueError(f"{name}_bounds lower = {lower_length:g} is outside the allowed range "
                             "(0, inf) length units")
    mu_low, mu_high = per_item_bounds("transmission_angle_bounds_deg",
                                      transmission_angle_bounds_deg, 1, 0.0, 180.0, "deg")[0]
    if mu_low <= 0 or mu_high >= 180:
        raise ValueError(f"transmission_angle_bounds_deg = ({mu_low:g}, {mu_high:g}) is outside "
                         "the allowed range (0, 180) deg")

    lower = np.array([pair[0] for pair in link_bounds.values()] + [0.0, 0.0])
    upper = np.array([pair[1] for pair in link_bounds.values()] + [math.pi, math.pi])
    inf = np.inf
    limits = RunLimits(
        lower, upper,
        constraint_lower=np.array([0.0, 0.0, -inf, math.cos(math.radians(mu_high))] + [-inf] * 6),
        constraint_upper=np.array([0.0, 0.0, math.cos(math.radians(mu_low)), inf] + [0.0] * 6),
    )
    lengths = np.clip([start.crank, start.coupler, start.rocker, start.ground], lower[:4],
                      upper[:4])
    user_start = np.concatenate([lengths, _limit_angles(*lengths)])
    solved = solve_from_starts(
        _compiled(), user_start, limits, np.zeros(0), solver_names=solver_names,
        starts=starts, seed=seed, solver_tol=solver_tol, max_iterations=max_iterations,
        to_solution=solution_from_run, objective_rtol=DEFAULT_OBJECTIVE_RTOL,
        objective_atol=DEFAULT_OBJECTIVE_ATOL, kkt_tolerance=DEFAULT_KKT_TOLERANCE)
    best = solved["best"]
    optimum = FourBar(**dict(zip(LINKS, best.x[:4], strict=True)), branch=start.branch)
    return FourBarDesignResult(
        initial=start,
        optimum=optimum,
        initial_swing_deg=(start.swing_angle_deg() if start.grashof() == "crank-rocker" else None),
        optimum_swing_deg=-math.degrees(best.fun),
        optimum_transmission_angle_deg=transmission_angle_range_deg(optimum),
        transmission_angle_bounds_deg=(mu_low, mu_high),
        link_bounds=link_bounds,
        **solved,
    )


def transmission_angle_range_deg(fourbar: FourBar) -> tuple[float, float]:
    """Smallest and largest transmission angle over a crank revolution, deg.

    They occur with the crank along the ground line (0 and 180 deg).
    """
    values = _transmission_cosines(np, fourbar.crank, fourbar.coupler, fourbar.rocker,
                                   fourbar.ground)
    low, high = (math.degrees(math.acos(min(max(value, -1.0), 1.0))) for value in values)
    return (min(low, high), max(low, high))


def _limit_angles(crank: float, coupler: float, rocker: float, ground: float) -> np.ndarray:
    """Rocker angles at the pivot at the two limit positions (rad), clamped where
    the start does not assemble there, as a start for the angle variables."""
    def angle(pivot_to_b: float) -> float:
        cosine = (ground**2 + rocker**2 - pivot_to_b**2) / (2 * ground * rocker)
        return math.acos(min(max(cosine, -1.0), 1.0))

    return np.array([angle(coupler + crank), angle(coupler - crank)])


def _transmission_cosines(xp: Any, crank: Any, coupler: Any, rocker: Any,
                          ground: Any) -> tuple[Any, Any]:
    common = coupler * coupler + rocker * rocker
    return ((common - (ground - crank) ** 2) / (2 * coupler * rocker),
            (common - (ground + crank) ** 2) / (2 * coupler * rocker))


def _compiled() -> Any:
    return cached_nlp("fourbar_swing", _build)


def _build() -> Any:
    import casadi

    x = casadi.SX.sym("x", 6)
    crank, coupler, rocker, ground, angle_extended, angle_folded = (x[i] for i in range(6))

    def closure(angle: Any, pivot_to_b: Any) -> Any:
        return ground**2 + rocker**2 - 2 * ground * rocker * casadi.cos(angle) - pivot_to_b**2

    cos_at_0, cos_at_180 = _transmission_cosines(casadi, crank, coupler, rocker, ground)
    constraints = casadi.vertcat(
        closure(angle_extended, coupler + crank), closure(angle_folded, coupler - crank),
        cos_at_0, cos_at_180,
        crank - coupler, crank - rocker, crank - ground,
        crank + coupler - rocker - ground,
        crank + rocker - coupler - ground,
        crank + ground - coupler - rocker,
    )
    return compile_nlp("sso_fourbar_swing", x, casadi.SX.sym("p", 0),
                       angle_folded - angle_extended, constraints)
