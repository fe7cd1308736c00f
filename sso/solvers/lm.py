"""A single-design bounded Levenberg-Marquardt on two residuals.

Minimises ``f(x) = r_1(x)^2 + r_2(x)^2 = |rho(x)|^2`` under box bounds, where the
problem supplies the two residuals as one complex number ``rho`` (``r_1 - i r_2``
for a shaft series; the sign of a residual does not matter to least squares) and
its Jacobian as one complex number per variable (a shaft series of the exact
model: :func:`sso.kinematics.hooke_matrix.residual_and_jacobian_complex`). With two
residuals and ``k`` variables the damped Gauss-Newton step

    dx = -(J^T J + mu I)^-1 J^T r = -J^T (J J^T + mu I)^-1 r

(the push-through identity) needs one 2x2 solve whatever ``k`` is, so a whole
iteration is a few dozen float operations on top of one residual-and-Jacobian
call. This solver exists for single solves,
:func:`sso.solvers.least_squares.batch_least_squares` for many at once. The method
is the batched one's (projected active-set LM, Nielsen's damping rule, Newton
steps when it converges slowly to a nonzero residual), on one design, with one
difference: the damping is also scaled by ``|r| / |r_0|`` (over 1,500 random cases
of 2 to 7 joints this took 8 to 12 % fewer evaluations on options 2 and 3 and 1 %
fewer on option 1, with no answer worse).

Where the problem gives its residuals as a CasADi expression (``nlp.residuals``),
the Gauss-Newton iterations run compiled, in blocks (:mod:`sso.solvers.lm_kernel`):
in Python every operation costs the interpreter tens of nanoseconds, and an
iteration cost more than the whole block does in CasADi's virtual machine. The
loop below, in plain Python numbers, is the same algorithm; it takes over for the
Newton steps (with the problem's closed-form Hessian, ``nlp.objective_hessian``,
or differences of the gradient) and runs alone for a problem without the
expression.

Its answer goes through the same measure as every other solver
(:mod:`sso.solvers.multistart`): the stopping test here is the same projected
gradient, of ``f``, per unit of ``x``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping
from types import MappingProxyType
from typing import Any

import numpy as np

from sso.solvers.lm_kernel import NEWTON, RUNNING, KernelState, kernel_of, run_kernel
from sso.solvers.run import RunLimits, RunOutcome
from sso.solvers.small_matrices import cholesky

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
}
_ACCEPT_RATIO = 1e-4
_INITIAL_DAMPING = 1e-3
_MAX_DAMPING = 1e16
_ZERO_RESIDUAL = 1e-30
_ROUND_OFF = 4.0 * 2.0**-52
_SLOW_LEVEL = 1e-20
_SLOW_STEPS = 3
_NEWTON_DAMPING = 1e-8
# Forward differences: truncation ~ step, round-off ~ eps / step; 1e-7 balances them
# well enough for Newton's superlinear convergence.
_HESSIAN_STEP = 1e-7
KERNEL_CONSTANTS: Mapping[str, float] = MappingProxyType({
    "accept_ratio": _ACCEPT_RATIO, "initial_damping": _INITIAL_DAMPING,
    "max_damping": _MAX_DAMPING, "zero_residual": _ZERO_RESIDUAL, "round_off": _ROUND_OFF,
    "slow_level": _SLOW_LEVEL, "slow_steps": _SLOW_STEPS})
"""The loop's constants, shared with the compiled kernel that repeats its iterations."""


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
    nlp : sso.solvers.nlp.CompiledNLP
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
    residual = getattr(nlp, "residuals_and_jacobian", None)
    if residual is None or limits.constrained:
        return RunOutcome(np.array(start, dtype=float), float("nan"), 0, 0, 0, -3, False,
                          "lm needs a bound-constrained problem with two residuals",
                          time.perf_counter() - started)
    fixed = parameters.tolist()
    lower, upper = limits.lower.tolist(), limits.upper.tolist()
    objective_hessian = getattr(nlp, "objective_hessian", None)
    kernel = kernel_of(nlp, KERNEL_CONSTANTS)
    state = (None if kernel is None else
             run_kernel(kernel, start.tolist(), fixed, lower, upper, solver_tol, max_iterations))
    if state is not None and state.status not in (RUNNING, NEWTON):
        x, fun, nit, nfev, status = state.x, state.fun, state.nit, state.nfev, state.status
    else:
        x, fun, nit, nfev, status = minimise(
            lambda point: residual(point, fixed), start.tolist(), lower, upper, solver_tol,
            max_iterations,
            None if objective_hessian is None else lambda point: objective_hessian(point, fixed),
            state)
    return RunOutcome(np.array(x), fun, nit, nfev, nfev, status, status > 0, MESSAGES[status],
                      time.perf_counter() - started)


def minimise(residual: Residual, start: list[float], lower: list[float], upper: list[float],
             tolerance: float, max_iterations: int, hessian: Hessian | None = None,
             state: KernelState | None = None) -> tuple[list[float], float, int, int, int]:
    """Minimise ``|rho|^2`` under bounds from ``start``.

    ``hessian(x)``, when given, is the exact Hessian of ``|rho|^2`` for the Newton
    steps (one call, counted as one evaluation); without it they difference the
    gradient (one residual call per free variable). ``state``, when given, is
    where the compiled kernel (:mod:`sso.solvers.lm_kernel`) left the solve: the
    loop continues from it (and ``start`` is not used).

    Returns
    -------
    x, fun, nit, nfev, status
        Final point, sum of squares, trial steps, residual evaluations and a key of
        :data:`MESSAGES`.
    """
    span = range(len(start))
    if state is None:
        x = [min(max(start[i], lower[i]), upper[i]) for i in span]
        rho, jacobian = residual(x)
        nfev, done = 1, 0
        fun = rho.real * rho.real + rho.imag * rho.imag
        damping, growth = _INITIAL_DAMPING, 2.0
        newton = False
        previous_norm = math.inf
        slow_steps = 0
        first_size = max(abs(rho), 1e-300)
    else:
        x, rho, jacobian, fun = state.x, state.rho, state.jacobian, state.fun
        nfev, done = state.nfev, state.nit
        damping, growth = state.damping, state.growth
        # The kernel stops where the loop switches to Newton steps (damping 0).
        newton = state.status == NEWTON
        if newton:
            damping = 0.0
        previous_norm, slow_steps, first_size = (state.previous_norm, state.slow_steps,
                                                 state.first_size)
    # The Hessian at x in Newton mode: a rejected step leaves x, the gradient and the
    # free variables as they were, so it is reused, not recomputed.
    newton_hessian: tuple[list[int], list[list[float]]] | None = None
    for nit in range(done, max_iterations):
        # A NaN or infinity anywhere makes the sum non-finite.
        if not math.isfinite(fun + abs(sum(jacobian))):
            return x, fun, nit, nfev, -2
        # One pass: the gradient 2 J^T r, its projection on the bounds, the free
        # variables (off their bounds, or pulled inwards) and J J^T over them.
        r1, r2 = 2.0 * rho.real, 2.0 * rho.imag
        gradient = [0.0] * len(x)
        free = [False] * len(x)
        norm = a11 = a12 = a22 = 0.0
        for i in span:
            entry = jacobian[i]
            real, imaginary = entry.real, entry.imag
            slope = r1 * real + r2 * imaginary
            value, low, high = x[i], lower[i], upper[i]
            projected = value - slope
            projected = low if projected < low else high if projected > high else projected
            distance = abs(value - projected)
            if distance > norm:
                norm = distance
            gradient[i] = slope
            if (high > low and not (value <= low and slope > 0.0)
                    and not (value >= high and slope < 0.0)):
                free[i] = True
                a11 += real * real
                a12 += real * imaginary
                a22 += imaginary * imaginary
        if norm <= tolerance:
            return x, fun, nit, nfev, 1
        if fun <= _ZERO_RESIDUAL:
            return x, fun, nit, nfev, 4
        if newton:
            if newton_hessian is None:
                newton_hessian = (_difference_hessian(residual, x, gradient, free)
                                  if hessian is None else _free_block(hessian(x), free))
                nfev += len(newton_hessian[0]) if hessian is None else 1
            step, predicted = _newton_step(newton_hessian, len(x), gradient, damping)
        else:
            # -J^T (J J^T + mu I)^-1 r over the free variables. mu = damping * trace / 2,
            # scaled by |r| / |r_0| once the residual has fallen: damping in proportion
            # to |r| keeps the convergence to a zero residual quadratic (Fan and Yuan),
            # where a damping that only shrinks by 1/3 a step makes the last steps linear.
            mu = damping * max(0.5 * (a11 + a22), 1e-30) * min(1.0, abs(rho) / first_size)
            a11 += mu
            a22 += mu
            determinant = a11 * a22 - a12 * a12
            y1 = (a22 * rho.real - a12 * rho.imag) / determinant
            y2 = (a11 * rho.imag - a12 * rho.real) / determinant
            step = [-(entry.real * y1 + entry.imag * y2) if is_free else 0.0
                    for entry, is_free in zip(jacobian, free, strict=True)]
        # The trial point (projected onto the bounds) and the linear model's residual there.
        trial = [0.0] * len(x)
        largest_move = largest_value = 0.0
        model = rho
        for i in span:
            value = x[i]
            moved = value + step[i]
            moved = lower[i] if moved < lower[i] else upper[i] if moved > upper[i] else moved
            trial[i] = moved
            move = moved - value
            model += jacobian[i] * move
            if abs(move) > largest_move:
                largest_move = abs(move)
            if abs(value) > largest_value:
                largest_value = abs(value)
        if largest_move <= _ROUND_OFF * (1.0 + largest_value):
            return x, fun, nit, nfev, 3
        if not newton:
            # The linear model's decrease for the projected step actually taken.
            predicted = fun - (model.real * model.real + model.imag * model.imag)
        trial_rho, trial_jacobian = residual(trial)
        nfev += 1
        trial_fun = trial_rho.real * trial_rho.real + trial_rho.imag * trial_rho.imag
        actual = fun - trial_fun
        if predicted > 0.0 and actual >= _ACCEPT_RATIO * predicted:
            ratio = actual / predicted
            damping *= max(1.0 / 3.0, 1.0 - (2.0 * ratio - 1.0) ** 3)
            growth = 2.0
            at_round_off = abs(actual) <= _ROUND_OFF * fun and predicted <= _ROUND_OFF * fun
            x, fun, rho, jacobian = trial, trial_fun, trial_rho, trial_jacobian
            newton_hessian = None
            if at_round_off:
                return x, fun, nit + 1, nfev, 2
            # Gauss-Newton is only linear at a nonzero residual: take Newton steps once
            # the projected gradient has fallen by less than half in _SLOW_STEPS
            # accepted steps.
            slow_steps += fun > _SLOW_LEVEL and norm > 0.5 * previous_norm
            if not newton and slow_steps >= _SLOW_STEPS:
                # Plain Newton first (shifted only to be positive definite), so
                # convergence is quadratic; damping returns on a rejected step.
                newton, damping = True, 0.0
            previous_norm = norm
        else:
            if predicted <= _ROUND_OFF * fun and abs(actual) <= _ROUND_OFF * fun:
                return x, fun, nit + 1, nfev, 2
            damping = max(damping * growth, _NEWTON_DAMPING if newton else 0.0)
            growth *= 2.0
            if damping > _MAX_DAMPING:
                return x, fun, nit + 1, nfev, -1
    return x, fun, max_iterations, nfev, 0


def _difference_hessian(residual: Residual, x: list[float], gradient: list[float],
                        free: list[bool]) -> tuple[list[int], list[list[float]]]:
    """The free variables' indices and the Hessian of ``f`` over them, by forward
    differences of the gradient (one residual-and-Jacobian call per free variable)."""
    index = [i for i, is_free in enumerate(free) if is_free]
    size = len(index)
    hessian = [[0.0] * size for _ in range(size)]
    for column, i in enumerate(index):
        ahead = list(x)
        ahead[i] += _HESSIAN_STEP
        ahead_rho, ahead_jacobian = residual(ahead)
        r1, r2 = 2.0 * ahead_rho.real, 2.0 * ahead_rho.imag
        for row, j in enumerate(index):
            entry = ahead_jacobian[j]
            hessian[row][column] = (r1 * entry.real + r2 * entry.imag
                                    - gradient[j]) / _HESSIAN_STEP
    return index, hessian


def _free_block(hessian: list[list[float]], free: list[bool]
                ) -> tuple[list[int], list[list[float]]]:
    """The free variables' indices and the Hessian's block over them."""
    index = [i for i, is_free in enumerate(free) if is_free]
    return index, [[hessian[row][column] for column in index] for row in index]


def _newton_step(free_hessian: tuple[list[int], list[list[float]]], length: int,
                 gradient: list[float], damping: float) -> tuple[list[float], float]:
    """Damped Newton step on the free variables of ``free_hessian`` (their indices and the
    Hessian over them, from :func:`_difference_hessian` or :func:`_free_block`).

    The Hessian is shifted by ``damping`` times its largest entry magnitude, and
    further until its Cholesky factorisation succeeds (positive definite); returns
    the step (``length`` entries) and the decrease the quadratic model predicts for
    it. Plain floats: the free variables are few, and a numpy call costs more than
    this arithmetic.
    """
    index, hessian = free_hessian
    size = len(index)
    step = [0.0] * length
    values = [value for row in hessian for value in row]
    if not index or not all(map(math.isfinite, values)):
        return step, 0.0
    hessian = [[0.5 * (hessian[r][c] + hessian[c][r]) for c in range(size)] for r in range(size)]
    g = [gradient[i] for i in index]
    scale = max(max(map(abs, values)), 1e-30)
    shift = damping * scale
    factor = cholesky(hessian, shift)
    if factor is None:
        # Indefinite (near a saddle): shift just past the most negative eigenvalue,
        # so the step is long along the direction of negative curvature (Moré and
        # Sorensen); a rejected step raises ``damping`` and shortens it.
        smallest = float(np.linalg.eigvalsh(np.array(hessian))[0])
        shift = 1.01 * max(-smallest, 0.0) + max(damping, 1e-8) * scale
        factor = cholesky(hessian, shift)
    while factor is None:
        shift = max(10.0 * shift, 1e-6 * scale)
        factor = cholesky(hessian, shift)
    # Solve L L^T d = -g (forward, then back substitution).
    forward = [0.0] * size
    for r in range(size):
        total = -g[r]
        row = factor[r]
        for c in range(r):
            total -= row[c] * forward[c]
        forward[r] = total / row[r]
    free_step = [0.0] * size
    for r in range(size - 1, -1, -1):
        total = forward[r]
        for c in range(r + 1, size):
            total -= factor[c][r] * free_step[c]
        free_step[r] = total / factor[r][r]
    # The quadratic model's decrease: -(g.d + d.H.d / 2).
    linear = curvature = 0.0
    for r, i in enumerate(index):
        value = free_step[r]
        step[i] = value
        linear += g[r] * value
        row = hessian[r]
        for c in range(size):
            curvature += value * row[c] * free_step[c]
    return step, -(linear + 0.5 * curvature)
