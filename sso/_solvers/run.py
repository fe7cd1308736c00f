"""What one solver run needs and what it returns, before it becomes a Solution."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np

from sso._record import rebuilt

# Shared by every problem without constraint functions (one per solve otherwise);
# read-only, so no caller can change it for the others.
_NO_CONSTRAINTS = np.zeros(0)
_NO_CONSTRAINTS.flags.writeable = False


@dataclass(frozen=True)
class RunLimits:
    """Bounds of one solve, in the NLP's own units (angles in rad).

    Attributes
    ----------
    lower, upper : numpy.ndarray
        Bounds of the design vector.
    constraint_lower, constraint_upper : numpy.ndarray
        Bounds of the constraint functions ``g(x, p)``; empty when the problem
        has only bounds. ``-inf``/``inf`` mark a one-sided constraint.
    """

    lower: np.ndarray
    upper: np.ndarray
    constraint_lower: np.ndarray = field(default_factory=lambda: _NO_CONSTRAINTS)
    constraint_upper: np.ndarray = field(default_factory=lambda: _NO_CONSTRAINTS)

    @property
    def constrained(self) -> bool:
        """True when the problem has constraint functions besides bounds."""
        return len(self.constraint_lower) > 0


@dataclass(frozen=True)
class RunOutcome:
    """Raw result of one run, design vector in the NLP's units.

    Attributes mirror :class:`sso.Solution`; ``njev`` counts gradient evaluations.
    """

    x: np.ndarray
    fun: float
    nit: int
    nfev: int
    njev: int
    status: int
    success: bool
    message: str
    time_s: float

    def with_time(self, time_s: float) -> RunOutcome:
        """The same outcome with wall time ``time_s`` (s)."""
        return rebuilt(self, time_s=time_s)


class Backend(Protocol):
    """A solver module (:mod:`sso._solvers.ipopt`, ``lm``, ``slsqp``): one run from one start.

    ``TESTS_ITS_START`` says whether the solver's own first step already stops at a
    start that is a minimum (then no second-order check is made before it).
    """

    TESTS_ITS_START: bool

    def solve(self, nlp: Any, start: np.ndarray, parameters: np.ndarray, limits: RunLimits,
              solver_tol: float, max_iterations: int) -> RunOutcome:
        """Run the solver once from ``start``; failures come back in the outcome, never raised.

        Parameters
        ----------
        nlp : sso._solvers.nlp.CompiledNLP
            The cached problem graph.
        start, parameters : numpy.ndarray
            Start of the design vector and the fixed parameters (NLP units).
        limits : RunLimits
            Bounds of the design vector and of the constraints.
        solver_tol : float
            The solver's tolerance (what it bounds is the solver's own).
        max_iterations : int
            Iterations, at most.
        """
