"""The one result base of every design problem, in the style of scipy's OptimizeResult.

:class:`sso.OptimisationResult` (shaft series) and :class:`sso.FourBarDesignResult`
extend :class:`DesignResult` with what their problem adds; the solver part (every
run, the best answer per solver, the cross-check) and its JSON form are written once,
here.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from sso.solvers.solution import CrossCheck, Solution


@dataclass(frozen=True, kw_only=True)
class DesignResult:
    """What the solvers found for one design problem.

    ``x``, ``fun``, ``nit``, ``nfev``, ``status``, ``message`` and ``success`` read
    as in :class:`scipy.optimize.OptimizeResult`, for the best answer.

    Attributes
    ----------
    best : sso.Solution
        Lowest objective among successful answers (among all, if none succeeded).
    solutions : dict of str to Solution
        Best answer of each solver.
    runs : tuple of Solution
        Every run, each solver from each start.
    crosscheck : sso.CrossCheck or None
        The solvers' verdict; None when one solver was asked for.
    local_minima : tuple of float
        Distinct objective values the successful runs stopped at, ascending.
    """

    best: Solution
    solutions: dict[str, Solution]
    runs: tuple[Solution, ...]
    crosscheck: CrossCheck | None
    local_minima: tuple[float, ...]

    @property
    def success(self) -> bool:
        """True when the best answer converged (feasible) and the solvers agree."""
        return self.best.success and (self.crosscheck is None or self.crosscheck.agree)

    @property
    def x(self) -> tuple[float, ...]:
        """Design vector of the best answer (the problem's units)."""
        return self.best.x

    @property
    def fun(self) -> float:
        """Objective of the best answer."""
        return self.best.fun

    @property
    def nit(self) -> int:
        """Iterations of the best answer's run."""
        return self.best.nit

    @property
    def nfev(self) -> int:
        """Objective evaluations of the best answer's run."""
        return self.best.nfev

    @property
    def status(self) -> int:
        """Solver status of the best answer's run."""
        return self.best.status

    @property
    def message(self) -> str:
        """Solver message of the best answer's run."""
        return self.best.message

    def solver_dict(self) -> dict[str, Any]:
        """JSON-ready solver part: best, solutions, runs, cross-check, minima, success."""
        return {
            "best": self.best.to_dict(),
            "solutions": {name: solution.to_dict() for name, solution in self.solutions.items()},
            "runs": [run.to_dict() for run in self.runs],
            "crosscheck": None if self.crosscheck is None else self.crosscheck.to_dict(),
            "local_minima": list(self.local_minima),
            "success": self.success,
        }

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary of every field (subclasses add their problem's part)."""
        return self.solver_dict()

    # summary() and _repr_html_() belong here too, for every result at once.
