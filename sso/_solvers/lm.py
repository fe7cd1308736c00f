"""A single-design bounded Levenberg-Marquardt on two residuals.

Minimises ``f(x) = r_1(x)^2 + r_2(x)^2 = |rho(x)|^2`` under box bounds, where the
problem supplies the two residuals as one complex number ``rho`` (``r_1 - i r_2``
for a shaft series; the sign of a residual does not matter to least squares) and
its Jacobian as one complex number per variable (a shaft series of the exact
model: :func:`sso._kinematics.hooke_matrix.residual_and_jacobian_complex`). With two
residuals and ``k`` variables the damped Gauss-Newton step

    dx = -(J^T J + mu I)^-1 J^T r = -J^T (J J^T + mu I)^-1 r

(the push-through identity) needs one 2x2 solve whatever ``k`` is, so a whole
iteration is a few dozen float operations on top of one residual-and-Jacobian
call. The method is a projected active-set Levenberg-Marquardt (Nielsen's damping
rule, scaled by ``|r| / |r_0|``, Newton steps when it converges slowly to a nonzero
residual); :mod:`sso._solvers.lm_rules` states it.

Where the problem gives its residuals as a CasADi expression (``nlp.residuals``),
the iterations run compiled, in blocks (:mod:`sso._solvers.lm_kernel`): in Python
every operation costs the interpreter tens of nanoseconds, and an iteration cost
more than the whole block does in CasADi's virtual machine. A shape solved
:data:`NATIVE_AFTER` times in a process runs the same instructions compiled to machine
code (:mod:`sso._solvers.lm_native`, one call per solve, Newton steps included), which
ends every solve bit for bit where the kernels end it. The loop below runs the
same rules in plain Python numbers; it takes the Newton steps the kernel does not
take (with the problem's closed-form Hessian, ``nlp.objective_hessian``, or
differences of the gradient) and runs alone for a problem without the expression.

Its answer goes through the same measure as every other solver
(:mod:`sso._solvers.multistart`): the stopping test here is the same projected
gradient, of ``f``, per unit of ``x``.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from sso._solvers import round_off_stops
from sso._solvers.lm_kernel import (
    NEWTON_KERNEL_VARIABLES,
    SWITCH_VARIABLE,
    flat_outcome,
    kernel_of,
    newton_kernel_of,
    run_kernel_flat,
    run_newton_kernel,
    unpack,
)
from sso._solvers.lm_rules import (
    NEWTON,
    NEWTON_INDEFINITE,
    PYTHON,
    RUNNING,
    fresh_state,
    gauss_newton_iteration,
    newton_iteration,
)
from sso._solvers.run import RunLimits, RunOutcome

Residual = Callable[[list[float]], tuple[complex, list[complex]]]
Hessian = Callable[[list[float]], list[list[float]]]

TESTS_ITS_START = True
"""Its first step stops at a start already at a minimum (round-off zero, or a projected
gradient under the tolerance), for the cost of one evaluation: no check before it."""

MESSAGES = {
    -2: "residual or Jacobian is not finite",
    -1: "no decrease possible (damping overflow) before the tolerance was met",
    0: "iteration limit reached",
    1: "projected gradient below the tolerance",
    2: "actual and predicted relative reductions at round-off",
    3: "step at round-off",
    4: "sum of squares at round-off zero",
    -4: "stopped at round-off, but a move of one variable lowers the sum of squares "
        "(not a minimum: the problem is beyond floating point's resolution there)",
}
ROUND_OFF_STOPS = (2, 3)
"""Statuses that stop because a step or a reduction reached round-off. Far from a
minimum, where the residuals change by more than their size within a rounding of
``x`` (a chain of near-90-deg joints), they come from a damping grown by steps the
linear model mispredicts, not from a minimum: :func:`_round_off_stop_holds` tests
each such stop directly."""
PROBE_STEPS = (1e-9, 1e-6, 1e-3)
"""Moves of one variable (NLP units, rad for a shaft series) tried at a round-off stop."""
PROBE_DECREASE = 1e-6
"""A probe that lowers the sum of squares by more than this fraction refutes the stop."""
NATIVE_AFTER = 64
"""Solves of one shape (in one thread) after which it runs compiled to machine code: the
library's build (1 to 3 s, once per machine and version of the code, kept in a cache
folder) or its load (the hash of the package, about 50 ms) costs more than a few dozen
solves gain, so a shape solved once or by one default call (eight screened starts) never
pays it."""
# Forward differences: truncation ~ step, round-off ~ eps / step; 1e-7 balances them
# well enough for Newton's superlinear convergence.
_HESSIAN_STEP = 1e-7


def solve(
    nlp: Any,
    start: np.ndarray,
    parameters: np.ndarray,
    limits: RunLimits,
    solver_tol: float,
    max_iterations: int,
) -> RunOutcome:
    """Run the bounded Levenberg-Marquardt once from ``start``; failures come back in the outcome.

    Parameters
    ----------
    nlp : sso._solvers.nlp.CompiledNLP
        The problem; its ``residuals_and_jacobian(x, parameters)`` gives ``(rho,
        jacobian)`` in Python complex numbers (a problem without it fails the run).
    start, parameters : numpy.ndarray
        Start of the design vector and the fixed parameters (NLP units).
    limits : RunLimits
        Bounds of the design vector (constraint functions are not supported).
    solver_tol : float
        Stop when the projected gradient of ``f`` (infinity norm) is at most this.
    max_iterations : int
        Trial steps, at most.
    """
    started = time.perf_counter()
    if getattr(nlp, "residuals_and_jacobian", None) is None or limits.constrained:
        return RunOutcome(np.array(start, dtype=float), float("nan"), 0, 0, 0, -3, False,
                          "lm needs a bound-constrained problem with two residuals",
                          time.perf_counter() - started)
    x, fun, nit, nfev, status = solve_floats(nlp, start.tolist(), parameters.tolist(),
                                             limits.lower.tolist(), limits.upper.tolist(),
                                             solver_tol, max_iterations)
    return RunOutcome(np.array(x), fun, nit, nfev, nfev, status, status > 0, MESSAGES[status],
                      time.perf_counter() - started)


def solve_floats(nlp: Any, start: list[float], fixed: list[float], lower: list[float],
                 upper: list[float], solver_tol: float, max_iterations: int
                 ) -> tuple[list[float], float, int, int, int]:
    """:func:`solve` on lists of floats, for a problem with residuals and bounds only.

    Returns
    -------
    x, fun, nit, nfev, status
        Final point, sum of squares, trial steps, residual evaluations and a key of
        :data:`MESSAGES` (the run succeeded where it is positive).
    """
    return _solve_floats(nlp, start, fixed, lower, upper, solver_tol, max_iterations, False)[0]


def solve_floats_measured(nlp: Any, start: list[float], fixed: list[float], lower: list[float],
                          upper: list[float], solver_tol: float, max_iterations: int
                          ) -> tuple[tuple[list[float], float, int, int, int], list[float] | None]:
    """:func:`solve_floats`, and where the shape's library compiled to machine code ran the
    whole solve (:func:`native_of`), its measure of the end in the same call: the point
    put onto the bounds, the objective and the projected gradient's norm there (bit for
    bit :func:`sso._solvers.multistart.measure_on_bounds`), and 0.0 where it found no
    negative curvature there as :func:`sso._solvers.saddle.saddle_direction` would, else
    1.0, one list (:meth:`sso._solvers.lm_native.OneDesign.solve_measured`); None where it
    did not run the whole solve.
    """
    return _solve_floats(nlp, start, fixed, lower, upper, solver_tol, max_iterations, True)


def _solve_floats(nlp: Any, start: list[float], fixed: list[float], lower: list[float],
                  upper: list[float], solver_tol: float, max_iterations: int, measured: bool
                  ) -> tuple[tuple[list[float], float, int, int, int], list[float] | None]:
    residual = nlp.residuals_and_jacobian
    state = None
    native = native_of(nlp)
    kernel = None if native is not None else kernel_of(nlp)
    if native is not None:
        problem = [*fixed, *lower, *upper, solver_tol, float(max_iterations)]
        if measured:
            ended, measure = native.solve_measured(start, problem)
        else:
            ended, measure = flat_outcome(native.solve(start, problem), len(lower)), None
        x, fun, nit, nfev, status = ended
        if status != NEWTON_INDEFINITE:
            return _checked(residual, fixed, x, fun, nit, nfev, status, lower, upper), measure
        state = unpack(native.state(), len(lower))
    elif kernel is not None:
        values = run_kernel_flat(kernel, start, fixed, lower, upper, solver_tol,
                                 max_iterations)
        x, fun, nit, nfev, status = flat_outcome(values, len(lower))
        if status not in (RUNNING, NEWTON):
            return _checked(residual, fixed, x, fun, nit, nfev, status, lower, upper), None
        state = unpack(values, len(lower))
    objective_hessian = getattr(nlp, "objective_hessian", None)
    newton_kernel = (newton_kernel_of(nlp)
                     if state is not None and state["status"] in (NEWTON, NEWTON_INDEFINITE)
                     else None)
    x, fun, nit, nfev, status = minimise(
        lambda point: residual(point, fixed), start, lower, upper, solver_tol,
        max_iterations,
        None if objective_hessian is None else lambda point: objective_hessian(point, fixed),
        state,
        None if newton_kernel is None else lambda given: run_newton_kernel(
            newton_kernel, given, fixed, lower, upper, solver_tol, max_iterations))
    return _checked(residual, fixed, x, fun, nit, nfev, status, lower, upper), None


def native_of(nlp: Any) -> Any:
    """The shape's library compiled to machine code (:mod:`sso._solvers.lm_native`), called
    one design at a time in this thread (:class:`sso._solvers.lm_native.OneDesign`), once
    this thread has solved the shape :data:`NATIVE_AFTER` times; None before, for a
    problem without one (no ``nlp.lm_shape``, too many variables, no compiler) and while
    ``SSO_NATIVE_LM=0`` (:data:`sso._solvers.lm_kernel.SWITCH_VARIABLE`) is in the
    environment (read until the library is loaded; a shape loaded keeps it).

    Each design ends there bit for bit where the compiled kernels end it (the Newton
    kernel built); only a shape's first solves, whose Newton steps the Python loop takes
    before that kernel is built, may end differently in the last digits.
    """
    native = nlp.lm_native
    if native is None:
        if nlp.lm_shape is None:
            return None
        nlp.lm_solves += 1
        if nlp.lm_solves < NATIVE_AFTER or os.environ.get(SWITCH_VARIABLE, "1").strip() == "0":
            return None
        from sso._solvers.lm_native import OneDesign, native_solver_of

        solver = native_solver_of(nlp.lm_shape, int(nlp.symbols["x"].numel()), lambda: nlp,
                                  NEWTON_KERNEL_VARIABLES)
        native = nlp.lm_native = False if solver is None else OneDesign(solver, *nlp.lm_shape)
    return native or None


def gauss_newton_flat(nlp: Any, kernel: Any, start: list[float], fixed: list[float],
                      lower: list[float], upper: list[float], solver_tol: float,
                      max_iterations: int) -> list[float]:
    """The start and Gauss-Newton steps of the rules from ``start``, as the flat state of
    :func:`sso._solvers.lm_kernel.run_kernel_flat` (read with
    :func:`sso._solvers.lm_kernel.flat_outcome`): by the shape's library compiled to machine
    code once :func:`native_of` has loaded it, else by ``kernel``'s blocks (``kernel_of(nlp)``);
    the same bits either way, whatever ran before."""
    native = nlp.lm_native
    if native:
        ended: list[float] = native.solve(
            start, [*fixed, *lower, *upper, solver_tol, float(max_iterations)],
            gauss_newton_only=True)
        return ended
    return run_kernel_flat(kernel, start, fixed, lower, upper, solver_tol, max_iterations)


def _checked(residual: Any, fixed: list[float], x: list[float], fun: float, nit: int,
             nfev: int, status: int, lower: list[float], upper: list[float]
             ) -> tuple[list[float], float, int, int, int]:
    """The outcome of a solve, a stop at round-off tested first: a minimum, or only a
    vanished step (:mod:`sso._solvers.round_off_stops`)?"""
    if status in round_off_stops.ROUND_OFF_STOPS:
        holds, probes = round_off_stops.holds(lambda point: abs(residual(point, fixed)[0]) ** 2,
                                              list(x), fun, lower, upper)
        nfev += probes
        status = status if holds else round_off_stops.REFUTED
    return x, fun, nit, nfev, status


def minimise(residual: Residual, start: list[float], lower: list[float], upper: list[float],
             tolerance: float, max_iterations: int, hessian: Hessian | None = None,
             state: dict[str, Any] | None = None,
             newton_kernel: Callable[[dict[str, Any]], dict[str, Any]] | None = None
             ) -> tuple[list[float], float, int, int, int]:
    """Minimise ``|rho|^2`` under bounds from ``start`` by the rules in plain Python floats.

    ``hessian(x)``, when given, is the exact Hessian of ``|rho|^2`` for the Newton
    steps (one call, counted as one evaluation); without it they difference the
    gradient (one residual call per free variable). ``state``, when given, is
    where the compiled kernel (:mod:`sso._solvers.lm_kernel`) left the solve: the
    loop continues from it (and ``start`` is not used). ``newton_kernel``, when
    given, takes the Newton steps from a state (compiled, :mod:`sso._solvers.lm_kernel`);
    the loop takes only those it hands back (a Hessian that the damping's shift leaves
    indefinite), one at a time.

    Returns
    -------
    x, fun, nit, nfev, status
        Final point, sum of squares, trial steps, residual evaluations and a key of
        :data:`MESSAGES`.
    """
    def evaluate(point: list[Any]) -> tuple[Any, Any, list[Any], list[Any]]:
        rho, jacobian = residual(point)
        # rho = r1 - i r2 (the sign of a residual does not matter to least squares).
        return (rho.real, -rho.imag, [entry.real for entry in jacobian],
                [-entry.imag for entry in jacobian])

    current = (fresh_state(PYTHON, evaluate, start, lower, upper) if state is None
               else dict(state))
    while current["status"] == RUNNING:
        current = gauss_newton_iteration(PYTHON, evaluate, current, lower, upper, tolerance,
                                         max_iterations)
    hessian_at = _hessian_of(residual, hessian)
    while current["status"] in (NEWTON, NEWTON_INDEFINITE):
        if current["status"] == NEWTON and newton_kernel is not None:
            current = newton_kernel(current)
            continue
        current["status"] = NEWTON
        current = newton_iteration(PYTHON, evaluate, hessian_at, current, lower, upper,
                                   tolerance, max_iterations)
    return (current["x"], current["fun"], int(current["nit"]), int(current["nfev"]),
            int(current["status"]))


def _hessian_of(residual: Residual, hessian: Hessian | None) -> Any:
    """The Newton steps' Hessian: the closed form, or forward differences of the gradient
    over the free variables; computed once per point (a rejected step keeps the point)."""
    last: list[Any] = [None, None]

    def at(point: list[float], gradient: list[float], free: list[bool], needed: bool
           ) -> tuple[list[list[float]], int]:
        size = len(point)
        evaluations = 1 if hessian is not None else sum(free)
        if not needed:
            return [[0.0] * size for _ in range(size)], evaluations
        if last[0] != point:
            last[0] = list(point)
            last[1] = (hessian(point) if hessian is not None
                       else _difference_hessian(residual, point, gradient, free))
        return last[1], evaluations

    return at


def _difference_hessian(residual: Residual, x: list[float], gradient: list[float],
                        free: list[bool]) -> list[list[float]]:
    """The Hessian of ``f`` over the free variables (zero elsewhere) by forward differences
    of the gradient (one residual-and-Jacobian call per free variable)."""
    size = len(x)
    hessian = [[0.0] * size for _ in range(size)]
    for i in (index for index, is_free in enumerate(free) if is_free):
        ahead = list(x)
        ahead[i] += _HESSIAN_STEP
        ahead_rho, ahead_jacobian = residual(ahead)
        r1, r2 = 2.0 * ahead_rho.real, 2.0 * ahead_rho.imag
        for j in (index for index, is_free in enumerate(free) if is_free):
            entry = ahead_jacobian[j]
            hessian[j][i] = (r1 * entry.real + r2 * entry.imag - gradient[j]) / _HESSIAN_STEP
    return hessian
