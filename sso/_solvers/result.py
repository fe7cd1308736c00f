"""The one result base of every design problem, in the style of scipy's OptimizeResult.

:class:`sso.OptimisationResult` (shaft series) and :class:`sso.FourBarDesignResult`
extend :class:`DesignResult` with what their problem adds; the solver part (every
run, the best answer per solver, the cross-check) and its JSON form are written once,
here.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from sso._display import Part, Readable, TextTable, format_number
from sso._record import Record
from sso._solvers.solution import CrossCheck, Solution


@dataclass(frozen=True, kw_only=True, eq=False, repr=False)
class DesignResult(Record, Readable):
    """What the solvers found for one design problem.

    ``x``, ``fun``, ``nit``, ``nfev``, ``status``, ``message`` and ``success`` read
    as in :class:`scipy.optimize.OptimizeResult`, for the best answer. ``summary()``,
    ``_repr_html_`` and the one-line ``repr`` come from :class:`sso._display.Readable`:
    each problem lists its design in ``_summary_parts`` and adds
    :meth:`_solver_parts`.

    Attributes
    ----------
    best : sso.Solution
        Lowest objective among successful runs (among all, if none succeeded): a
        solver's own answer, the "lm" screen's (``best.role == "screen"``) or a
        solver's run from the screen's point; :attr:`found_by` says which.
    solutions : dict of str to Solution
        Each solver's own answer (its iterations from its starts; after a screen,
        the better of its solve from the one common start and its run from the
        screen's point when that iterated), the answers the cross-check compares.
    runs : tuple of Solution
        Every run, each solver from each start.
    crosscheck : sso.CrossCheck or None
        The solvers' verdict; None when one solver was asked for.
    local_minima : tuple of float
        Distinct objective values the successful runs stopped at, ascending.
    confirmations : dict of str to Solution
        After a screen, each solver's run from the screen's best point where its own
        answer was worse (``role`` ``"confirmation"`` when it took no iteration,
        ``"from screen"`` when it iterated); empty otherwise.
    """

    best: Solution
    solutions: dict[str, Solution]
    runs: tuple[Solution, ...]
    crosscheck: CrossCheck | None
    local_minima: tuple[float, ...]
    confirmations: dict[str, Solution] = field(default_factory=dict)

    @property
    def found_by(self) -> str:
        """Who found the reported optimum, in words (a solver, or the "lm" screen)."""
        return self.best.method

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

    @property
    def verdict(self) -> str:
        """What the solvers found, in words: a failure, one solver alone, or the cross-check."""
        if not self.best.success:
            return f"solver failed: {self.best.solver}: {self.best.message}"
        if self.crosscheck is None:
            return f"solved by {self.found_by} alone (no cross-check): {self.best.message}"
        return self.crosscheck.message

    def _solver_parts(self, objective: str, kkt: str) -> list[Part]:
        """The solvers table and the cross-check line of a summary.

        Parameters
        ----------
        objective, kkt : str
            Column labels (with units) of the objective and the KKT residual.
        """
        rows = [(name, solution.role, str(solution.start_index),
                 "yes" if solution.success else "no", format_number(solution.fun),
                 format_number(solution.kkt, 2), str(solution.nit), solution.message)
                for name, solution in [*self.solutions.items(),
                                       *[(name, run) for name, run in self.confirmations.items()
                                         if run != self.solutions.get(name)]]]
        solvers = TextTable(("solver", "run", "start", "converged", objective, kkt, "iterations",
                             "message"), tuple(rows))
        check = ("cross-check: one solver, none made" if self.crosscheck is None
                 else f"cross-check of the solvers' own answers: {self.crosscheck.message}")
        return [f"found by: {self.found_by}", solvers, check]
