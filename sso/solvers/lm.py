"""A single-design bounded Levenberg-Marquardt on two residuals, in plain Python floats.

Minimises ``f(x) = r_1(x)^2 + r_2(x)^2`` under box bounds, where the problem
supplies the two residuals and their Jacobian (a shaft series of the exact model:
:func:`sso.kinematics.hooke_matrix.residuals_and_jacobian_floats`). With two
residuals and ``k`` variables the damped Gauss-Newton step

    dx = -(J^T J + mu I)^-1 J^T r = -J^T (J J^T + mu I)^-1 r

(the push-through identity) needs one 2x2 solve whatever ``k`` is, so a whole
iteration is a few dozen float operations on top of one residual-and-Jacobian
call. For one design of a few joints that is several times cheaper than any numpy
or CasADi call (whose fixed overhead per call exceeds the arithmetic): this
solver exists for single solves, :func:`sso.solvers.least_squares.batch_least_squares`
for many at once. The method is the batched one's (projected active-set LM,
Nielsen's damping rule, Newton steps from differences of the gradient when it
converges slowly to a nonzero residual), on one design.

Its answer goes through the same measure as every other solver
(:mod:`sso.solvers.multistart`): the stopping test here is the same projected
gradient, of ``f``, per unit of ``x``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from sso.solvers.run import RunLimits, RunOutcome

Residuals = Callable[[list[float]], tuple[float, float, list[float], list[float]]]

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
        The problem; its ``residuals_and_jacobian(x, parameters)`` gives
        ``(r1, r2, row1, row2)`` in floats (a problem without it fails the run).
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
    residuals = getattr(nlp, "residuals_and_jacobian", None)
    if residuals is None or limits.constrained:
        return RunOutcome(np.array(start, dtype=float), float("nan"), 0, 0, 0, -3, False,
                          "lm needs a bound-constrained problem with two residuals",
                          time.perf_counter() - started)
    fixed = [float(value) for value in parameters]
    x, fun, nit, nfev, status = minimise(
        lambda point: residuals(point, fixed), [float(value) for value in start],
        [float(value) for value in limits.lower], [float(value) for value in limits.upper],
        solver_tol, max_iterations)
    return RunOutcome(np.array(x), fun, nit, nfev, nfev, status, status > 0, MESSAGES[status],
                      time.perf_counter() - started)


def minimise(residuals: Residuals, start: list[float], lower: list[float], upper: list[float],
             tolerance: float, max_iterations: int) -> tuple[list[float], float, int, int, int]:
    """Minimise ``r1^2 + r2^2`` under bounds from ``start``.

    Returns
    -------
    x, fun, nit, nfev, status
        Final point, sum of squares, trial steps, residual evaluations and a key of
        :data:`MESSAGES`.
    """
    size = len(start)
    x = [min(max(value, low), high) for value, low, high in zip(start, lower, upper, strict=True)]
    r1, r2, row1, row2 = residuals(x)
    nfev = 1
    fun = r1 * r1 + r2 * r2
    damping, growth = _INITIAL_DAMPING, 2.0
    newton = False
    previous_norm = math.inf
    slow_steps = 0
    for nit in range(max_iterations):
        if not (math.isfinite(fun) and all(map(math.isfinite, row1))
                and all(map(math.isfinite, row2))):
            return x, fun, nit, nfev, -2
        gradient = [2.0 * (a * r1 + b * r2) for a, b in zip(row1, row2, strict=True)]
        free = [upper[i] > lower[i]
                and not (x[i] <= lower[i] and gradient[i] > 0.0)
                and not (x[i] >= upper[i] and gradient[i] < 0.0) for i in range(size)]
        norm = max((abs(x[i] - min(max(x[i] - gradient[i], lower[i]), upper[i]))
                    for i in range(size)), default=0.0)
        if norm <= tolerance:
            return x, fun, nit, nfev, 1
        if fun <= _ZERO_RESIDUAL:
            return x, fun, nit, nfev, 4
        if newton:
            step, predicted = _newton_step(residuals, x, gradient, free, damping)
            nfev += sum(free)
        else:
            step, predicted = _gauss_newton_step(r1, r2, row1, row2, free, damping)
        trial = [min(max(x[i] + step[i], lower[i]), upper[i]) for i in range(size)]
        if max(abs(t - v) for t, v in zip(trial, x, strict=True)) <= _ROUND_OFF * (
                1.0 + max(abs(v) for v in x)):
            return x, fun, nit, nfev, 3
        if not newton:
            # The model's decrease for the projected step actually taken.
            model1 = r1 + sum(a * (t - v) for a, t, v in zip(row1, trial, x, strict=True))
            model2 = r2 + sum(b * (t - v) for b, t, v in zip(row2, trial, x, strict=True))
            predicted = fun - (model1 * model1 + model2 * model2)
        t1, t2, trial_row1, trial_row2 = residuals(trial)
        nfev += 1
        trial_fun = t1 * t1 + t2 * t2
        actual = fun - trial_fun
        if predicted > 0.0 and actual >= _ACCEPT_RATIO * predicted:
            ratio = actual / predicted
            damping *= max(1.0 / 3.0, 1.0 - (2.0 * ratio - 1.0) ** 3)
            growth = 2.0
            if abs(actual) <= _ROUND_OFF * fun and predicted <= _ROUND_OFF * fun:
                x, fun, r1, r2, row1, row2 = trial, trial_fun, t1, t2, trial_row1, trial_row2
                return x, fun, nit + 1, nfev, 2
            x, fun, r1, r2, row1, row2 = trial, trial_fun, t1, t2, trial_row1, trial_row2
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


def _gauss_newton_step(r1: float, r2: float, row1: list[float], row2: list[float],
                       free: list[bool], damping: float) -> tuple[list[float], float]:
    """``-J^T (J J^T + mu I)^-1 r`` over the free variables, ``mu = damping * trace / 2``."""
    a11 = a12 = a22 = 0.0
    for a, b, is_free in zip(row1, row2, free, strict=True):
        if is_free:
            a11 += a * a
            a12 += a * b
            a22 += b * b
    mu = damping * max(0.5 * (a11 + a22), 1e-30)
    a11 += mu
    a22 += mu
    determinant = a11 * a22 - a12 * a12
    y1 = (a22 * r1 - a12 * r2) / determinant
    y2 = (a11 * r2 - a12 * r1) / determinant
    return [-(a * y1 + b * y2) if is_free else 0.0
            for a, b, is_free in zip(row1, row2, free, strict=True)], 0.0


def _newton_step(residuals: Residuals, x: list[float], gradient: list[float], free: list[bool],
                 damping: float) -> tuple[list[float], float]:
    """Damped Newton step on the free variables, Hessian from forward differences of the gradient.

    The Hessian is shifted by ``damping`` times its largest diagonal magnitude, and
    further until its Cholesky factorisation succeeds (positive definite); returns
    the step and the decrease the quadratic model predicts for it. Plain floats:
    the free variables are few, and a numpy call costs more than this arithmetic.
    """
    index = [i for i, is_free in enumerate(free) if is_free]
    size = len(index)
    hessian = [[0.0] * size for _ in range(size)]
    for column, i in enumerate(index):
        ahead = list(x)
        ahead[i] += _HESSIAN_STEP
        a1, a2, a_row1, a_row2 = residuals(ahead)
        for row, j in enumerate(index):
            hessian[row][column] = (2.0 * (a_row1[j] * a1 + a_row2[j] * a2)
                                    - gradient[j]) / _HESSIAN_STEP
    step = [0.0] * len(x)
    values = [value for row in hessian for value in row]
    if not index or not all(map(math.isfinite, values)):
        return step, 0.0
    hessian = [[0.5 * (hessian[r][c] + hessian[c][r]) for c in range(size)] for r in range(size)]
    g = [gradient[i] for i in index]
    scale = max(max(abs(value) for value in values), 1e-30)
    shift = damping * scale
    factor = _cholesky(hessian, shift)
    if factor is None:
        # Indefinite (near a saddle): shift just past the most negative eigenvalue,
        # so the step is long along the direction of negative curvature (Moré and
        # Sorensen); a rejected step raises ``damping`` and shortens it.
        smallest = float(np.linalg.eigvalsh(np.array(hessian))[0])
        shift = 1.01 * max(-smallest, 0.0) + max(damping, 1e-8) * scale
        factor = _cholesky(hessian, shift)
    while factor is None:
        shift = max(10.0 * shift, 1e-6 * scale)
        factor = _cholesky(hessian, shift)
    # Solve L L^T d = -g.
    forward = [0.0] * size
    for r in range(size):
        forward[r] = (-g[r] - sum(factor[r][c] * forward[c] for c in range(r))) / factor[r][r]
    free_step = [0.0] * size
    for r in range(size - 1, -1, -1):
        free_step[r] = ((forward[r] - sum(factor[c][r] * free_step[c] for c in range(r + 1, size)))
                        / factor[r][r])
    for position, i in enumerate(index):
        step[i] = free_step[position]
    curvature = sum(free_step[r] * hessian[r][c] * free_step[c]
                    for r in range(size) for c in range(size))
    predicted = -(sum(a * b for a, b in zip(g, free_step, strict=True)) + 0.5 * curvature)
    return step, predicted


def _cholesky(matrix: list[list[float]], shift: float) -> list[list[float]] | None:
    """Lower Cholesky factor of ``matrix + shift I``, or None if it is not positive definite."""
    size = len(matrix)
    factor = [[0.0] * size for _ in range(size)]
    for r in range(size):
        for c in range(r + 1):
            total = matrix[r][c] + (shift if r == c else 0.0)
            total -= sum(factor[r][k] * factor[c][k] for k in range(c))
            if r == c:
                if not total > 0.0:
                    return None
                factor[r][r] = math.sqrt(total)
            else:
                factor[r][c] = total / factor[c][c]
    return factor
