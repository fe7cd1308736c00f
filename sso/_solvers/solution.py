"""What a solver returns, and how two solvers' answers compare."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Protocol

from sso._display import Part, Readable, TextTable, format_number, format_numbers
from sso._record import register_record

ROLE_SOLVE = "solve"
"""A solver's own iterations from a start."""
ROLE_SCREEN = "screen"
"""The "lm" screen of one start (the multi-start search of a least-squares problem)."""
ROLE_CONFIRMATION = "confirmation"
"""A solver's run from a point another method found, which took no iteration: it
confirms that point; it did not find it."""
ROLE_FROM_SCREEN = "from screen"
"""A solver's run from the point the screen found, which iterated from there."""
ROLE_SELECTION = "selection"
"""The choice of the most robust design within a set of exact optima (a solver's run on
that secondary problem, starting from the exact optima found)."""


class SeriesDesign(Protocol):
    """What a solution needs of a shaft-series design (:class:`sso.ShaftSeries` is one).

    A protocol, so the generic solvers do not import the shaft package above them.
    """

    @property
    def beta_deg(self) -> Sequence[float]: ...

    @property
    def phase_deg(self) -> Sequence[float]: ...


@register_record
@dataclass(frozen=True, repr=False)
class Solution(Readable):
    """One solver's answer, named after :class:`scipy.optimize.OptimizeResult`.

    Attributes
    ----------
    solver : str
        ``"ipopt"`` or ``"slsqp"``.
    series : sso.ShaftSeries or None
        The shaft-series design found (all angles, deg); None for other problems.
    x : tuple of float
        The design vector. Shaft series: deg, free operating angles first, then
        free phases. Other problems: in their own units (see their result).
    fun : float
        Objective at ``x``: residual error RE (dimensionless) for a shaft series.
    nit : int
        Iterations of the run that found ``x``.
    nfev : int
        Objective evaluations of that run.
    status : int
        The solver's own code: IPOPT's ``ApplicationReturnStatus`` (0 solved,
        1 solved to acceptable level, negative or >1 failures), SLSQP's exit mode
        (0 success).
    success : bool
        Whether the solver reports convergence.
    message : str
        The solver's own message.
    kkt : float
        First-order optimality: infinity norm of the projected gradient under the
        bounds (per rad for a shaft series); with constraints, of the gradient
        left after the best non-negative multipliers of the active constraints.
    time_s : float
        Wall time of that run, s.
    start_index : int
        Which start the run began from (0 is the user's start).
    total_nfev : int
        Objective evaluations over every start this solver ran.
    constraint_violation : float
        Largest violation of a bound or constraint at ``x`` (0 when feasible).
    role : str
        What the run was: ``"solve"`` (the solver's own iterations from a start),
        ``"screen"`` (the "lm" screen of a start), ``"confirmation"`` (a run from a
        point another method found that took no iteration) or ``"from screen"``
        (a run from that point that iterated) or ``"selection"`` (the choice of the
        most robust design within a set of exact optima).
    """

    solver: str
    series: SeriesDesign | None
    x: tuple[float, ...]
    fun: float
    nit: int
    nfev: int
    status: int
    success: bool
    message: str
    kkt: float
    time_s: float
    start_index: int = 0
    total_nfev: int = 0
    constraint_violation: float = 0.0
    role: str = ROLE_SOLVE

    @property
    def method(self) -> str:
        """Who produced ``x``, in words: ``"ipopt from start 0"``, ``"the 'lm' screen of start
        3"``, ``"slsqp from the screen's best point"``, ``"ipopt confirming the screen's
        best point (0 iterations)"`` or ``"slsqp choosing within the exact optima"``."""
        if self.role == ROLE_SCREEN:
            return f"the {self.solver!r} screen of start {self.start_index}"
        if self.role == ROLE_FROM_SCREEN:
            return f"{self.solver} from the screen's best point"
        if self.role == ROLE_CONFIRMATION:
            return f"{self.solver} confirming the screen's best point (0 iterations)"
        if self.role == ROLE_SELECTION:
            return f"{self.solver} choosing within the exact optima"
        return f"{self.solver} from start {self.start_index}"

    def _repr_text(self) -> str:
        state = "converged" if self.success else "not converged"
        return (f"{self.method}, {state}, fun {format_number(self.fun, 4)}, kkt "
                f"{format_number(self.kkt, 2)}, nit {self.nit}, start {self.start_index}, "
                f"x [{format_numbers(self.x, 6)}]")

    def _summary_parts(self) -> list[Part]:
        rows = [("converged", "yes" if self.success else "no"),
                ("objective", format_number(self.fun)),
                ("KKT residual", format_number(self.kkt, 2)),
                ("iterations", str(self.nit)), ("evaluations", str(self.nfev)),
                ("start", str(self.start_index)), ("x", format_numbers(self.x)),
                ("message", self.message), ("role", self.role)]
        if self.series is not None:
            rows[6:7] = [("beta (deg)", format_numbers(self.series.beta_deg)),
                         ("phase (deg)", format_numbers(self.series.phase_deg))]
        return [f"Solution by {self.method}", TextTable(("item", "value"), tuple(rows))]

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary (a shaft series' design as ``beta_deg``/``phase_deg``)."""
        design = {} if self.series is None else {"beta_deg": list(self.series.beta_deg),
                                                 "phase_deg": list(self.series.phase_deg)}
        return {
            "solver": self.solver,
            "x": list(self.x),
            **design,
            "fun": self.fun,
            "nit": self.nit,
            "nfev": self.nfev,
            "status": self.status,
            "success": self.success,
            "message": self.message,
            "kkt": self.kkt,
            "time_s": self.time_s,
            "start_index": self.start_index,
            "total_nfev": self.total_nfev,
            "constraint_violation": self.constraint_violation,
            "role": self.role,
        }


@register_record
@dataclass(frozen=True, repr=False)
class CrossCheck(Readable):
    """Verdict of comparing solvers by objective value and first-order optimality.

    Design vectors are compared only where each answer is an isolated minimum
    reached from the same start (optima are often whole sets of designs).

    Attributes
    ----------
    agree : bool
        Every solver succeeded, their objectives agree within
        ``objective_atol + objective_rtol * max|fun|``, each is first-order
        optimal (``kkt <= kkt_tolerance``) and feasible (constraint violation at
        most ``kkt_tolerance``).
    objective_gap : float
        Largest difference of RE between solvers (dimensionless).
    objective : dict
        RE of each solver.
    kkt : dict
        Projected-gradient norm of each solver (per rad).
    better : str or None
        The solver with the lower RE when the objectives disagree, else None.
    message : str
        The verdict in words.
    objective_atol, objective_rtol, kkt_tolerance : float
        The tolerances used.
    design_gap : float or None
        Largest difference of a design variable between the answers (the problem's
        solver units, rad for a shaft series) when they were compared; None when not
        (an answer is not an isolated minimum, or they started from different points).
    design_tolerance : float
        The largest ``design_gap`` that counts as the same design (a larger gap at
        equal objectives is two minima, each valid: reported in ``message``).
    """

    agree: bool
    objective_gap: float
    objective: dict[str, float]
    kkt: dict[str, float]
    better: str | None
    message: str
    objective_atol: float
    objective_rtol: float
    kkt_tolerance: float
    design_gap: float | None = None
    design_tolerance: float = 0.0

    def _repr_text(self) -> str:
        return f"agree={self.agree}, {self.message}"

    def _summary_parts(self) -> list[Part]:
        return [f"Cross-check: {self.message}"]

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary of every field."""
        return {
            "agree": self.agree,
            "objective_gap": self.objective_gap,
            "objective": dict(self.objective),
            "kkt": dict(self.kkt),
            "better": self.better,
            "message": self.message,
            "objective_atol": self.objective_atol,
            "objective_rtol": self.objective_rtol,
            "kkt_tolerance": self.kkt_tolerance,
            "design_gap": self.design_gap,
            "design_tolerance": self.design_tolerance,
        }
