"""IPOPT through CasADi's ``nlpsol``, with the exact Hessian of the residual error."""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from sso.interrupts import raised_after_native_call
from sso.solvers.run import RunLimits, RunOutcome

TESTS_ITS_START = False
"""A run costs a solver set-up and iterations even from a minimum: check the start first."""

# IPOPT's ApplicationReturnStatus codes, keyed by the names CasADi reports.
RETURN_STATUS_CODES = {
    "Solve_Succeeded": 0,
    "Solved_To_Acceptable_Level": 1,
    "Infeasible_Problem_Detected": 2,
    "Search_Direction_Becomes_Too_Small": 3,
    "Diverging_Iterates": 4,
    "User_Requested_Stop": 5,
    "Feasible_Point_Found": 6,
    "Maximum_Iterations_Exceeded": -1,
    "Restoration_Failed": -2,
    "Error_In_Step_Computation": -3,
    "Maximum_CpuTime_Exceeded": -4,
    "Maximum_WallTime_Exceeded": -5,
    "Not_Enough_Degrees_Of_Freedom": -10,
    "Invalid_Problem_Definition": -11,
    "Invalid_Option": -12,
    "Invalid_Number_Detected": -13,
    "Unrecoverable_Exception": -100,
    "NonIpopt_Exception_Thrown": -101,
    "Insufficient_Memory": -102,
    "Internal_Error": -199,
}
UNKNOWN_STATUS = -999
SNAP_DISTANCE = 1e-6


def solve(
    nlp: Any,
    start: np.ndarray,
    parameters: np.ndarray,
    limits: RunLimits,
    solver_tol: float,
    max_iterations: int,
) -> RunOutcome:
    """Run IPOPT once from ``start``; failures come back in the outcome.

    Parameters
    ----------
    nlp : sso.solvers.nlp.CompiledNLP
        The cached problem graph.
    start, parameters : numpy.ndarray
        Start of the design vector and the fixed parameters (NLP units).
    limits : RunLimits
        Bounds of the design vector and of the constraints.
    solver_tol : float
        IPOPT's ``tol`` (scaled NLP error).
    max_iterations : int
        IPOPT's ``max_iter``.
    """
    options = {"tol": solver_tol, "max_iter": max_iterations}
    if limits.constrained:
        # IPOPT's default accepts a constraint violation of 1e-4 at convergence.
        options["constr_viol_tol"] = solver_tol
    solver = nlp.ipopt(options)
    arguments = {"x0": start, "p": parameters, "lbx": limits.lower, "ubx": limits.upper}
    if limits.constrained:
        arguments.update(lbg=limits.constraint_lower, ubg=limits.constraint_upper)
    started = time.perf_counter()
    try:
        with raised_after_native_call():  # CasADi would end the solve and drop Ctrl-C
            answer = solver(**arguments)
    except RuntimeError as error:
        return RunOutcome(np.array(start, dtype=float), float("nan"), 0, 0, 0,
                          UNKNOWN_STATUS, False, f"IPOPT raised: {error}",
                          time.perf_counter() - started)
    stats = solver.stats()
    return_status = str(stats.get("return_status", "unknown"))
    x = np.array(answer["x"], dtype=float).ravel()
    fun = float(answer["f"])
    if not limits.constrained:
        x, fun = _snap_to_active_bounds(nlp, x, fun, np.array(answer["lam_x"], dtype=float).ravel(),
                                        parameters, limits)
    elapsed = time.perf_counter() - started
    return RunOutcome(
        x=x,
        fun=fun,
        nit=int(stats.get("iter_count", 0)),
        nfev=int(stats.get("n_call_nlp_f", 0)),
        njev=int(stats.get("n_call_nlp_grad_f", 0)),
        status=RETURN_STATUS_CODES.get(return_status, UNKNOWN_STATUS),
        success=bool(stats.get("success", False)),
        message=return_status,
        time_s=elapsed,
    )


def _snap_to_active_bounds(
    nlp: Any,
    x: np.ndarray,
    fun: float,
    bound_multipliers: np.ndarray,
    parameters: np.ndarray,
    limits: RunLimits,
) -> tuple[np.ndarray, float]:
    """Move variables whose bound is active onto it (bound-only problems).

    An interior-point method stops a barrier-width short of an active bound, and
    with a steep gradient there that gap shows in the objective. A bound is
    taken as active when its multiplier pushes against it (CasADi's ``lam_x``:
    negative at a lower bound, positive at an upper one) and the variable lies
    within ``SNAP_DISTANCE``. The snapped point is kept only if it is no worse.
    """
    at_lower = (bound_multipliers < 0) & (x - limits.lower < SNAP_DISTANCE)
    at_upper = (bound_multipliers > 0) & (limits.upper - x < SNAP_DISTANCE)
    if not (at_lower.any() or at_upper.any()):
        return x, fun
    snapped = np.where(at_lower, limits.lower, np.where(at_upper, limits.upper, x))
    snapped_fun = float(nlp.objective_and_gradient(snapped, parameters)[0])
    return (snapped, snapped_fun) if snapped_fun <= fun else (x, fun)
