"""The saddle check's rules one by one, on small objectives whose derivatives are known by
hand: which variables it may move, where it clips, its thresholds, the branches at the
start, the escape step and the counts it reports (written after mutation testing showed
each rule could change unseen; docs/mutation-testing.md).

Every objective is ``p[0]`` times a polynomial in ``x`` (``p = [1]``), so its gradient and
Hessian are written out in each docstring.
"""

from __future__ import annotations

import math
from dataclasses import replace

import casadi
import numpy as np
import pytest
from solvers.problems import BOX, PARAMETERS, bowl, saddle

from sso._solvers import slsqp
from sso._solvers.nlp import compile_nlp
from sso._solvers.run import RunLimits
from sso._solvers.saddle import (
    isolated_minimum,
    saddle_direction,
    solve_with_second_order_care,
)


def _nlp(objective_of, variables=2):
    x, p = casadi.SX.sym("x", variables), casadi.SX.sym("p", 1)
    return compile_nlp("test_saddle_rules", x, p, p[0] * objective_of(x))


def _limits(x1_bounds, variables=2):
    lower = np.full(variables, -2.0)
    upper = np.full(variables, 2.0)
    lower[1], upper[1] = x1_bounds
    return RunLimits(lower, upper)


# f = x0^2 - (x1 - c)^2 + s (x1 - c): Hessian diag(2, -2) everywhere; at x1 = c the slope in
# x1 is s. x0 is free with positive curvature, so a direction is found exactly when x1 may
# move (free) and None when x1 is held.
MOVABLE = [
    # (x1 bounds, x1, c, s, x1 may move)
    ((-2.0, 2.0), 0.0, 0.0, 0.1, True),  # inside the bounds a slope holds nothing
    ((-2.0, 2.0), 0.0, 0.0, -0.1, True),
    ((-3.0, -1.0), -2.0, -2.0, -0.1, True),
    ((0.0, 1.0), 0.0, 0.0, 0.0, True),  # on a bound, no slope: free (a symmetric point)
    ((-1.0, 0.0), 0.0, 0.0, 0.0, True),
    ((0.0, 1.0), 0.0, 0.0, 1e-12, True),  # a slope of STATIONARY_START is no push
    ((-1.0, 0.0), 0.0, 0.0, -1e-12, True),
    ((0.0, 1.0), 0.0, 0.0, 0.1, False),  # pushed against its lower bound: held
    ((-1.0, 0.0), 0.0, 0.0, -0.1, False),  # against its upper bound
    ((0.0, 1.0), 1e-9, 0.0, 0.1, False),  # ON_BOUND (1e-9) from it is on it
    ((-1.0, 0.0), -1e-9, 0.0, -0.1, False),
    ((0.0, 0.0), 0.0, 0.0, 0.0, False),  # pinned by its bounds
    ((0.0, 1e-9), 0.0, 0.0, 0.0, False),  # bounds ON_BOUND apart pin it
]


@pytest.mark.parametrize(("bounds", "x1", "centre", "slope", "moves"), MOVABLE)
def test_the_variables_the_check_may_move(bounds, x1, centre, slope, moves):
    nlp = _nlp(lambda x: x[0] ** 2 - (x[1] - centre) ** 2 + slope * (x[1] - centre))
    found = saddle_direction(nlp, True, 0.0, [0.0, x1], PARAMETERS, _limits(bounds))
    assert (found is not None) == moves
    if moves:
        point, direction = found
        np.testing.assert_array_equal(point, [0.0, x1])
        np.testing.assert_allclose(np.abs(direction), [0.0, 1.0], atol=1e-9)


@pytest.mark.parametrize(("bounds", "x1", "cubic"), [((0.0, 1.0), -0.1, 1.0),
                                                       ((-1.0, 0.0), 0.1, -1.0)])
def test_a_point_outside_the_bounds_is_judged_where_it_is_clipped_to(bounds, x1, cubic):
    # f = x0^2 + k x1^3: curvature 6 k x1 in x1, zero on the bound x1 = 0 (no saddle, no
    # isolated minimum) and -0.6 at the given point outside the bounds (+0.6 for -k)
    limits = _limits(bounds)
    assert saddle_direction(_nlp(lambda x: x[0] ** 2 + cubic * x[1] ** 3), True, 0.0,
                            [0.0, x1], PARAMETERS, limits) is None
    assert not isolated_minimum(_nlp(lambda x: x[0] ** 2 - cubic * x[1] ** 3),
                                np.array([0.0, x1]), PARAMETERS, limits)


def test_the_largest_eigenvalue_scales_the_threshold():
    # f = (x0^2 + x1^2) / 2 + (1 + d) x0 x1 + x2^2 / 4: eigenvalues -d, 1/2 and 2 + d; with
    # d = 1.5e-6 the smallest lies above -1e-6 (2 + d), the stated threshold relative to the
    # largest, though below -1e-6 times the largest diagonal entry: not a saddle
    d = 1.5e-6
    nlp = _nlp(lambda x: 0.5 * (x[0] ** 2 + x[1] ** 2) + (1 + d) * x[0] * x[1]
               + 0.25 * x[2] ** 2, variables=3)
    box = RunLimits(np.full(3, -2.0), np.full(3, 2.0))
    assert saddle_direction(nlp, True, 0.0, [0.0, 0.0, 0.0], PARAMETERS, box) is None
    # 1e-7 x0^2 + 1e-7 x1^2 + x2^2: eigenvalues 2e-7, 2e-7, 2: flat next to 1e-6 * 2
    flat = _nlp(lambda x: 1e-7 * x[0] ** 2 + 1e-7 * x[1] ** 2 + x[2] ** 2, variables=3)
    assert not isolated_minimum(flat, np.zeros(3), PARAMETERS, box)
    steep = _nlp(lambda x: 1e-5 * x[0] ** 2 + 1e-5 * x[1] ** 2 + x[2] ** 2, variables=3)
    assert isolated_minimum(steep, np.zeros(3), PARAMETERS, box)


def test_isolated_minimum_in_its_special_cases():
    # with constraint functions: not judged
    constrained = RunLimits(BOX.lower, BOX.upper, np.array([0.0]), np.array([1.0]))
    assert not isolated_minimum(bowl(), np.zeros(2), PARAMETERS, constrained)
    # every variable pinned: nothing can move, the point is isolated
    pinned = RunLimits(np.zeros(2), np.zeros(2))
    assert isolated_minimum(saddle(), np.zeros(2), PARAMETERS, pinned)
    # a Hessian that is not finite (sqrt(x1 + 1e-5) has no value at x1 - 1e-4): not judged
    root = _nlp(lambda x: x[0] ** 2 + x[1] ** 2 + casadi.sqrt(x[1] + 1e-5))
    assert not isolated_minimum(root, np.zeros(2), PARAMETERS, BOX)
    # the parameters enter: p = 1 gives the bowl's curvature
    assert isolated_minimum(bowl(), np.zeros(2), PARAMETERS, BOX)


def _least_squares(residuals, variables):
    """A nonnegative objective ``r1^2 + r2^2`` with its residuals, as the shaft problems
    give them (``residuals_and_jacobian``)."""
    x, p = casadi.SX.sym("x", variables), casadi.SX.sym("p", 1)
    r1, r2 = residuals(x)
    nlp = compile_nlp("test_least_squares", x, p, p[0] * (r1 ** 2 + r2 ** 2))
    function = casadi.Function("r", [x], [r1, r2, casadi.jacobian(casadi.vertcat(r1, r2), x)])

    def residuals_and_jacobian(point, parameters):
        first, second, jacobian = function(point)
        rows = np.array(jacobian)
        return (complex(float(first), float(second)),
                [complex(a, b) for a, b in zip(rows[0], rows[1], strict=True)])

    return replace(nlp, nonnegative_objective=True, residuals_and_jacobian=residuals_and_jacobian)


def test_a_least_squares_zero_is_isolated_only_with_two_variables_free():
    # r = (x0 - 1/2, x1 - 1/4): one zero, Hessian 2 I: isolated
    two = _least_squares(lambda x: (x[0] - 0.5, x[1] - 0.25), 2)
    assert isolated_minimum(two, np.array([0.5, 0.25]), PARAMETERS, BOX)
    # r = (x0 + x1 - 1, x2): zero on a line, Hessian rank 2 of 3: not isolated
    three = _least_squares(lambda x: (x[0] + x[1] - 1.0, x[2]), 3)
    box = RunLimits(np.full(3, -2.0), np.full(3, 2.0))
    assert not isolated_minimum(three, np.array([0.5, 0.5, 0.0]), PARAMETERS, box)
    # a nonnegative objective that is no sum of squares is judged by its Hessian
    for variables in (2, 3):
        nlp = replace(_nlp(lambda x: casadi.sumsqr(x), variables), nonnegative_objective=True)
        limits = RunLimits(np.full(variables, -2.0), np.full(variables, 2.0))
        assert isolated_minimum(nlp, np.zeros(variables), PARAMETERS, limits)


def _recorded(nlp, limits, check_start=True):
    """``solve_with_second_order_care`` with SLSQP, each leg's start and outcome kept."""
    legs = []

    def solve(start):
        outcome = slsqp.solve(nlp, start, PARAMETERS, limits, 1e-12, 500)
        legs.append((np.array(start), outcome))
        return outcome

    return legs, solve


def test_every_evaluation_of_the_checks_is_counted():
    nlp = saddle()
    legs, solve = _recorded(nlp, BOX)
    outcome = solve_with_second_order_care(solve, nlp, np.zeros(2), PARAMETERS, BOX, 1e-12)
    assert len(legs) == 2
    first, second = legs[0][1], legs[1][1]
    # the start: its value and gradient (1, 1), the curvature check's gradient and the
    # difference Hessian's 2 n = 4 gradients; at the first leg's end the same 1 + 4
    # gradients and the escape's value and one candidate (+-0.1 along x1 already
    # descends); at the second leg's end 1 + 4 gradients again
    assert outcome.nfev == first.nfev + second.nfev + 1 + 2
    assert outcome.njev == first.njev + second.njev + 1 + 5 + 5 + 5
    assert outcome.nit == first.nit + second.nit
    assert 0.0 < outcome.time_s < 60.0
    escape = legs[1][0]
    assert escape[0] == pytest.approx(0.0, abs=1e-9)
    assert abs(escape[1]) == pytest.approx(0.1, abs=1e-9)


def test_the_checks_of_a_run_that_skips_the_start_are_counted():
    # "lm"-like: no look at the start; the run ends at the bowl's minimum and the check
    # there costs 1 + 4 gradients and no value
    nlp = bowl()
    legs, solve = _recorded(nlp, BOX)
    outcome = solve_with_second_order_care(solve, nlp, np.array([1.0, -0.5]), PARAMETERS, BOX,
                                           1e-12, check_start=False)
    assert len(legs) == 1
    assert (outcome.nfev, outcome.njev) == (legs[0][1].nfev, legs[0][1].njev + 5)


def test_a_closed_form_hessian_is_used_and_counted_as_one_gradient():
    # x0^2 - x1^2 + x1^4 / 4: Hessian diag(2, -2 + 3 x1^2), by hand
    calls = []

    def hessian(point, parameters):
        calls.append(list(point))
        return [[2.0, 0.0], [0.0, -2.0 + 3.0 * point[1] ** 2]]

    nlp = replace(saddle(), objective_hessian=hessian)
    legs, solve = _recorded(nlp, BOX)
    outcome = solve_with_second_order_care(solve, nlp, np.zeros(2), PARAMETERS, BOX, 1e-12)
    assert len(calls) == 3  # the start, each leg's end
    first, second = legs[0][1], legs[1][1]
    assert outcome.njev == first.njev + second.njev + 1 + 2 + 2 + 2


@pytest.mark.parametrize(("cubic", "side"), [(12.0, -1.0), (-12.0, 1.0)])
def test_the_escape_takes_the_first_side_that_descends(cubic, side):
    # x0^2 - x1^2 + k x1^3: at x1 = +-0.1 the value is -0.01 +- 0.012 k / 12, so only the
    # side -sign(k) descends at the first step
    nlp = _nlp(lambda x: x[0] ** 2 - x[1] ** 2 + cubic * x[1] ** 3)
    legs, solve = _recorded(nlp, BOX)
    solve_with_second_order_care(solve, nlp, np.zeros(2), PARAMETERS, BOX, 1e-12)
    np.testing.assert_allclose(legs[1][0], [0.0, side * 0.1], atol=1e-9)


def test_the_escape_step_is_quartered_until_it_descends():
    # x0^2 - x1^2 + 200 x1^4: +-0.1 rises (+0.01), +-0.025 falls (-4.7e-4)
    nlp = _nlp(lambda x: x[0] ** 2 - x[1] ** 2 + 200.0 * x[1] ** 4)
    legs, solve = _recorded(nlp, BOX)
    solve_with_second_order_care(solve, nlp, np.zeros(2), PARAMETERS, BOX, 1e-12)
    assert abs(legs[1][0][1]) == pytest.approx(0.025, abs=1e-9)


@pytest.mark.parametrize("bounds", [(0.0, 1.0), (-1.0, 0.0)])
def test_the_escape_stays_within_the_bounds(bounds):
    # the saddle on a bound of x1: the step out of the box is clipped back onto the bound,
    # where the value does not fall, so the escape goes into the box
    limits = _limits(bounds)
    legs, solve = _recorded(saddle(), limits)
    solve_with_second_order_care(solve, saddle(), np.zeros(2), PARAMETERS, limits, 1e-12)
    inside = 0.1 if bounds[0] == 0.0 else -0.1
    np.testing.assert_allclose(legs[1][0], [0.0, inside], atol=1e-9)


def _start_outcome(nlp, start, limits=BOX):
    calls = []

    def solve(point):
        calls.append(point)
        return slsqp.solve(nlp, point, PARAMETERS, limits, 1e-12, 500)

    outcome = solve_with_second_order_care(solve, nlp, start, PARAMETERS, limits, 1e-12)
    return calls, outcome


GLOBAL = ("start is a global minimum (nonnegative objective at round-off zero): solver "
          "not run")
STATIONARY = ("start is a minimum to tolerance (stationary, no negative curvature): solver "
              "not run")


@pytest.mark.parametrize("floor", [0.0, 1e-20])
def test_a_start_at_round_off_zero_of_a_nonnegative_objective_is_the_answer(floor):
    # x0^2 + x1^2 + floor, declared nonnegative: at the origin RE-like value 0 or 1e-20
    x, p = casadi.SX.sym("x", 2), casadi.SX.sym("p", 1)
    nlp = replace(compile_nlp("test_floor", x, p, p[0] * (x[0] ** 2 + x[1] ** 2) + floor),
                  nonnegative_objective=True)
    start = np.zeros(2)
    calls, outcome = _start_outcome(nlp, start)
    assert calls == []
    np.testing.assert_array_equal(outcome.x, start)
    assert (outcome.fun, outcome.nit, outcome.nfev, outcome.njev, outcome.status,
            outcome.success, outcome.message) == (floor, 0, 1, 1, 0, True, GLOBAL)
    assert 0.0 <= outcome.time_s < 60.0
    # at 1e-20 and below no saddle check either
    assert saddle_direction(nlp, True, 1e-20, [0.0, 0.0], PARAMETERS, BOX) is None


def test_a_stationary_start_without_negative_curvature_is_the_answer():
    # x0^2 + x1^2 + 1e-12 x0: gradient (1e-12, 0) at the origin, as large as
    # STATIONARY_START and the tolerance allow; curvature 2, 2
    nlp = _nlp(lambda x: x[0] ** 2 + x[1] ** 2 + 1e-12 * x[0])
    start = np.zeros(2)
    calls, outcome = _start_outcome(nlp, start)
    assert calls == []
    np.testing.assert_array_equal(outcome.x, start)
    assert (outcome.fun, outcome.nit, outcome.nfev, outcome.njev, outcome.status,
            outcome.success, outcome.message) == (0.0, 0, 1, 1 + 1 + 4, 0, True, STATIONARY)


def test_limits_may_be_given_as_a_function():
    found = saddle_direction(saddle(), True, 0.0, [0.0, 0.0], PARAMETERS, lambda: BOX)
    assert found is not None
    np.testing.assert_allclose(np.abs(found[1]), [0.0, 1.0], atol=1e-9)
    assert math.isfinite(found[0][0])


@pytest.mark.parametrize(("bounds", "x1", "slope"), [((0.0, 1.0), -0.1, -0.2),
                                                      ((-1.0, 0.0), 0.1, 0.2)])
def test_the_saddle_point_reported_is_clipped_into_the_bounds(bounds, x1, slope):
    # x0^2 - x1^2 + s x1 (s = -+0.2): a saddle along x1 both at the given point outside the
    # bounds (slope 0 there) and at the bound x1 = 0 it is clipped to (slope s, pointing into
    # the box): the point reported is the clipped one
    nlp = _nlp(lambda x: x[0] ** 2 - x[1] ** 2 + slope * x[1])
    found = saddle_direction(nlp, True, 0.0, [0.0, x1], PARAMETERS, _limits(bounds))
    assert found is not None
    np.testing.assert_array_equal(found[0], [0.0, 0.0])
