"""The batched Levenberg-Marquardt solver on problems with known answers."""

import numpy as np
import pytest

from sso._solvers.least_squares import STATUS_MESSAGES, batch_least_squares


def rosenbrock(x, rows):
    # f = 100 (x2 - x1^2)^2 + (1 - x1)^2 as |r|^2; minimum 0 at (1, 1).
    residual = np.stack([10.0 * (x[:, 1] - x[:, 0] ** 2), 1.0 - x[:, 0]], axis=1)
    jacobian = np.zeros((len(x), 2, 2))
    jacobian[:, 0, 0] = -20.0 * x[:, 0]
    jacobian[:, 0, 1] = 10.0
    jacobian[:, 1, 0] = -1.0
    return residual, jacobian


def test_unconstrained_rosenbrock_from_many_starts():
    starts = np.array([[-1.2, 1.0], [0.0, 0.0], [2.0, -1.0], [-3.0, 5.0]])
    result = batch_least_squares(rosenbrock, starts, -10.0, 10.0)
    np.testing.assert_allclose(result.x, 1.0, atol=1e-10)
    assert np.all(result.fun <= 1e-20)
    assert np.all(result.success)
    # One evaluation per iteration and the start's, plus 2 p per Hessian (Newton
    # steps, saddle check).
    assert np.all(result.nit >= 1)
    assert np.all((result.nfev - result.nit - 1) % 4 == 0)


def test_bound_active_rosenbrock():
    # With x1 <= 0.5 the minimum is x1 = 0.5 (bound), x2 = 0.25, f = (1 - 0.5)^2 = 0.25.
    starts = np.array([[-1.2, 1.0], [0.4, 3.0], [0.5, -2.0]])
    result = batch_least_squares(rosenbrock, starts, [-2.0, -5.0], [0.5, 5.0])
    np.testing.assert_allclose(result.x, [[0.5, 0.25]] * 3, atol=1e-9)
    np.testing.assert_allclose(result.fun, 0.25, rtol=1e-12)
    assert np.all(result.success)
    # ftol stops where the decrease is round-off: |g| ~ sqrt(ftol f H) ~ 1e-7 here.
    assert np.all(result.projected_gradient <= 1e-7)


def test_starts_outside_the_bounds_are_moved_and_iterates_stay_inside():
    visited = []

    def recording(x, rows):
        visited.append(x.copy())
        return rosenbrock(x, rows)

    result = batch_least_squares(recording, [[5.0, 5.0]], [-1.0, -1.0], [0.8, 0.6])
    points = np.concatenate(visited)
    assert np.all(points >= [-1.0, -1.0]) and np.all(points <= [0.8, 0.6])
    assert result.success[0]
    # x2 = x1^2 is feasible up to x1 = sqrt(0.6) < 0.8: the optimum lies on x2 = 0.6.
    assert result.x[0, 1] == pytest.approx(0.6, abs=1e-12)


def test_saddle_point_is_left():
    # r = (x1^2 - x2^2 + 1, 0): f = (x1^2 - x2^2 + 1)^2 with bounds x in [-2, 2]^2.
    # From (0, 0) the gradient is zero: a saddle of f (f_x2x2 = -4). Its minima
    # (f = 0) lie on x2^2 = x1^2 + 1.
    def saddle(x, rows):
        value = x[:, 0] ** 2 - x[:, 1] ** 2 + 1.0
        residual = np.stack([value, np.zeros_like(value)], axis=1)
        jacobian = np.zeros((len(x), 2, 2))
        jacobian[:, 0, 0] = 2.0 * x[:, 0]
        jacobian[:, 0, 1] = -2.0 * x[:, 1]
        return residual, jacobian

    stuck = batch_least_squares(saddle, [[0.0, 0.0]], -2.0, 2.0, escape_saddles=False)
    assert stuck.fun[0] == 1.0 and stuck.status[0] == 1
    left = batch_least_squares(saddle, [[0.0, 0.0]], -2.0, 2.0)
    assert left.fun[0] <= 1e-20 and left.success[0]
    assert left.x[0, 1] ** 2 - left.x[0, 0] ** 2 == pytest.approx(1.0, abs=1e-10)


def test_nonzero_residual_minimum_converges_fast():
    # r = (x1 - 1, x1 x2 - 10, x2 - 1) has no zero. By symmetry the minimum has
    # x1 = x2 = t with d/dt [2 (t - 1)^2 + (t^2 - 10)^2] = 0, i.e. t^3 - 9 t - 1 = 0.
    # Gauss-Newton alone converges linearly here (42 iterations); the switch to
    # Newton steps with the true Hessian needs 9.
    def residuals(x, rows):
        residual = np.stack([x[:, 0] - 1.0, x[:, 0] * x[:, 1] - 10.0, x[:, 1] - 1.0], axis=1)
        jacobian = np.zeros((len(x), 3, 2))
        jacobian[:, 0, 0] = 1.0
        jacobian[:, 1, 0] = x[:, 1]
        jacobian[:, 1, 1] = x[:, 0]
        jacobian[:, 2, 1] = 1.0
        return residual, jacobian

    root = max(np.roots([1.0, 0.0, -9.0, -1.0]).real)
    result = batch_least_squares(residuals, [[0.0, 3.0], [3.0, 0.5]], -5.0, 5.0)
    assert np.all(result.success) and np.all(result.nit <= 15)
    np.testing.assert_allclose(result.x, root, rtol=1e-7)
    np.testing.assert_allclose(result.fun, 2 * (root - 1) ** 2 + (root**2 - 10) ** 2, rtol=1e-13)


def test_iteration_limit_and_non_finite_residuals_are_reported():
    limited = batch_least_squares(rosenbrock, [[-1.2, 1.0]], -10.0, 10.0, max_iterations=2)
    assert limited.status.tolist() == [0] and not limited.success[0]
    assert limited.nit.tolist() == [2]
    assert limited.message == (STATUS_MESSAGES[0],)

    def broken(x, rows):
        residual, jacobian = rosenbrock(x, rows)
        residual[:, 0] = np.nan
        return residual, jacobian

    failed = batch_least_squares(broken, [[0.0, 0.0]], -1.0, 1.0)
    assert failed.status.tolist() == [-2] and not failed.success[0]


def test_inverted_bounds_are_refused():
    with pytest.raises(ValueError, match="lower bound exceeds"):
        batch_least_squares(rosenbrock, [[0.0, 0.0]], [1.0, 0.0], [0.0, 1.0])
