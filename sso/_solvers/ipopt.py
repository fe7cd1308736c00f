"""IPOPT through CasADi's ``nlpsol``, with the exact Hessian of the residual error."""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from sso._interrupts import raised_after_native_call
from sso._record import built
from sso._solvers.run import RunLimits, RunOutcome

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
BOUND_ONLY_OPTIONS = {"fast_step_computation": "yes"}
"""IPOPT's options on a problem with bounds only (a shaft series' angles): its step
system of a few variables is solved without a residual check and iterative
refinement. On the paper's three exact-model cases it takes the same iterations (9, 8,
11), each about 12 % cheaper; on 250 random shaft series (3 to 6 joints, options 1 to
3) the same iterations to within one in the mean, the answers moving by round-off."""
ACTIVE_DISTANCE = 1e-2
"""Largest distance (NLP units: rad for a shaft series) from a bound whose multiplier
pushes against it at which IPOPT's answer is moved onto that bound (see
:func:`_onto_active_bounds`)."""


def solve(nlp: Any, start: np.ndarray, parameters: np.ndarray, limits: RunLimits,
          solver_tol: float, max_iterations: int) -> RunOutcome:
    """:meth:`sso._solvers.run.Backend.solve` by IPOPT: ``solver_tol`` is its ``tol`` (scaled
    NLP error), ``max_iterations`` its ``max_iter``."""
    options: dict[str, Any] = {"tol": solver_tol, "max_iter": max_iterations}
    if limits.constrained:
        # IPOPT's default accepts a constraint violation of 1e-4 at convergence.
        options["constr_viol_tol"] = solver_tol
    else:
        options.update(BOUND_ONLY_OPTIONS)
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
    x = answer["x"]
    fun = float(answer["f"][0])
    iterations, evaluations = int(stats.get("iter_count", 0)), int(stats.get("n_call_nlp_f", 0))
    gradients = int(stats.get("n_call_nlp_grad_f", 0))
    if not limits.constrained:
        x, fun, more = _onto_active_bounds(nlp, solver, x, fun,
                                           answer["lam_x"],
                                           parameters, limits)
        iterations, evaluations, gradients = (iterations + more[0], evaluations + more[1],
                                              gradients + more[2])
    elapsed = time.perf_counter() - started
    return built(
        RunOutcome,
        x=x,
        fun=fun,
        nit=iterations,
        nfev=evaluations,
        njev=gradients,
        status=RETURN_STATUS_CODES.get(return_status, UNKNOWN_STATUS),
        success=bool(stats.get("success", False)),
        message=return_status,
        time_s=elapsed,
    )


def _onto_active_bounds(
    nlp: Any,
    solver: Any,
    x: np.ndarray,
    fun: float,
    bound_multipliers: np.ndarray,
    parameters: np.ndarray,
    limits: RunLimits,
) -> tuple[np.ndarray, float, tuple[int, int, int]]:
    """Move variables whose bound is active onto it (bound-only problems); the point,
    its objective and the iterations, objective and gradient evaluations it cost.

    An interior-point method stops short of an active bound: a barrier's width, and
    much further where the objective is flat along the bound. A bound is taken as
    active when its multiplier pushes against it (CasADi's ``lam_x``: negative at a
    lower bound, positive at an upper one) and the variable lies within
    :data:`ACTIVE_DISTANCE`. Those variables are put onto their bounds; where that
    alone is worse (the others must move with them: two phases in a narrow valley
    that ends on a phase bound stopped 5e-4 rad off it, RE 1.9e-4 relative above the
    corner's), IPOPT solves again from there with them held on their bounds. The new
    point is kept only if it is no worse.
    """
    lower, upper = limits.lower, limits.upper
    # On plain floats: the vectors are short, and each numpy operation costs more than its
    # arithmetic (most answers have no such variable).
    entries = list(zip(bound_multipliers.tolist(), x.tolist(), lower.tolist(), upper.tolist(),
                       strict=True))
    lower_active = [multiplier < 0.0 and value - bottom < ACTIVE_DISTANCE and value != bottom
                    for multiplier, value, bottom, _ in entries]
    upper_active = [multiplier > 0.0 and top - value < ACTIVE_DISTANCE and value != top
                    for multiplier, value, _, top in entries]
    if not (any(lower_active) or any(upper_active)):
        return x, fun, (0, 0, 0)
    at_lower, at_upper = np.array(lower_active), np.array(upper_active)
    snapped = np.where(at_lower, lower, np.where(at_upper, upper, x))
    snapped_fun = float(nlp.objective_and_gradient(snapped, parameters)[0])
    if snapped_fun <= fun:
        return snapped, snapped_fun, (0, 1, 0)
    held = at_lower | at_upper
    try:
        with raised_after_native_call():
            answer = solver(x0=snapped, p=parameters, lbx=np.where(held, snapped, lower),
                            ubx=np.where(held, snapped, upper))
    except RuntimeError:
        return x, fun, (0, 1, 0)
    stats = solver.stats()
    cost = (int(stats.get("iter_count", 0)), 1 + int(stats.get("n_call_nlp_f", 0)),
            int(stats.get("n_call_nlp_grad_f", 0)))
    polished = np.clip(answer["x"], lower, upper)
    polished_fun = float(nlp.objective_and_gradient(polished, parameters)[0])
    if stats.get("success", False) and polished_fun <= fun:
        return polished, polished_fun, cost
    return x, fun, cost
