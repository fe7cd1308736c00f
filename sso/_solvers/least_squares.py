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

Two additions make it reliable where plain Gauss-Newton is not. A problem that
converges slowly to a nonzero residual (Gauss-Newton is then only linear) switches
to Newton steps with the true Hessian, from differences of the analytic gradient,
shifted to be positive definite. And a problem that stops at a nonzero residual is
checked for negative curvature (a saddle, or a bound whose multiplier is only
round-off) and moved downhill and restarted if it has some: RE-like sums of squares
are never negative, so a stop at zero needs no such check.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from sso._solvers.round_off_stops import REFUTED, REFUTED_MESSAGE

ResidualFunction = Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]

STATUS_MESSAGES = {
    -2: "residual or Jacobian is not finite",
    -1: "no decrease possible (damping overflow) before the tolerances were met",
    0: "iteration limit reached",
    1: "projected gradient below gtol",
    2: "actual and predicted relative reductions below ftol",
    3: "relative step below xtol",
    4: "sum of squares below fatol",
    REFUTED: REFUTED_MESSAGE,
}
SUCCESS_STATUSES = (1, 2, 3, 4)
_ACCEPT_RATIO = 1e-4
_INITIAL_DAMPING = 1e-3
_MIN_DAMPING = 1e-15
_MAX_DAMPING = 1e16
_SCALE_FLOOR = 1e-30
_HESSIAN_STEP = 1e-6
_NEGATIVE_CURVATURE = 1e-6
_STRONGLY_ACTIVE = 1e-8
_ESCAPE_LENGTHS = 0.5 ** np.arange(1, 16)


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
    escape_saddles: bool = True,
    max_saddle_escapes: int = 3,
    zero_residual_level: float = 1e-20,
    iterations_taken: Any = 0,
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
        Trial steps per problem, over all its restarts.
    escape_saddles : bool
        Check every converged problem whose sum of squares is above ``zero_residual_level`` for
        negative curvature (a saddle point, or a stationary point on a bound that
        only the true Hessian shows is not a minimum); move such a point downhill
        and iterate again, at most ``max_saddle_escapes`` times.
    zero_residual_level : float
        Sums of squares at or below this count as zero: such a point is a global
        minimum (the sum is never negative), so it is not checked for a saddle,
        and a problem above it whose Gauss-Newton steps converge slowly (the
        projected gradient falls by less than half in an accepted step, the mark of
        a minimum with nonzero residuals) switches to Newton steps with the true
        Hessian (differences of the gradient, ``2 p`` evaluations per step).
    iterations_taken : int or array of shape (m,)
        Iterations each problem has already taken (another solver's, continued
        here): they count against ``max_iterations`` and are included in ``nit``.

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
    count = x.shape[0]
    state = _State(
        x=x, lower=lower_bound, upper=upper_bound,
        residual=np.zeros((count, 0)), jacobian=np.zeros((count, 0, x.shape[1])),
        cost=np.zeros(count), gradient=np.zeros_like(x),
        nit=np.broadcast_to(np.asarray(iterations_taken, dtype=int), (count,)).copy(),
        nfev=np.zeros(count, dtype=int),
        status=np.zeros(count, dtype=int),
    )
    settings = _Settings(gtol, fatol, ftol, xtol, max_iterations, zero_residual_level)
    _levenberg_marquardt(residual_and_jacobian, state, np.arange(count), settings)
    # A problem found no saddle keeps its point: only those moved are checked again, so
    # a problem's counts do not depend on the others in the batch.
    checked = np.ones(count, dtype=bool)
    for _ in range(max_saddle_escapes * escape_saddles):
        candidates = np.flatnonzero(checked & np.isin(state.status, SUCCESS_STATUSES)
                                    & (state.cost > max(fatol, zero_residual_level))
                                    & (state.nit < max_iterations))
        moved = _leave_saddles(residual_and_jacobian, state, candidates)
        if moved.size == 0:
            break
        _levenberg_marquardt(residual_and_jacobian, state, moved, settings)
        checked = np.isin(np.arange(count), moved)

    return BatchLeastSquaresResult(
        x=state.x,
        fun=state.cost,
        projected_gradient=2.0 * np.max(np.abs(_free_gradient(state, slice(None))[0]), axis=1,
                                        initial=0.0),
        nit=state.nit,
        nfev=state.nfev,
        status=state.status,
        success=np.isin(state.status, SUCCESS_STATUSES),
    )


def leave_saddles(residual_and_jacobian: ResidualFunction, x: np.ndarray, lower: np.ndarray,
                  upper: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Move the stationary points ``x`` (one row per problem) that are saddles downhill, as
    :func:`batch_least_squares` does between its runs, for another solver to go on from.

    Parameters
    ----------
    residual_and_jacobian : callable
        ``f(x, rows) -> (r, J)`` as for :func:`batch_least_squares` (``rows`` index ``x``).
    x : numpy.ndarray of shape (m, p)
        Points where a solver stopped, inside the bounds.
    lower, upper : numpy.ndarray broadcastable to (m, p)
        Bounds.

    Returns
    -------
    moved : numpy.ndarray
        Rows of ``x`` that were saddles and moved to a lower sum of squares.
    points : numpy.ndarray of shape (len(moved), p)
        Where they moved.
    evaluations : numpy.ndarray of shape (m,)
        Residual-and-Jacobian evaluations spent on each problem.
    """
    count = x.shape[0]
    state = _State(
        x=np.array(x, dtype=float), lower=np.broadcast_to(lower, x.shape),
        upper=np.broadcast_to(upper, x.shape), residual=np.zeros((count, 0)),
        jacobian=np.zeros((count, 0, x.shape[1])), cost=np.zeros(count),
        gradient=np.zeros(x.shape), nit=np.zeros(count, dtype=int),
        nfev=np.ones(count, dtype=int), status=np.zeros(count, dtype=int))
    every = np.arange(count)
    state.store(every, *residual_and_jacobian(state.x, every))
    moved = _leave_saddles(residual_and_jacobian, state, every)
    return moved, state.x[moved], state.nfev


@dataclass(frozen=True)
class _Settings:
    gtol: float
    fatol: float
    ftol: float
    xtol: float
    max_iterations: int
    zero_residual_level: float


@dataclass
class _State:
    """Arrays of the whole batch, updated in place for the rows being iterated."""

    x: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    residual: np.ndarray
    jacobian: np.ndarray
    cost: np.ndarray
    gradient: np.ndarray
    nit: np.ndarray
    nfev: np.ndarray
    status: np.ndarray

    def store(self, rows: np.ndarray, residual: np.ndarray, jacobian: np.ndarray) -> None:
        """Residuals, Jacobian, sum of squares and half-gradient ``J^T r`` at ``x[rows]``."""
        if self.residual.shape[1] != residual.shape[1]:
            self.residual = np.zeros((len(self.x), residual.shape[1]))
            self.jacobian = np.zeros((len(self.x), *jacobian.shape[1:]))
        self.residual[rows] = residual
        self.jacobian[rows] = jacobian
        self.cost[rows] = np.einsum("kq,kq->k", residual, residual)
        self.gradient[rows] = np.einsum("kqp,kq->kp", jacobian, residual)


def _free_gradient(state: _State, rows: Any) -> tuple[np.ndarray, np.ndarray]:
    """Half-gradient with the components that push through an active bound removed, and those."""
    x, gradient = state.x[rows], state.gradient[rows]
    held = (((x <= state.lower[rows]) & (gradient > 0))
            | ((x >= state.upper[rows]) & (gradient < 0)))
    return np.where(held, 0.0, gradient), held


def _levenberg_marquardt(fun: ResidualFunction, state: _State, rows: np.ndarray,
                         settings: _Settings) -> None:
    """Iterate the problems ``rows`` from ``state.x`` until each stops; update ``state``."""
    residual, jacobian = fun(state.x[rows], rows)
    state.store(rows, residual, jacobian)
    state.nfev[rows] += 1
    state.status[rows] = 0
    finite = np.isfinite(state.cost[rows]) & np.all(np.isfinite(jacobian), axis=(1, 2))
    state.status[rows[~finite]] = -2
    size = state.x.shape[1]
    scale = np.full((len(state.x), size), _SCALE_FLOOR)
    scale[rows] = np.maximum(np.einsum("kqp,kqp->kp", jacobian, jacobian), _SCALE_FLOOR)
    damping = np.full(len(state.x), _INITIAL_DAMPING)
    growth = np.full(len(state.x), 2.0)
    done = np.ones(len(state.x), dtype=bool)
    done[rows[finite]] = False
    newton = np.zeros(len(state.x), dtype=bool)
    identity = np.eye(size)

    while True:
        live = np.flatnonzero(~done)
        if live.size == 0:
            return
        free_gradient, held = _free_gradient(state, live)
        projected = 2.0 * np.max(np.abs(free_gradient), axis=1, initial=0.0)
        finished = np.full(live.size, -9)
        finished[state.nit[live] >= settings.max_iterations] = 0
        finished[projected <= settings.gtol] = 1
        finished[state.cost[live] <= settings.fatol] = 4
        stop = finished != -9
        state.status[live[stop]] = finished[stop]
        done[live[stop]] = True
        if np.all(stop):
            return
        live, free_gradient, held = live[~stop], free_gradient[~stop], held[~stop]
        x_live, j_live = state.x[live], state.jacobian[live]
        previous_cost = state.cost[live]

        # The model's half Hessian: J^T J (Gauss-Newton), or the true one's half
        # for the problems that switched to Newton steps, shifted to be positive
        # definite on the free variables.
        model = np.einsum("kqi,kqj->kij", j_live, j_live)
        pinned = held[:, :, None] | held[:, None, :]
        in_newton = np.flatnonzero(newton[live])
        if in_newton.size:
            exact = 0.5 * _hessian(fun, state, live[in_newton])
            free_part = (np.where(pinned[in_newton], 0.0, exact)
                         + held[in_newton][:, :, None] * identity)
            lowest = np.linalg.eigvalsh(free_part)[:, 0]
            shift = np.maximum(0.0, -2.0 * lowest)
            model[in_newton] = exact + shift[:, None, None] * identity
        normal = model + (damping[live][:, None] * scale[live])[:, :, None] * identity
        normal = np.where(pinned, 0.0, normal) + held[:, :, None] * identity
        step = np.linalg.solve(normal, -free_gradient[:, :, None])[:, :, 0]
        trial = np.clip(x_live + step, state.lower[live], state.upper[live])
        taken = trial - x_live
        predicted = -(2.0 * np.einsum("kp,kp->k", state.gradient[live], taken)
                      + np.einsum("kp,kpq,kq->k", taken, model, taken))

        trial_residual, trial_jacobian = fun(trial, live)
        state.nfev[live] += 1
        state.nit[live] += 1
        trial_cost = np.einsum("kq,kq->k", trial_residual, trial_residual)
        usable = np.isfinite(trial_cost) & np.all(np.isfinite(trial_jacobian), axis=(1, 2))
        positive = np.where(predicted > 0, predicted, 1.0)
        ratio = np.where(predicted > 0, (previous_cost - trial_cost) / positive, -1.0)
        accept = usable & (ratio > _ACCEPT_RATIO)

        rows_accepted = live[accept]
        state.x[rows_accepted] = trial[accept]
        state.store(rows_accepted, trial_residual[accept], trial_jacobian[accept])
        scale[rows_accepted] = np.maximum(
            scale[rows_accepted],
            np.einsum("kqp,kqp->kp", trial_jacobian[accept], trial_jacobian[accept]))
        # Linear convergence to a nonzero residual: the sum of squares and the
        # projected gradient both fall by less than half in a step the model predicted.
        slow = ((2.0 * np.max(np.abs(_free_gradient(state, rows_accepted)[0]), axis=1,
                              initial=0.0) > 0.5 * projected[~stop][accept])
                & (trial_cost[accept] > 0.5 * previous_cost[accept])
                & (trial_cost[accept] > settings.zero_residual_level))
        newton[rows_accepted[slow]] = True
        shrink = np.maximum(1.0 / 3.0, 1.0 - (2.0 * ratio[accept] - 1.0) ** 3)
        damping[rows_accepted] = np.maximum(damping[rows_accepted] * shrink, _MIN_DAMPING)
        growth[rows_accepted] = 2.0
        small_step = (np.max(np.abs(taken[accept]), axis=1)
                      <= settings.xtol * (settings.xtol + np.max(np.abs(trial[accept]), axis=1)))
        state.status[rows_accepted[small_step]] = 3
        done[rows_accepted[small_step]] = True

        level = settings.ftol * previous_cost
        flat = (usable & (predicted <= level) & (np.abs(previous_cost - trial_cost) <= level)
                & (ratio <= 2.0) & ~done[live])
        state.status[live[flat]] = 2
        done[live[flat]] = True

        rejected = live[~accept & ~flat]
        damping[rejected] *= growth[rejected]
        growth[rejected] *= 2.0
        stalled = rejected[damping[rejected] > _MAX_DAMPING]
        state.status[stalled] = -1
        done[stalled] = True


def _hessian(fun: ResidualFunction, state: _State, rows: np.ndarray) -> np.ndarray:
    """Hessian of ``|r|^2`` at ``x[rows]`` from differences of the gradient ``2 J^T r``.

    Central differences, one-sided at a bound, so every point stays inside the
    bounds; symmetrised. Costs ``2 p`` evaluations per problem.
    """
    count, size = rows.size, state.x.shape[1]
    x = state.x[rows]
    offsets = _HESSIAN_STEP * np.eye(size)
    shifted = np.clip(np.stack([x[:, None, :] + offsets, x[:, None, :] - offsets], axis=1),
                      state.lower[rows][:, None, None, :], state.upper[rows][:, None, None, :])
    residual, jacobian = fun(shifted.reshape(-1, size), np.repeat(rows, 2 * size))
    state.nfev[rows] += 2 * size
    gradient = 2.0 * np.einsum("kqp,kq->kp", jacobian, residual).reshape(count, 2, size, size)
    spacing = np.einsum("kjj->kj", shifted[:, 0] - shifted[:, 1])
    spacing = np.where(spacing > 0, spacing, 1.0)
    hessian = (gradient[:, 0] - gradient[:, 1]) / spacing[:, :, None]
    result: np.ndarray = 0.5 * (hessian + hessian.transpose(0, 2, 1))
    return result


def _leave_saddles(fun: ResidualFunction, state: _State, rows: np.ndarray) -> np.ndarray:
    """Move the stationary points among ``rows`` that are saddles downhill; return those moved.

    The Hessian of ``|r|^2`` (:func:`_hessian`; not the Gauss-Newton one, which
    cannot be indefinite) is taken over the variables not held by a bound. Along its
    most negative eigenvector, both ways where the bounds allow, the lowest of a
    ladder of step lengths is taken if it lowers the sum of squares.
    """
    if rows.size == 0:
        return rows
    size = state.x.shape[1]
    x = state.x[rows]
    _, held = _free_gradient(state, rows)
    # A bound holds a variable only if it pushes outwards with a multiplier that
    # is not round-off: a degenerate bound (zero gradient) with negative curvature
    # inwards is no minimum.
    strongly = held & (2.0 * np.abs(state.gradient[rows]) > _STRONGLY_ACTIVE)
    pinned = strongly | (state.lower[rows] == state.upper[rows])
    hessian = _hessian(fun, state, rows)
    mask = pinned[:, :, None] | pinned[:, None, :]
    hessian = np.where(mask, 0.0, hessian) + pinned[:, :, None] * np.eye(size)
    values, vectors = np.linalg.eigh(hessian)
    size_of_curvature = np.maximum(1.0, np.max(np.abs(values), axis=1))
    saddle = np.isfinite(values[:, 0]) & (values[:, 0] < -_NEGATIVE_CURVATURE * size_of_curvature)
    if not np.any(saddle):
        return rows[:0]
    rows, x, direction = rows[saddle], x[saddle], vectors[saddle, :, 0]
    lengths = _ESCAPE_LENGTHS[None, :, None] * np.array([1.0, -1.0])[:, None, None]
    trials = x[:, None, None, :] + lengths[None] * direction[:, None, None, :]
    trials = np.clip(trials, state.lower[rows][:, None, None, :],
                     state.upper[rows][:, None, None, :]).reshape(len(rows), -1, size)
    per_row = trials.shape[1]
    residual, _ = fun(trials.reshape(-1, size), np.repeat(rows, per_row))
    state.nfev[rows] += per_row
    cost = np.einsum("kq,kq->k", residual, residual).reshape(len(rows), per_row)
    cost = np.where(np.isfinite(cost), cost, np.inf)
    best = np.argmin(cost, axis=1)
    lower_cost = cost[np.arange(len(rows)), best] < state.cost[rows] * (1.0 - 1e-9)
    rows = rows[lower_cost]
    state.x[rows] = trials[lower_cost, best[lower_cost]]
    return rows
