"""SciPy's SLSQP fed the exact CasADi gradient of the residual error."""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from sso.solvers.run import RunOutcome


def solve(
    nlp: Any,
    start_rad: np.ndarray,
    parameters_rad: np.ndarray,
    lower_rad: np.ndarray,
    upper_rad: np.ndarray,
    tolerance: float,
    max_iterations: int,
) -> RunOutcome:
    """Run SLSQP once from ``start_rad``; failures come back in the outcome.

    SLSQP stops when the objective changes by less than ``ftol`` in absolute
    terms, which near a zero residual error would stop it far from the optimum.
    ``ftol`` is therefore ``tolerance`` times the objective at the start, floored
    at the square of ``tolerance`` times machine precision... never at zero.

    Parameters
    ----------
    nlp : sso.design.nlp.CompiledNLP
        The cached problem graph (its objective-and-gradient function is used).
    start_rad, parameters_rad, lower_rad, upper_rad : numpy.ndarray
        Start, fixed angles and bounds (rad).
    tolerance : float
        Relative tolerance on the objective.
    max_iterations : int
        SLSQP's ``maxiter``.
    """
    from scipy.optimize import Bounds, minimize

    objective_and_gradient = nlp.objective_and_gradient

    def fun(x: np.ndarray) -> tuple[float, np.ndarray]:
        value, gradient = objective_and_gradient(x, parameters_rad)
        return float(value), np.array(gradient, dtype=float).ravel()

    start_value, _ = fun(start_rad)
    ftol = max(tolerance * start_value, tolerance * tolerance * np.finfo(float).eps)
    started = time.perf_counter()
    try:
        answer = minimize(fun, np.array(start_rad, dtype=float), jac=True, method="SLSQP",
                          bounds=Bounds(lower_rad, upper_rad),
                          options={"ftol": ftol, "maxiter": max_iterations})
    except (ValueError, ArithmeticError) as error:
        return RunOutcome(np.array(start_rad, dtype=float), float("nan"), 0, 0, 0, -1, False,
                          f"SLSQP raised: {error}", time.perf_counter() - started)
    elapsed = time.perf_counter() - started
    return RunOutcome(
        x_rad=np.array(answer.x, dtype=float),
        fun=float(answer.fun),
        nit=int(answer.nit),
        nfev=int(answer.nfev) + 1,
        njev=int(answer.njev) + 1,
        status=int(answer.status),
        success=bool(answer.success),
        message=str(answer.message),
        time_s=elapsed,
    )
