"""SciPy's SLSQP fed the exact CasADi gradient (and constraint Jacobian)."""

from __future__ import annotations

import time
from typing import Any

import numpy as np
from scipy.optimize import Bounds, minimize
from threadpoolctl import ThreadpoolController

from sso._record import built
from sso._solvers.nlp import value_and_gradient_floats
from sso._solvers.run import RunLimits, RunOutcome

TESTS_ITS_START = False
"""A run costs iterations even from a minimum: check the start first."""

BLAS_LIBRARIES = ThreadpoolController()
"""The BLAS libraries loaded with SciPy. SLSQP runs on one thread of theirs: SciPy's
OpenBLAS rounds SLSQP's linear algebra differently on two threads than on one (the
paper's option 3 in the paper model then ends at another design), and a Dask worker
runs on one; so an answer is the same bits wherever it is computed."""


def solve(nlp: Any, start: np.ndarray, parameters: np.ndarray, limits: RunLimits,
          solver_tol: float, max_iterations: int) -> RunOutcome:
    """:meth:`sso._solvers.run.Backend.solve` by SLSQP: ``solver_tol`` is a relative tolerance
    on the objective, ``max_iterations`` its ``maxiter``; the problem's constraint-and-Jacobian
    function is used when ``limits`` has constraints.

    SLSQP stops when the objective changes by less than ``ftol`` in absolute
    terms; near a zero residual error a fixed ``ftol`` would stop it far from the
    optimum. ``ftol`` is therefore ``solver_tol`` times the objective at the start,
    floored at ``solver_tol**2 * eps`` so it is never zero.
    """
    # The closed form on plain floats takes the parameters as a list, made once.
    fixed = parameters if nlp.objective_and_gradient_floats is None else parameters.tolist()

    def evaluate(point: list[float]) -> tuple[float, list[float]]:
        return value_and_gradient_floats(nlp, point, fixed)

    # SLSQP's objective and gradient evaluations, counted as scipy.optimize.minimize
    # counts them (nfev, njev), and the last point (as a list) with its gradient: SLSQP
    # asks for the gradient at the point whose objective it has just asked for.
    counts = [0, 0]
    last: list[Any] = [None, None]

    def objective(x: np.ndarray) -> float:
        counts[0] += 1
        point = x.tolist()
        value, last[1] = evaluate(point)
        last[0] = point
        return value

    def gradient(x: np.ndarray) -> np.ndarray:
        counts[1] += 1
        point = x.tolist()
        return np.array(last[1] if point == last[0] else evaluate(point)[1], dtype=float)

    start = np.array(start, dtype=float)
    start_value, _ = evaluate(start.tolist())
    ftol = max(solver_tol * abs(start_value), solver_tol * solver_tol * np.finfo(float).eps)
    started = time.perf_counter()
    try:
        with BLAS_LIBRARIES.limit(limits=1, user_api="blas"):
            answer = minimize(objective, start, method="SLSQP", jac=gradient,
                              bounds=Bounds(limits.lower, limits.upper),
                              constraints=_constraints(nlp, parameters, limits),
                              options={"maxiter": max_iterations, "ftol": ftol})
    except (ValueError, ArithmeticError) as error:
        return RunOutcome(start, float("nan"), 0, 0, 0, -1, False, f"SLSQP raised: {error}",
                          time.perf_counter() - started)
    elapsed = time.perf_counter() - started
    return built(
        RunOutcome,
        x=np.array(answer.x, dtype=float),
        fun=float(answer.fun),
        nit=int(answer.nit),
        nfev=counts[0] + 1,
        njev=counts[1] + 1,
        status=int(answer.status),
        success=int(answer.status) == 0,
        message=str(answer.message),
        time_s=elapsed,
    )


def _constraints(nlp: Any, parameters: np.ndarray, limits: RunLimits
                 ) -> list[dict[str, Any]]:
    """SLSQP's ``c(x) = 0`` and ``c(x) >= 0`` form of ``lbg <= g(x) <= ubg``, as
    ``scipy.optimize.minimize``'s constraints: the equalities, and the inequalities (the
    rows with a lower bound, then those with an upper bound)."""
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
    constraints: list[dict[str, Any]] = []
    if equal.any():
        constraints.append({"type": "eq",
                            "fun": lambda x: evaluate(x)[0][equal] - lower[equal],
                            "jac": lambda x: evaluate(x)[1][equal]})
    if has_lower.any() or has_upper.any():
        def inequalities(x: np.ndarray) -> np.ndarray:
            values = evaluate(x)[0]
            return np.concatenate([values[has_lower] - lower[has_lower],
                                   upper[has_upper] - values[has_upper]])

        def inequalities_jacobian(x: np.ndarray) -> np.ndarray:
            jacobian = evaluate(x)[1]
            return np.vstack([jacobian[has_lower], -jacobian[has_upper]])

        constraints.append({"type": "ineq", "fun": inequalities,
                            "jac": inequalities_jacobian})
    return constraints
