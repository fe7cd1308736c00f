"""SciPy's SLSQP fed the exact CasADi gradient (and constraint Jacobian)."""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from sso._solvers.run import RunLimits, RunOutcome

TESTS_ITS_START = False
"""A run costs iterations even from a minimum: check the start first."""


def solve(
    nlp: Any,
    start: np.ndarray,
    parameters: np.ndarray,
    limits: RunLimits,
    solver_tol: float,
    max_iterations: int,
) -> RunOutcome:
    """Run SLSQP once from ``start``; failures come back in the outcome.

    SLSQP stops when the objective changes by less than ``ftol`` in absolute
    terms; near a zero residual error a fixed ``ftol`` would stop it far from the
    optimum. ``ftol`` is therefore ``solver_tol`` times the objective at the start,
    floored at ``solver_tol**2 * eps`` so it is never zero.

    Parameters
    ----------
    nlp : sso._solvers.nlp.CompiledNLP
        The cached problem graph: its objective-and-gradient function, and its
        constraint-and-Jacobian function when ``limits`` has constraints.
    start, parameters : numpy.ndarray
        Start of the design vector and the fixed parameters (NLP units).
    limits : RunLimits
        Bounds of the design vector and of the constraints.
    solver_tol : float
        Relative tolerance on the objective.
    max_iterations : int
        SLSQP's ``maxiter``.
    """
    from scipy.optimize import Bounds, minimize

    objective_and_gradient = nlp.objective_and_gradient

    def fun(x: np.ndarray) -> tuple[float, np.ndarray]:
        value, gradient = objective_and_gradient(x, parameters)
        return float(value), np.array(gradient, dtype=float).ravel()

    start = np.array(start, dtype=float)
    start_value, _ = fun(start)
    ftol = max(solver_tol * abs(start_value), solver_tol * solver_tol * np.finfo(float).eps)
    started = time.perf_counter()
    try:
        answer = minimize(fun, start, jac=True, method="SLSQP",
                          bounds=Bounds(limits.lower, limits.upper),
                          constraints=_constraints(nlp, parameters, limits),
                          options={"ftol": ftol, "maxiter": max_iterations})
    except (ValueError, ArithmeticError) as error:
        return RunOutcome(start, float("nan"), 0, 0, 0, -1, False, f"SLSQP raised: {error}",
                          time.perf_counter() - started)
    elapsed = time.perf_counter() - started
    return RunOutcome(
        x=np.array(answer.x, dtype=float),
        fun=float(answer.fun),
        nit=int(answer.nit),
        nfev=int(answer.nfev) + 1,
        njev=int(answer.njev) + 1,
        status=int(answer.status),
        success=bool(answer.success),
        message=str(answer.message),
        time_s=elapsed,
    )


def _constraints(nlp: Any, parameters: np.ndarray, limits: RunLimits) -> list[dict[str, Any]]:
    """SLSQP's ``c(x) >= 0`` / ``c(x) = 0`` form of ``lbg <= g(x) <= ubg``."""
    if not limits.constrained:
        return []
    constraints_and_jacobian = nlp.constraints_and_jacobian

    def evaluate(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        values, jacobian = constraints_and_jacobian(x, parameters)
        return np.array(values, dtype=float).ravel(), np.array(jacobian, dtype=float)

    lower, upper = limits.constraint_lower, limits.constraint_upper
    equal = lower == upper
    has_lower = np.isfinite(lower) & ~equal
    has_upper = np.isfinite(upper) & ~equal
    constraints = []
    if equal.any():
        constraints.append({"type": "eq",
                            "fun": lambda x: evaluate(x)[0][equal] - lower[equal],
                            "jac": lambda x: evaluate(x)[1][equal]})
    if has_lower.any():
        constraints.append({"type": "ineq",
                            "fun": lambda x: evaluate(x)[0][has_lower] - lower[has_lower],
                            "jac": lambda x: evaluate(x)[1][has_lower]})
    if has_upper.any():
        constraints.append({"type": "ineq",
                            "fun": lambda x: upper[has_upper] - evaluate(x)[0][has_upper],
                            "jac": lambda x: -evaluate(x)[1][has_upper]})
    return constraints
