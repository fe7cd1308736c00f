"""The "lm" step rules one by one, on plain floats, against the same rules computed here by
hand with numpy (written after mutation testing showed each rule could change unseen;
docs/mutation-testing.md).

References: the damped Gauss-Newton step in its textbook form
``d = -(J^T J + mu I)^-1 J^T r`` over the free variables (numpy's solve, where the rules
take the push-through 2x2 solve), ``mu = damping * trace(J J^T) / 2 * min(1, |r| / |r_0|)``;
Nielsen's damping update ``damping * max(1/3, 1 - (2 rho - 1)^3)`` on an accepted step
(K. Madsen, H. B. Nielsen, O. Tingleff, "Methods for non-linear least squares problems",
2nd ed., IMM, DTU, 2004, eq. 3.16) and ``damping * growth``, growth doubled, on a
rejected one; the Newton step ``-(H + shift I)^-1 g`` (numpy's solve) with the shift
of :func:`sso._solvers.lm_rules.newton_iteration`'s docstring. The tests and
thresholds are those the docstrings of :mod:`sso._solvers.lm_rules` state.

The residuals are ``curved`` (below, derivatives written out) or fabricated: a trial
step's residuals chosen so that the actual decrease is a given fraction of the
predicted one.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from sso._solvers.lm_rules import (
    ACCEPT_RATIO,
    INITIAL_DAMPING,
    MAX_DAMPING,
    NEWTON,
    NEWTON_DAMPING,
    NEWTON_INDEFINITE,
    PYTHON,
    ROUND_OFF,
    RUNNING,
    SLOW_LEVEL,
    ZERO_RESIDUAL,
    fresh_state,
    gauss_newton_iteration,
    newton_iteration,
    top_of_iteration,
    trial_step,
)

LOWER = [-1.0, -1.0, -1.0]
UPPER = [1.0, 1.0, 1.0]
START = [0.3, 0.6, -0.2]
SCALE = 0.1
"""Residuals scaled so that half the trace of ``J J^T`` (about 0.02) lies below 1."""
ON_BOUND = [-0.5, 0.2, 1.0]
"""x2 on its upper bound, where the gradient pushes it out (checked in each test)."""


def curved(point):
    """``r1 = 0.1 (x0^2 + x1 - 1 + x2 / 2)``, ``r2 = 0.1 (x0 - x1^3 + x2 / 4)`` and their
    derivatives."""
    x0, x1, x2 = point
    return (SCALE * (x0 * x0 + x1 - 1.0 + 0.5 * x2), SCALE * (x0 - x1**3 + 0.25 * x2),
            [SCALE * 2.0 * x0, SCALE, SCALE * 0.5], [SCALE, SCALE * -3.0 * x1 * x1, SCALE * 0.25])


def _arrays(point):
    r1, r2, first, second = curved(point)
    return np.array([r1, r2]), np.array([first, second])


def _gradient(point):
    residual, jacobian = _arrays(point)
    return 2.0 * jacobian.T @ residual


def _gauss_newton_step(point, free, damping, residual_scale=1.0):
    """``-(J^T J + mu I)^-1 J^T r`` with the columns of the variables not free zeroed."""
    residual, jacobian = _arrays(point)
    jacobian = jacobian * np.array(free, dtype=float)
    mu = damping * 0.5 * np.trace(jacobian @ jacobian.T) * residual_scale
    normal = jacobian.T @ jacobian + mu * np.eye(len(point))
    return -np.linalg.solve(normal, jacobian.T @ residual)


def _nielsen(damping, ratio):
    return damping * max(1.0 / 3.0, 1.0 - (2.0 * ratio - 1.0) ** 3)


def _fabricated(point_of_start, trial_residuals):
    """``curved`` at the start; ``trial_residuals`` (with curved's derivatives) anywhere else;
    the points asked for are recorded."""
    asked = []

    def evaluate(point):
        asked.append(list(point))
        if list(point) == list(point_of_start):
            return curved(point)
        _, _, first, second = curved(point)
        return (*trial_residuals, first, second)

    return evaluate, asked


def _state(point=START, **changes):
    state = fresh_state(PYTHON, curved, list(point), LOWER, UPPER)
    state.update(changes)
    return state


def _predicted(point, move):
    """The linear model's decrease ``|r|^2 - |r + J move|^2``."""
    residual, jacobian = _arrays(point)
    return float(residual @ residual - np.sum((residual + jacobian @ np.array(move)) ** 2))


# The start ------------------------------------------------------------------------------

def test_a_fresh_state_is_the_start_moved_onto_the_bounds_and_evaluated_there():
    state = fresh_state(PYTHON, curved, [-3.0, 0.5, 9.0], LOWER, UPPER)
    r1, r2, first, second = curved([-1.0, 0.5, 1.0])
    assert state == {
        "x": [-1.0, 0.5, 1.0], "r1": r1, "r2": r2, "J1": first, "J2": second,
        "fun": r1 * r1 + r2 * r2, "nit": 0, "nfev": 1, "status": RUNNING,
        "damping": INITIAL_DAMPING, "growth": 2.0, "slow_steps": 0,
        "previous_norm": math.inf, "first_size": math.hypot(r1, r2), "hessian_counted": 0}


def test_a_fresh_state_at_zero_residual_keeps_a_positive_first_size():
    state = fresh_state(PYTHON, lambda point: (0.0, 0.0, [1.0], [0.0]), [0.5], [0.0], [1.0])
    assert state["fun"] == 0.0
    assert state["first_size"] == 1e-300


# The tests at the top of an iteration ---------------------------------------------------

def test_the_gradient_and_projected_gradient_norm_are_the_hand_computed_ones():
    point = [0.3, -1.0, 1.0]
    status, gradient, norm, free = top_of_iteration(PYTHON, _state(point), RUNNING, LOWER, UPPER,
                                                    0.0, 10)
    expected = _gradient(point)
    np.testing.assert_allclose(gradient, expected, rtol=1e-14)
    projected = np.array(point) - np.clip(np.array(point) - expected, LOWER, UPPER)
    assert norm == pytest.approx(np.max(np.abs(projected)), rel=1e-14)
    assert status == RUNNING


@pytest.mark.parametrize(("nit", "status"), [(9, RUNNING), (10, 0), (11, 0)])
def test_the_iteration_limit_ends_a_solve_at_max_iterations(nit, status):
    assert top_of_iteration(PYTHON, _state(nit=nit), RUNNING, LOWER, UPPER, 0.0, 10)[0] == status


@pytest.mark.parametrize("field", ["r1", "r2", "J1", "J2", "fun"])
@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_a_residual_or_derivative_that_is_not_finite_ends_the_solve_with_minus_2(field, bad):
    state = _state()
    state[field] = [bad, 0.1, 0.2] if field in ("J1", "J2") else bad
    if field in ("r1", "r2"):
        # fun is r1^2 + r2^2 of the same residuals
        state["fun"] = state["r1"] ** 2 + state["r2"] ** 2
    assert top_of_iteration(PYTHON, state, RUNNING, LOWER, UPPER, 0.0, 10)[0] == -2
    # the iteration limit is tested first
    assert top_of_iteration(PYTHON, state, RUNNING, LOWER, UPPER, 0.0, state["nit"])[0] == 0


def test_derivatives_whose_magnitudes_add_past_the_largest_float_count_as_not_finite():
    # 1e308 in each residual's derivative: each is finite, their magnitudes' total is not
    # (the 2x2 system's trace would overflow too).
    state = _state(J1=[1e308, 0.0, 0.0], J2=[1e308, 0.0, 0.0])
    assert top_of_iteration(PYTHON, state, RUNNING, LOWER, UPPER, 0.0, 10)[0] == -2


def test_the_tolerance_on_the_projected_gradient_ends_a_solve_with_1_at_equality():
    state = _state()
    norm = top_of_iteration(PYTHON, state, RUNNING, LOWER, UPPER, 0.0, 10)[2]
    assert norm > 0.0
    assert top_of_iteration(PYTHON, state, RUNNING, LOWER, UPPER, norm, 10)[0] == 1
    assert top_of_iteration(PYTHON, state, RUNNING, LOWER, UPPER, 0.999 * norm, 10)[0] == RUNNING


@pytest.mark.parametrize(("fun", "status"), [(ZERO_RESIDUAL, 4), (0.0, 4),
                                             (1.001 * ZERO_RESIDUAL, RUNNING)])
def test_a_sum_of_squares_at_round_off_zero_ends_a_solve_with_4(fun, status):
    assert top_of_iteration(PYTHON, _state(fun=fun), RUNNING, LOWER, UPPER, 0.0, 10)[0] == status


def test_a_state_in_another_mode_keeps_its_status_through_the_tests():
    for status in (0, 1, 3, NEWTON):
        state = _state(status=status, nit=10, fun=0.0)
        assert top_of_iteration(PYTHON, state, RUNNING, LOWER, UPPER, 1.0, 10)[0] == status


def test_free_variables_are_off_their_bounds_or_pulled_inwards_and_not_pinned():
    # Every variable's gradient is set by hand: r1 = sum(slope_i x_i) / 2, r2 = 0, r1 = 1
    # at the point, so the gradient 2 J^T r is the slopes.
    slopes = [1.0, -1.0, -1.0, 1.0, 0.0, 0.0, 0.0, 0.5]
    lower = [0.0, 0.0, -1.0, -1.0, 0.0, -1.0, 0.5, -1.0]
    upper = [1.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.5, 1.0]
    point = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.5, 0.2]
    state = _state(x=point, r1=1.0, r2=0.0, J1=[0.5 * slope for slope in slopes],
                   J2=[0.0] * 8, fun=1.0)
    _, gradient, _, free = top_of_iteration(PYTHON, state, RUNNING, lower, upper, 0.0, 10)
    assert gradient == slopes
    # on the lower bound pushed out, pulled in; on the upper bound pushed out, pulled in;
    # on either bound with no slope; pinned (with no slope, which frees either bound);
    # inside
    assert free == [False, True, False, True, True, True, False, True]


# One Gauss-Newton iteration -------------------------------------------------------------

def _accepted_after(state, lower=LOWER, upper=UPPER):
    after = gauss_newton_iteration(PYTHON, curved, state, lower, upper, 0.0, 10)
    assert after["status"] == RUNNING and after["x"] != state["x"], "the step is accepted"
    return after


def test_the_first_gauss_newton_step_is_the_damped_textbook_step_and_its_state():
    state = _state()
    norm = top_of_iteration(PYTHON, state, RUNNING, LOWER, UPPER, 0.0, 10)[2]
    after = _accepted_after(state)
    step = _gauss_newton_step(START, [True] * 3, INITIAL_DAMPING)
    np.testing.assert_allclose(np.array(after["x"]) - START, step, rtol=1e-10)
    r1, r2, first, second = curved(after["x"])
    move = np.array(after["x"]) - START
    ratio = (state["fun"] - (r1 * r1 + r2 * r2)) / _predicted(START, move)
    assert 0.0 < ratio < 2.0 and ratio != pytest.approx(1.0, abs=1e-3)
    assert after == {
        "x": after["x"], "r1": r1, "r2": r2, "J1": first, "J2": second,
        "fun": r1 * r1 + r2 * r2, "nit": 1, "nfev": 2, "status": RUNNING,
        "damping": pytest.approx(_nielsen(INITIAL_DAMPING, ratio), rel=1e-9),
        "growth": 2.0, "slow_steps": 0, "previous_norm": norm,
        "first_size": state["first_size"], "hessian_counted": 0}


def test_the_damping_scales_with_the_residual_once_it_has_fallen():
    # As if the start's residual had been four times this one: mu is a quarter.
    state = _state(first_size=4.0 * math.sqrt(_state()["fun"]), damping=0.05)
    after = _accepted_after(state)
    np.testing.assert_allclose(np.array(after["x"]) - START,
                               _gauss_newton_step(START, [True] * 3, 0.05, 0.25), rtol=1e-10)


def test_the_step_moves_only_the_free_variables():
    # x2 on its upper bound with the gradient pushing it out; x0 and x1 free.
    point = ON_BOUND
    assert _gradient(point)[2] < 0.0
    state = _state(point)
    after = _accepted_after(state)
    step = _gauss_newton_step(point, [True, True, False], INITIAL_DAMPING)
    assert step[2] == 0.0 and after["x"][2] == 1.0
    np.testing.assert_allclose(np.array(after["x"]) - point, step, rtol=1e-10)


def test_a_step_past_a_bound_is_projected_onto_it_and_judged_by_the_projected_move():
    # The step takes x1 from -0.5 past its upper bound 0: the trial point is clipped,
    # and the predicted decrease is that of the clipped move.
    point = [0.5, -0.5, 0.5]
    upper = [1.0, 0.0, 1.0]
    step = _gauss_newton_step(point, [True] * 3, INITIAL_DAMPING)
    assert point[1] + step[1] > 0.1
    state = fresh_state(PYTHON, curved, point, LOWER, upper)
    after = _accepted_after(state, upper=upper)
    clipped = np.clip(np.array(point) + step, LOWER, upper)
    np.testing.assert_allclose(after["x"], clipped, rtol=1e-10)
    r1, r2, _, _ = curved(list(clipped))
    ratio = (state["fun"] - (r1 * r1 + r2 * r2)) / _predicted(point, clipped - point)
    assert after["damping"] == pytest.approx(_nielsen(INITIAL_DAMPING, ratio), rel=1e-8)


def test_a_state_that_has_ended_passes_through_unchanged_and_evaluates_nothing():
    evaluate, asked = _fabricated(START, (0.0, 0.0))
    for status in (0, 1, 2, 3, 4, -1, -2, NEWTON):
        state = _state(status=status)
        assert gauss_newton_iteration(PYTHON, evaluate, state, LOWER, UPPER, 0.0, 10) == state
    assert asked == []


# A trial step's test and the damping ----------------------------------------------------

def _trial(fraction, mode=RUNNING, step=(0.05, -0.02, 0.01), **changes):
    """A trial of ``step`` from START whose actual decrease is ``fraction`` of the
    predicted one; the state after it and the ratio actual / predicted."""
    state = _state(status=mode, **changes)
    predicted = _predicted(START, step)
    trial_fun = state["fun"] - fraction * predicted
    evaluate, _ = _fabricated(START, (math.sqrt(trial_fun), 0.0))
    after, moved = trial_step(PYTHON, evaluate, state, mode, mode, 0.01, list(step), None,
                              LOWER, UPPER)
    return state, after, moved, (state["fun"] - trial_fun) / predicted


@pytest.mark.parametrize("fraction", [0.25, 0.75, 1.0, 1.5])
def test_an_accepted_step_changes_the_damping_by_nielsens_rule(fraction):
    state, after, moved, ratio = _trial(fraction, damping=0.02, growth=8.0)
    assert moved and after["x"] == pytest.approx(np.add(START, (0.05, -0.02, 0.01)), abs=1e-15)
    assert after["damping"] == pytest.approx(_nielsen(0.02, ratio), rel=1e-9)
    assert after["growth"] == 2.0
    assert (after["nit"], after["nfev"], after["status"]) == (1, 2, RUNNING)


def test_a_gain_far_above_the_model_s_shrinks_the_damping_by_a_third_without_overflow():
    # A predicted decrease of 1e-200 and an actual one of about fun: a ratio of 1e198,
    # whose cube overflows a float unless the ratio is capped.
    state = _state(damping=0.02)
    evaluate, _ = _fabricated(START, (0.0, 0.0))
    after, moved = trial_step(PYTHON, evaluate, state, RUNNING, RUNNING, 0.01, [0.05, 0.0, 0.0],
                              1e-200, LOWER, UPPER)
    assert moved and after["damping"] == pytest.approx(0.02 / 3.0, rel=1e-15)


@pytest.mark.parametrize(("fraction", "accepted"), [(1.5e-4, True), (0.5e-4, False),
                                                    (-0.5, False)])
def test_a_step_is_accepted_only_for_a_ten_thousandth_of_the_predicted_decrease(fraction,
                                                                               accepted):
    state, after, moved, _ = _trial(fraction)
    assert moved == accepted
    assert (after["x"] != state["x"]) == accepted


def _unit_state():
    """fun = 1 exactly, from r = (1, 0) at x = 0."""
    return _state(x=[0.0, 0.0, 0.0], r1=1.0, r2=0.0, fun=1.0)


def _unit_trial(trial_r1, predicted, step=(1e-3, 0.0, 0.0)):
    evaluate = _fabricated(START, (trial_r1, 0.0))[0]
    return trial_step(PYTHON, evaluate, _unit_state(), RUNNING, RUNNING, 0.01, list(step),
                      predicted, LOWER, UPPER)


def test_a_step_is_accepted_at_exactly_a_ten_thousandth_of_the_predicted_decrease():
    # From fun = 1 to 0.99995^2: an actual decrease that is exactly 1e-4 of this one.
    predicted = 0.9999750000000418
    assert 1.0 - 0.99995**2 == ACCEPT_RATIO * predicted
    after, moved = _unit_trial(0.99995, predicted)
    assert moved and after["status"] == RUNNING
    assert not _unit_trial(0.99995, math.nextafter(predicted, 2.0))[1]


def test_a_step_with_no_predicted_decrease_is_rejected_however_good():
    after, moved = _unit_trial(0.5, 0.0)
    assert not moved and after["damping"] == 2.0 * INITIAL_DAMPING


def test_a_step_that_raises_the_sum_of_squares_is_rejected_and_grows_the_damping():
    # Madsen, Nielsen and Tingleff, section 3.2: the point stays, the damping grows by
    # the growth factor, which doubles.
    state, after, moved, _ = _trial(-0.5, damping=0.02, growth=4.0, slow_steps=2,
                                    previous_norm=0.5, hessian_counted=1)
    assert not moved
    assert after == {**state, "nit": 1, "nfev": 2, "damping": 0.08, "growth": 8.0}


def test_a_step_with_a_nan_component_is_rejected_even_where_the_trial_is_better():
    state = _state(damping=0.02)
    evaluate, asked = _fabricated(START, (0.0, 0.0))
    after, moved = trial_step(PYTHON, evaluate, state, RUNNING, RUNNING, 0.01,
                              [math.nan, 0.05, 0.0], 1.0, LOWER, UPPER)
    assert len(asked) == 1 and not moved
    assert (after["x"], after["status"], after["damping"]) == (START, RUNNING, 0.04)


@pytest.mark.parametrize(("damping", "growth", "status"), [(5e15, 2.0, RUNNING),
                                                           (2e15, 4.0, RUNNING),
                                                           (4e15, 4.0, -1)])
def test_a_rejected_step_ends_the_solve_once_the_damping_passes_its_largest(damping, growth,
                                                                          status):
    # 5e15 * 2 is MAX_DAMPING exactly, which is not past it.
    assert (damping * growth > MAX_DAMPING) == (status == -1)
    after = _trial(-0.5, damping=damping, growth=growth)[1]
    assert after["status"] == status and after["damping"] == damping * growth


def test_a_rejected_newton_step_raises_the_damping_to_at_least_newton_damping():
    after = _trial(-0.5, mode=NEWTON, damping=0.0, growth=2.0)[1]
    assert (after["status"], after["damping"], after["growth"]) == (NEWTON, NEWTON_DAMPING, 4.0)
    after = _trial(-0.5, mode=NEWTON, damping=1e-3, growth=2.0)[1]
    assert after["damping"] == 2e-3


def test_a_move_at_round_off_ends_the_solve_with_3_where_it_stands():
    # ROUND_OFF (1 + max |x|) with max |x| = 0.6 from START: the largest move allowed
    # is 1.42e-15.
    limit = ROUND_OFF * 1.6
    for change, status in ((0.9 * limit, 3), (1.1 * limit, RUNNING)):
        state = _state()
        evaluate, asked = _fabricated(START, (0.0, 0.0))
        after, moved = trial_step(PYTHON, evaluate, state, RUNNING, RUNNING, 0.01,
                                  [0.0, -change, 0.0], 1.0, LOWER, UPPER)
        assert after["status"] == status
        assert moved == (status == RUNNING) and len(asked) == (status == RUNNING)


def test_the_round_off_move_is_relative_to_the_largest_magnitude_of_x():
    # x = (-1000, 0): moves below 8.9e-13 are at round-off, whatever the sign of x.
    state = _state(x=[-1000.0, 0.0, 0.0])
    lower, upper = [-2000.0, -1.0, -1.0], UPPER
    after, _ = trial_step(PYTHON, _fabricated(START, (0.0, 0.0))[0], state, RUNNING, RUNNING,
                          0.01, [0.0, 5e-13, 0.0], 1.0, lower, upper)
    assert after["status"] == 3
    after, _ = trial_step(PYTHON, _fabricated(START, (0.0, 0.0))[0], state, RUNNING, RUNNING,
                          0.01, [0.0, 1e-12, 0.0], 1.0, lower, upper)
    assert after["status"] == RUNNING


@pytest.mark.parametrize(("change", "status"), [(5e-16, 3), (ROUND_OFF, 3),
                                                (1.5 * ROUND_OFF, RUNNING)])
def test_a_move_off_a_coordinate_of_zero_is_at_round_off_up_to_round_off_itself(change,
                                                                              status):
    # x = 0: the largest move at round-off is ROUND_OFF (2^-50) exactly.
    assert _unit_trial(1.0, 1.0, (change, 0.0, 0.0))[0]["status"] == status


def test_a_step_of_nan_and_zeros_is_no_move_and_ends_the_solve_with_3():
    after, moved = _unit_trial(0.5, 1.0, (math.nan, 0.0, 0.0))
    assert not moved and (after["status"], after["nit"], after["nfev"]) == (3, 0, 1)


@pytest.mark.parametrize("accepted", [True, False])
def test_actual_and_predicted_decreases_at_round_off_end_the_solve_with_2(accepted):
    # fun = 1 from r = (1, 0): a predicted decrease of 1e-16 and an actual one of
    # +-4.4e-16 (a residual one or two units in the last place from 1) are both at most
    # ROUND_OFF * fun = 8.9e-16.
    state = _state(x=[0.0, 0.0, 0.0], r1=1.0, r2=0.0, fun=1.0)
    trial_r1 = math.nextafter(1.0, 0.0) if accepted else math.nextafter(1.0, 2.0)
    actual = 1.0 - trial_r1 * trial_r1
    assert 1e-16 < abs(actual) <= ROUND_OFF and (actual > 0.0) == accepted
    evaluate = _fabricated(START, (trial_r1, 0.0))[0]
    after, moved = trial_step(PYTHON, evaluate, state, RUNNING, RUNNING, 0.01, [1e-3, 0.0, 0.0],
                              1e-16, LOWER, UPPER)
    assert moved == accepted and after["status"] == 2
    # a predicted decrease above round-off goes on
    after, _ = trial_step(PYTHON, evaluate, state, RUNNING, RUNNING, 0.01, [1e-3, 0.0, 0.0],
                          1e-14, LOWER, UPPER)
    assert after["status"] == RUNNING


def test_decreases_of_exactly_round_off_are_at_round_off():
    # fun = 1: ROUND_OFF * fun = 2^-50, and (1 - 2^-51)^2 rounds to 1 - 2^-50.
    trial_r1 = 1.0 - 2.0**-51
    assert 1.0 - trial_r1 * trial_r1 == ROUND_OFF
    after, moved = _unit_trial(trial_r1, ROUND_OFF)
    assert moved and after["status"] == 2


def test_an_actual_decrease_above_round_off_goes_on_with_a_predicted_one_at_it():
    state = _state(x=[0.0, 0.0, 0.0], r1=1.0, r2=0.0, fun=1.0)
    for trial_fun in (1.0 - 1e-14, 1.0 + 1e-14):
        evaluate = _fabricated(START, (math.sqrt(trial_fun), 0.0))[0]
        after, _ = trial_step(PYTHON, evaluate, state, RUNNING, RUNNING, 0.01, [1e-3, 0.0, 0.0],
                              1e-16, LOWER, UPPER)
        assert after["status"] == RUNNING


# Slow steps and the turn to Newton steps ------------------------------------------------

@pytest.mark.parametrize(("slow_steps", "norm", "status", "after_slow"), [
    (2, 0.6, NEWTON, 3),     # the third slow step
    (1, 0.6, RUNNING, 2),    # the second
    (2, 0.5, RUNNING, 2),    # the gradient halved: not slow
])
def test_three_accepted_steps_that_do_not_halve_the_gradient_turn_to_newton_steps(
        slow_steps, norm, status, after_slow):
    state = _state(slow_steps=slow_steps, previous_norm=1.0, damping=0.02)
    predicted = _predicted(START, [0.05, -0.02, 0.01])
    evaluate = _fabricated(START, (math.sqrt(state["fun"] - 0.5 * predicted), 0.0))[0]
    after, moved = trial_step(PYTHON, evaluate, state, RUNNING, RUNNING, norm,
                              [0.05, -0.02, 0.01], None, LOWER, UPPER)
    assert moved
    assert (after["status"], after["slow_steps"], after["previous_norm"]) == (
        status, after_slow, norm)
    # Newton steps start undamped
    assert after["damping"] == (0.0 if status == NEWTON else pytest.approx(_nielsen(0.02, 0.5)))


def test_a_step_to_a_sum_of_squares_at_the_slow_level_is_not_slow():
    # residuals whose squares add up to SLOW_LEVEL exactly in floats
    trial = (math.nextafter(1e-10, 0.0), 9e-19)
    state = _state(slow_steps=2, previous_norm=1.0)
    evaluate = _fabricated(START, trial)[0]
    after, moved = trial_step(PYTHON, evaluate, state, RUNNING, RUNNING, 0.9,
                              [0.05, -0.02, 0.01], None, LOWER, UPPER)
    assert moved and after["fun"] == SLOW_LEVEL
    assert (after["status"], after["slow_steps"]) == (RUNNING, 2)


def test_an_accepted_newton_step_keeps_newton_mode_and_nielsens_damping():
    state, after, moved, ratio = _trial(0.5, mode=NEWTON, damping=0.02, slow_steps=5)
    assert moved and after["status"] == NEWTON
    assert after["damping"] == pytest.approx(_nielsen(0.02, ratio), rel=1e-12)


# One Newton iteration -------------------------------------------------------------------

HESSIAN = [[2.0, 0.5, 0.1], [0.5, 1.0, -0.2], [0.1, -0.2, 0.8]]
INDEFINITE = [[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 0.5]]


def _given_hessian(matrix, evaluations=3):
    calls = []

    def hessian_at(point, gradient, free, needed):
        calls.append(list(point))
        return [list(row) for row in matrix], evaluations

    return hessian_at, calls


def _newton(matrix, trial_residuals=(0.0, 0.0), point=START, ops=PYTHON, **changes):
    state = _state(point, status=NEWTON, **changes)
    evaluate, _ = _fabricated(point, trial_residuals)
    hessian_at, calls = _given_hessian(matrix)
    after = newton_iteration(ops, evaluate, hessian_at, state, LOWER, UPPER, 0.0, 10)
    return state, after, calls


def test_a_newton_step_solves_the_damped_hessian_system_and_charges_the_hessian_once():
    state, after, calls = _newton(HESSIAN, damping=0.01, hessian_counted=0)
    hessian = np.array(HESSIAN)
    gradient = _gradient(START)
    shift = 0.01 * np.max(np.abs(hessian))
    step = np.linalg.solve(hessian + shift * np.eye(3), -gradient)
    np.testing.assert_allclose(np.array(after["x"]) - START, step, rtol=1e-12, atol=1e-17)
    predicted = -(gradient @ step + 0.5 * step @ hessian @ step)
    ratio = state["fun"] / predicted
    assert after["damping"] == pytest.approx(_nielsen(0.01, ratio), rel=1e-9)
    assert (after["status"], after["nit"], after["nfev"], after["hessian_counted"]) == (
        NEWTON, 1, 1 + 1 + 3, 0)
    assert len(calls) == 1


def test_a_rejected_newton_step_keeps_its_hessian_counted_for_the_next_try():
    state, after, _ = _newton(HESSIAN, trial_residuals=(1.0, 0.0), damping=0.0,
                              hessian_counted=0)
    assert after["x"] == START
    assert (after["nfev"], after["hessian_counted"], after["damping"]) == (5, 1, NEWTON_DAMPING)
    # at the same point the Hessian is not charged again
    evaluate, _ = _fabricated(START, (1.0, 0.0))
    again = newton_iteration(PYTHON, evaluate, _given_hessian(HESSIAN)[0], after, LOWER, UPPER,
                             0.0, 10)
    assert (again["nfev"], again["hessian_counted"]) == (6, 1)


@pytest.mark.parametrize("damping", [0.01, 0.0])
def test_a_newton_step_on_a_bound_moves_only_the_free_variables(damping):
    # x2 on its upper bound pushed out: its row and column of the Hessian are left out,
    # large as they are, and the shift's scale is the free block's largest entry (0.2).
    point = ON_BOUND
    gradient = _gradient(point)
    assert gradient[2] < 0.0
    hessian = 0.1 * np.array(HESSIAN)
    hessian[2, :] = hessian[:, 2] = [3.0, -4.0, 5.0]
    _, after, _ = _newton(hessian.tolist(), point=point, damping=damping)
    block = hessian[:2, :2]
    step = np.linalg.solve(block + damping * 0.2 * np.eye(2), -gradient[:2])
    assert after["x"][2] == 1.0
    np.testing.assert_allclose(np.array(after["x"][:2]) - point[:2], step, rtol=1e-12)


def test_an_indefinite_hessian_is_shifted_just_past_its_lowest_eigenvalue():
    # Eigenvalues -1, 0.5 and 3: the shift is 1.01 * 1 + max(damping, 1e-8) * 2.
    assert np.linalg.eigvalsh(np.array(INDEFINITE))[0] == pytest.approx(-1.0, abs=1e-15)
    for damping, shift in ((0.0, 1.01 + 2e-8), (0.01, 1.01 + 0.02)):
        _, after, _ = _newton(INDEFINITE, damping=damping)
        step = np.linalg.solve(np.array(INDEFINITE) + shift * np.eye(3), -_gradient(START))
        np.testing.assert_allclose(np.array(after["x"]) - START, step, rtol=1e-9)
        assert after["status"] == NEWTON


def test_without_an_eigenvalue_solver_an_indefinite_hessian_is_handed_back_untaken():
    ops = replace(PYTHON, lowest_eigenvalue=None)
    state, after, _ = _newton(INDEFINITE, ops=ops, damping=0.0, hessian_counted=1)
    assert after == {**state, "status": NEWTON_INDEFINITE}
    # a definite one is taken as usual
    assert _newton(HESSIAN, ops=ops, damping=0.0)[1]["status"] == NEWTON


def test_a_hessian_entry_that_is_not_finite_gives_no_step():
    for bad in (math.nan, math.inf):
        matrix = [list(row) for row in HESSIAN]
        matrix[0][1] = bad
        state, after, _ = _newton(matrix, damping=0.0)
        assert after["x"] == START and after["status"] == 3


def test_a_newton_iteration_passes_an_ended_state_unchanged():
    for status in (0, 1, 3, RUNNING):
        state = _state(status=status)
        evaluate, asked = _fabricated(START, (0.0, 0.0))
        after = newton_iteration(PYTHON, evaluate, _given_hessian(HESSIAN)[0], state, LOWER,
                                 UPPER, 0.0, 10)
        assert after == state and asked == []


def _eigenvalue_reported_as(fraction):
    """An eigenvalue solver that reports ``fraction`` of the lowest eigenvalue (round-off
    made large)."""
    return lambda matrix: fraction * float(np.linalg.eigvalsh(np.array(matrix))[0])


def _rescued_shift(reported, damping, scale, lowest):
    """The shift past ``reported``, then tenfold (at least 1e-6 * scale) until the
    Hessian of lowest eigenvalue ``lowest`` is positive definite; the shifts tried."""
    shifts = [1.01 * max(-reported, 0.0) + max(damping, NEWTON_DAMPING) * scale]
    while lowest + shifts[-1] <= 0.0:
        shifts.append(max(10.0 * shifts[-1], 1e-6 * scale))
    return shifts


@pytest.mark.parametrize("lazy", [True, False])
def test_a_shift_that_leaves_the_hessian_indefinite_is_raised_tenfold(lazy):
    # Half the lowest eigenvalue reported (-0.5 for -1): 1.01 * 0.5 + 2e-8 leaves it
    # indefinite, ten times that does not.
    ops = replace(PYTHON, lazy=lazy, lowest_eigenvalue=_eigenvalue_reported_as(0.5))
    shifts = _rescued_shift(-0.5, 0.0, 2.0, -1.0)
    assert len(shifts) == 2
    _, after, _ = _newton(INDEFINITE, ops=ops, damping=0.0)
    step = np.linalg.solve(np.array(INDEFINITE) + shifts[-1] * np.eye(3), -_gradient(START))
    assert after["status"] == NEWTON
    np.testing.assert_allclose(np.array(after["x"]) - START, step, rtol=1e-12)


def test_the_tenfold_shifts_start_at_a_millionth_of_the_hessian_s_scale():
    # No negative eigenvalue reported: 2e-8, then 2e-6, 2e-5, ... 2: seven tenfold
    # shifts, which plain floats take to the end.
    ops = replace(PYTHON, lowest_eigenvalue=_eigenvalue_reported_as(0.0))
    shifts = _rescued_shift(0.0, 0.0, 2.0, -1.0)
    assert shifts[:3] == [2e-8, 2e-6, pytest.approx(2e-5, rel=1e-15)] and len(shifts) == 8
    _, after, _ = _newton(INDEFINITE, ops=ops, damping=0.0)
    step = np.linalg.solve(np.array(INDEFINITE) + shifts[-1] * np.eye(3), -_gradient(START))
    np.testing.assert_allclose(np.array(after["x"]) - START, step, rtol=1e-12)


def test_a_backend_of_fixed_rounds_hands_the_step_back_after_four_tenfold_shifts():
    # As above on arrays or symbols (not lazy): four tenfold shifts (to 2e-3) leave the
    # Hessian indefinite, so the state is handed back untaken.
    ops = replace(PYTHON, lazy=False, lowest_eigenvalue=_eigenvalue_reported_as(0.0))
    state, after, _ = _newton(INDEFINITE, ops=ops, damping=0.0)
    assert after == {**state, "status": NEWTON_INDEFINITE}
    # one tenfold shift fewer needed (half the eigenvalue reported) and it is taken
    ops = replace(ops, lowest_eigenvalue=_eigenvalue_reported_as(0.5))
    assert _newton(INDEFINITE, ops=ops, damping=0.0)[1]["status"] == NEWTON


@pytest.mark.parametrize(("reported", "taken"), [(1.98e-4, True), (1.98e-5, False)])
def test_a_backend_of_fixed_rounds_tries_four_tenfold_shifts_and_no_more(reported, taken):
    # A shift of about 2e-4 past the reported eigenvalue needs four tenfold shifts (to
    # 2), one of 2e-5 five.
    ops = replace(PYTHON, lazy=False, lowest_eigenvalue=_eigenvalue_reported_as(reported))
    shifts = _rescued_shift(-reported, 0.0, 2.0, -1.0)
    assert len(shifts) == (5 if taken else 6)
    state, after, _ = _newton(INDEFINITE, ops=ops, damping=0.0)
    if not taken:
        assert after == {**state, "status": NEWTON_INDEFINITE}
        return
    step = np.linalg.solve(np.array(INDEFINITE) + shifts[-1] * np.eye(3), -_gradient(START))
    assert after["status"] == NEWTON
    np.testing.assert_allclose(np.array(after["x"]) - START, step, rtol=1e-12)
