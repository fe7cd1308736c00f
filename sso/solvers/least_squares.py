"""Batched, bound-constrained Levenberg-Marquardt: many small least-squares problems at once.

Minimises ``f(x) = |r(x)|^2`` for ``m`` independent problems of the same shape under
box bounds, as numpy array work: every iteration evaluates the residuals and
Jacobians of the problems still running in one call and solves their damped
normal equations with one batched ``numpy.linalg.solve``.

Why a projected, active-set Levenberg-Marquardt (and not a reflective or a
transformed one): the problems it serves are tiny (a few variables, two residuals
for a shaft series), their bounds are simple boxes, and their optima often lie on
a bound (the paper's option 2 optimum has two angles at bounds). A variable on a
bound whose gradient pushes outwards is held fixed for the step (the active set),
the other variables take the damped Gauss-Newton step, and the trial point is
projected onto the box, so every iterate is feasible and a bound that is active at
the solution is identified in finitely many steps, after which the method is plain
Levenberg-Marquardt on the free variables (quadratic convergence on zero-residual
problems). A reflective (Coleman-Li) method needs scaling matrices that change the
model at every step, more code for the same small problems; a transform such as
``x = lower + (upper - lower) sin^2 z`` makes the derivative vanish on a bound, so
a bound-active optimum is approached only linearly.

Each step is accepted when the actual decrease of ``f`` is at least ``1e-4`` of the
decrease the Gauss-Newton model predicts for the projected step; the damping
follows Nielsen's rule. The damping matrix is ``lambda * diag(s)``, with ``s`` the
running maximum of the diagonal of ``J^T J`` (Moré's scaling), floored so the
matrix stays positive definite.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

ResidualFunction = Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]

STATUS_MESSAGES = {
    -2: "residual or Jacobian is not finite",
    -1: "no decrease possible (damping overflow) before the tolerances were met",
    0: "iteration limit reached",
    1: "projected gradient below gtol",
    2: "actual and predicted relative reductions below ftol",
    3: "relative step below xtol",
    4: "sum of squares below fatol",
}
SUCCESS_STATUSES = (1, 2, 3, 4)
_ACCEPT_RATIO = 1e-4
_INITIAL_DAMPING = 1e-3
_MIN_DAMPING = 1e-15
_MAX_DAMPING = 1e16
_SCALE_FLOOR = 1e-30


@dataclass(frozen=True)
class BatchLeastSquaresResult:
    """Outcome of every problem of a batch, as arrays named after ``OptimizeResult``.

    Attributes
    ----------
    x : numpy.ndarray of shape (m, p)
        Final point of each problem (inside its bounds).
    fun : numpy.ndarray of shape (m,)
        Sum of squared residuals ``|r(x)|^2`` there.
    projected_gradient : numpy.ndarray of shape (m,)
        Infinity norm of the gradient of ``fun`` with the components that push a
        variable out through an active bound removed (0 at a bound-constrained
        stationary point).
    nit : numpy.ndarray of shape (m,)
        Iterations (trial steps) of each problem.
    nfev : numpy.ndarray of shape (m,)
        Residual-and-Jacobian evaluations of each problem.
    status : numpy.ndarray of shape (m,)
        Reason for stopping, a key of :data:`STATUS_MESSAGES`.
    success : numpy.ndarray of shape (m,)
        True for statuses 1 to 4.
    """

    x: np.ndarray
    fun: np.ndarray
    projected_gradient: np.ndarray
    nit: np.ndarray
    nfev: np.ndarray
    status: np.ndarray
    success: np.ndarray

    @property
    def message(self) -> tuple[str, ...]:
        """The stopping reason of each problem in words."""
        return tuple(STATUS_MESSAGES[int(code)] for code in self.status)


def batch_least_squares(
    residual_and_jacobian: ResidualFunction,
    x0: Any,
    lower: Any,
    upper: Any,
    *,
    gtol: float = 1e-12,
    fatol: float = 1e-30,
    ftol: float = 1e-15,
    xtol: float = 1e-15,
    max_iterations: int = 200,
) -> BatchLeastSquaresResult:
    """Minimise ``|r(x)|^2`` under ``lower <= x <= upper`` for ``m`` problems at once.

    Parameters
    ----------
    residual_and_jacobian : callable
        ``f(x, rows) -> (r, J)`` for points ``x`` of shape ``(k, p)`` of the
        problems ``rows`` (indices into the batch, so per-problem parameters can be
        looked up): residuals of shape ``(k, q)`` and Jacobian of shape
        ``(k, q, p)``. It is called with the problems still running.
    x0 : array of shape (m, p)
        Starts; moved onto the bounds where they lie outside.
    lower, upper : array broadcastable to (m, p)
        Bounds (equal bounds pin a variable).
    gtol : float
        Stop when the projected gradient's infinity norm is at most ``gtol``.
    fatol : float
        Stop when the sum of squares is at most ``fatol``.
    ftol : float
        Stop when a trial step's actual and predicted decreases are both at most
        ``ftol`` times the sum of squares (Moré's test): the model can no longer
        distinguish a decrease from round-off, as at a minimum with nonzero
        residuals, where ``gtol`` may lie below what round-off lets the gradient reach.
    xtol : float
        Stop when an accepted step's infinity norm is at most
        ``xtol * (xtol + |x|_inf)``.
    max_iterations : int
        Trial steps per problem.

    Returns
    -------
    BatchLeastSquaresResult
        Per-problem results; failures are reported in ``status``, not raised.

    Raises
    ------
    ValueError
        If the shapes disagree or a bound is inverted or not finite.
    """
    x = np.array(x0, dtype=float, ndmin=2)
    if x.ndim != 2:
        raise ValueError(f"x0 has shape {x.shape}; expected (m, p)")
    lower_bound = np.broadcast_to(np.asarray(lower, dtype=float), x.shape).copy()
    upper_bound = np.broadcast_to(np.asarray(upper, dtype=float), x.shape).copy()
    if not (np.all(np.isfinite(lower_bound)) and np.all(np.isfinite(upper_bound))):
        raise ValueError("lower and upper bounds must be finite")
    if np.any(lower_bound > upper_bound):
        raise ValueError("a lower bound exceeds its upper bound")
    x = np.clip(x, lower_bound, upper_bound)
    count, size = x.shape

    residual, jacobian = (np.array(value, dtype=float) for value in residual_and_jacobian(x, np.arange(len(x))))
    cost = np.einsum("kq,kq->k", residual, residual)
    scale = np.maximum(np.einsum("kqp,kqp->kp", jacobian, jacobian), _SCALE_FLOOR)
    damping = np.full(count, _INITIAL_DAMPING)
    growth = np.full(count, 2.0)
    nit = np.zeros(count, dtype=int)
    nfev = np.ones(count, dtype=int)
    status = np.zeros(count, dtype=int)
    done = np.zeros(count, dtype=bool)
    gradient = np.einsum("kqp,kq->kp", jacobian, residual)

    finite = np.isfinite(cost) & np.all(np.isfinite(jacobian), axis=(1, 2))
    status[~finite] = -2
    done[~finite] = True
    identity = np.eye(size)

    for _ in range(max_iterations + 1):
        live = np.flatnonzero(~done)
        if live.size == 0:
            break
        x_live, r_live, j_live = x[live], residual[live], jacobian[live]
        g_live = gradient[live]
        low, high = lower_bound[live], upper_bound[live]
        held = ((x_live <= low) & (g_live > 0)) | ((x_live >= high) & (g_live < 0))
        free_gradient = np.where(held, 0.0, g_live)
        projected = 2.0 * np.max(np.abs(free_gradient), axis=1, initial=0.0)

        finished = np.zeros(live.size, dtype=int)
        finished[projected <= gtol] = 1
        finished[cost[live] <= fatol] = 4
        finished[(finished == 0) & (nit[live] >= max_iterations)] = -9
        stop = finished != 0
        status[live[stop]] = np.where(finished[stop] == -9, 0, finished[stop])
        done[live[stop]] = True
        keep = ~stop
        if not np.any(keep):
            break
        live = live[keep]
        x_live, r_live, j_live = x_live[keep], r_live[keep], j_live[keep]
        free_gradient, held = free_gradient[keep], held[keep]
        low, high = low[keep], high[keep]

        normal = np.einsum("kqi,kqj->kij", j_live, j_live)
        normal += (damping[live][:, None] * scale[live])[:, :, None] * identity
        pinned = held[:, :, None] | held[:, None, :]
        normal = np.where(pinned, 0.0, normal) + held[:, :, None] * identity
        step = np.linalg.solve(normal, -free_gradient[:, :, None])[:, :, 0]
        trial = np.clip(x_live + step, low, high)
        taken = trial - x_live
        model_residual = r_live + np.einsum("kqp,kp->kq", j_live, taken)
        predicted = cost[live] - np.einsum("kq,kq->k", model_residual, model_residual)

        trial_residual, trial_jacobian = residual_and_jacobian(trial, live)
        nfev[live] += 1
        nit[live] += 1
        trial_cost = np.einsum("kq,kq->k", trial_residual, trial_residual)
        previous_cost = cost[live]
        usable = np.isfinite(trial_cost) & np.all(np.isfinite(trial_jacobian), axis=(1, 2))
        ratio = np.where(predicted > 0,
                         (cost[live] - trial_cost) / np.where(predicted > 0, predicted, 1.0),
                         -1.0)
        accept = usable & (ratio > _ACCEPT_RATIO)

        rows = live[accept]
        x[rows] = trial[accept]
        residual[rows] = trial_residual[accept]
        jacobian[rows] = trial_jacobian[accept]
        cost[rows] = trial_cost[accept]
        gradient[rows] = np.einsum("kqp,kq->kp", jacobian[rows], residual[rows])
        scale[rows] = np.maximum(scale[rows],
                                 np.einsum("kqp,kqp->kp", jacobian[rows], jacobian[rows]))
        shrink = np.maximum(1.0 / 3.0, 1.0 - (2.0 * ratio[accept] - 1.0) ** 3)
        damping[rows] = np.maximum(damping[rows] * shrink, _MIN_DAMPING)
        growth[rows] = 2.0
        small_step = (np.max(np.abs(taken[accept]), axis=1)
                      <= xtol * (xtol + np.max(np.abs(trial[accept]), axis=1)))
        status[rows[small_step]] = 3
        done[rows[small_step]] = True

        level = ftol * previous_cost
        flat = (usable & (predicted <= level) & (np.abs(previous_cost - trial_cost) <= level)
                & (ratio <= 2.0) & (status[live] == 0))
        status[live[flat]] = 2
        done[live[flat]] = True

        rejected = live[~accept & ~flat]
        damping[rejected] *= growth[rejected]
        growth[rejected] *= 2.0
        stalled = rejected[damping[rejected] > _MAX_DAMPING]
        status[stalled] = -1
        done[stalled] = True

    held = (((x <= lower_bound) & (gradient > 0)) | ((x >= upper_bound) & (gradient < 0)))
    projected = 2.0 * np.max(np.abs(np.where(held, 0.0, gradient)), axis=1, initial=0.0)
    return BatchLeastSquaresResult(
        x=x,
        fun=cost,
        projected_gradient=projected,
        nit=nit,
        nfev=nfev,
        status=status,
        success=np.isin(status, SUCCESS_STATUSES),
    )
