"""The choice within a set of exact optima and the search of its extent, on sets known in
closed form.

The set is the quarter circle ``x0^2 + x1^2 = R^2``, ``x2 = 1/2`` in the box ``[0, 1]^3``
(residual ``rho = x0^2 + x1^2 - R^2 + i (x2 - 1/2)``). By hand: it meets the bounds
``x0 = 0`` and ``x1 = 0`` (at ``(0, R)`` and ``(R, 0)``) and, for ``R < 1``, never the
bounds ``x0 = 1`` or ``x1 = 1``, so those ends of its extent are ``R``, found by
bisection (a lower estimate within the bisection's bracket), not the bounds; its point
of largest margin to the bounds is ``(R, R) / sqrt 2``, margin ``1 - R / sqrt 2``
(``R > sqrt 2 / 2``: the upper bounds are the nearer ones there, and ``x2``'s margin is
1/2); ``x2`` has the single value 1/2 on the set, an extent that reaches neither bound.
"""

import functools
import math

import numpy as np
import pytest

from sso._shafts.exact_optima import (
    EXTENT_HALVINGS,
    EXTENT_PROBES,
    MARGIN_RESOLUTION,
    SetProblem,
    _minimised,
    choose_exact_optimum,
    is_exact,
    set_extent,
)

MARGIN_STEP = 1e-3
"""The margin's unit in the solver's units (as a column's millimetres in metres)."""


def _circle(radius):
    def residuals(x):
        return complex(x[0] * x[0] + x[1] * x[1] - radius * radius, x[2] - 0.5), [
            complex(2.0 * x[0], 0.0), complex(2.0 * x[1], 0.0), 1j]

    return residuals


def _problem():
    return SetProblem(lower=np.zeros(3), upper=np.ones(3), variables=("x0", "x1", "x2"),
                      units=("mm",) * 3, scale=np.full(3, 1.0 / MARGIN_STEP),
                      in_margin=np.ones(3, dtype=bool), margin_step=MARGIN_STEP,
                      margin_unit="mm")


def _extent(radius):
    residuals = _circle(radius)
    chosen = np.array([0.6 * radius, 0.8 * radius, 0.5])
    return set_extent(_problem(), residuals, functools.partial(_minimised, residuals), chosen)


def test_a_set_that_reaches_a_bound_ends_on_it_and_one_that_stops_short_is_bisected():
    radius = 1.0 - 1e-9  # RE pinned at x0 = 1 is (1 - R^2)^2 = 4e-18: not round-off zero
    search = _extent(radius)
    # the bisection's bracket: 0.4 R (chosen to bound) halved EXTENT_HALVINGS times
    bracket = 0.4 * radius / 2 ** EXTENT_HALVINGS
    *circle, middle = search.ends
    for index, (low, high) in enumerate(circle):
        # towards 0 the set reaches the bound: exact, with a witness on it
        assert low.at_bound and low.value == 0.0 and low.witness[index] == 0.0
        other = low.witness[1 - index] * MARGIN_STEP
        # RE <= 1e-20 leaves |x| within 1e-10 / (2 R) of R
        assert other == pytest.approx(radius, abs=1e-10)
        # towards 1 it stops at R, 1e-9 short: a lower estimate within the bracket
        assert not high.at_bound
        value = high.value * MARGIN_STEP
        assert radius - bracket <= value <= radius
        assert high.witness[index] == high.value
        witness = np.array(high.witness) * MARGIN_STEP
        assert np.hypot(*witness[:2]) == pytest.approx(radius, abs=1e-10)
        assert is_exact(high.witness_residual_error)
    # x2 is 1/2 on the whole set: no halving lands, both ends stay at the chosen value
    for end in middle:
        assert not end.at_bound and end.value == 0.5 / MARGIN_STEP
    # per end: the chosen design and every probe at the bound, then two starts a halving
    assert search.probes == EXTENT_PROBES
    assert search.solves <= 6 * (1 + EXTENT_PROBES + 2 * EXTENT_HALVINGS)


def test_a_set_that_reaches_past_the_bound_ends_exactly_on_it():
    # R = 1.2: the arc in the box runs from (sqrt 0.44, 1) to (1, sqrt 0.44), so each of
    # x0, x1 reaches its upper bound and stops short of its lower one, at sqrt 0.44
    radius = 1.2
    search = _extent(radius)
    chosen = (0.6 * radius, 0.8 * radius)
    for index, (low, high) in enumerate(search.ends[:2]):
        assert high.at_bound and high.value == 1.0 / MARGIN_STEP
        assert high.witness[1 - index] * MARGIN_STEP == pytest.approx(math.sqrt(0.44),
                                                                      abs=1e-10)
        assert not low.at_bound
        bracket = chosen[index] / 2 ** EXTENT_HALVINGS
        assert math.sqrt(0.44) <= low.value * MARGIN_STEP <= math.sqrt(0.44) + bracket


def test_is_exact_takes_round_off_zero_only():
    # ZERO_OBJECTIVE = 1e-20: sqrt(RE) 1e-10, far above the 1e-16 round-off of a residual
    # of order one, far below any RE a design is sought for
    assert is_exact(0.0) and is_exact(1e-20)
    assert not is_exact(4e-18) and not is_exact(math.nan) and not is_exact(math.inf)


@pytest.mark.parametrize("first", [(0.96, 0.28, 0.5), (0.28, 0.96, 0.5), (0.6, 0.8, 0.5)])
def test_the_chosen_exact_optimum_has_the_largest_margin(first):
    radius = 1.0
    residuals = _circle(radius)
    problem = _problem()
    choice = choose_exact_optimum(problem, residuals, functools.partial(_minimised, residuals),
                                  [np.array(first)], None)
    best = 1.0 - radius / math.sqrt(2.0)
    chosen = choice.x
    assert np.hypot(*chosen[:2]) == pytest.approx(radius, abs=1e-10)
    assert chosen[2] == pytest.approx(0.5, abs=1e-10)
    margin = min(*chosen, *(1.0 - chosen))
    # the margin's bisection stops at a bracket of MARGIN_RESOLUTION margin units
    assert best - MARGIN_RESOLUTION * MARGIN_STEP <= margin <= best
    exact_set = choice.exact_set
    assert exact_set.margin == pytest.approx(margin / MARGIN_STEP, rel=1e-12)
    assert exact_set.first_margin == pytest.approx(min(*first, *(1.0 - np.array(first)))
                                                   / MARGIN_STEP, rel=1e-12)
    assert exact_set.chosen == pytest.approx(tuple(chosen / MARGIN_STEP), rel=1e-15)
    assert exact_set.dimension == 1  # two variables, one real residual
    assert exact_set.starts == 1
    assert choice.solver == "lm"  # the bisection moved the design


def _recording(residuals):
    calls = []

    def solve(start, lower, upper, max_iterations):
        answer = _minimised(residuals, start, lower, upper, max_iterations)
        calls.append(answer)
        return answer

    return calls, solve


def test_the_choice_counts_its_solves_and_keeps_a_first_found_that_is_best():
    radius = 1.0
    residuals = _circle(radius)
    problem = _problem()
    # from (0.96, 0.28): the bisection moves the design; its solves are counted
    calls, solve = _recording(residuals)
    first = np.array([0.96, 0.28, 0.5])
    choice = choose_exact_optimum(problem, residuals, solve, [first], None)
    assert calls
    assert choice.nit == sum(call[2] for call in calls)
    assert choice.nfev == sum(call[3] for call in calls)
    assert choice.exact_set.first_found == pytest.approx(tuple(first / MARGIN_STEP), rel=1e-15)
    assert 0.0 <= choice.exact_set.time_s < 60.0
    # from the point of largest margin itself: no margin above it is feasible, the
    # design stays, and nobody moved it
    best = np.array([radius / math.sqrt(2.0), radius / math.sqrt(2.0), 0.5])
    again = choose_exact_optimum(problem, residuals, solve, [best], None)
    np.testing.assert_array_equal(again.x, best)
    assert again.solver is None


def test_the_margin_counts_only_its_variables_and_measures_from_each_bound():
    # x2 (fixed at 1/2 on the set) has bounds [0.45, 0.55] but is not in the margin: the
    # margin is the circle's, 1 - R / sqrt 2, as if x2 were unbounded
    residuals = _circle(1.0)
    problem = SetProblem(lower=np.array([0.0, 0.0, 0.45]), upper=np.array([1.0, 1.0, 0.55]),
                         variables=("x0", "x1", "x2"), units=("mm",) * 3,
                         scale=np.full(3, 1.0 / MARGIN_STEP),
                         in_margin=np.array([True, True, False]), margin_step=MARGIN_STEP,
                         margin_unit="mm")
    choice = choose_exact_optimum(problem, residuals, functools.partial(_minimised, residuals),
                                  [np.array([0.96, 0.28, 0.5])], None)
    best = 1.0 - 1.0 / math.sqrt(2.0)
    assert best - MARGIN_RESOLUTION * MARGIN_STEP <= choice.exact_set.margin * MARGIN_STEP <= best
    # lower bounds of 0.1 and a circle of 0.6: the lower bounds bind, margin
    # 0.6 / sqrt 2 - 0.1 at the diagonal
    small = _circle(0.6)
    shifted = SetProblem(lower=np.full(3, 0.1), upper=np.ones(3), variables=("x0", "x1", "x2"),
                         units=("mm",) * 3, scale=np.full(3, 1.0 / MARGIN_STEP),
                         in_margin=np.array([True, True, False]), margin_step=MARGIN_STEP,
                         margin_unit="mm")
    choice = choose_exact_optimum(shifted, small, functools.partial(_minimised, small),
                                  [np.array([0.55, math.sqrt(0.36 - 0.55 ** 2), 0.5])], None)
    best = 0.6 / math.sqrt(2.0) - 0.1
    assert best - MARGIN_RESOLUTION * MARGIN_STEP <= choice.exact_set.margin * MARGIN_STEP <= best
    assert choice.exact_set.margin * MARGIN_STEP == pytest.approx(min(choice.x[:2]) - 0.1,
                                                                  rel=1e-12)


def test_a_chosen_design_on_a_bound_is_that_end():
    radius = 1.0 - 1e-9
    residuals = _circle(radius)
    chosen = np.array([0.0, radius, 0.5])
    search = set_extent(_problem(), residuals, functools.partial(_minimised, residuals), chosen)
    low = search.ends[0][0]
    assert low.at_bound and low.value == 0.0
    assert low.witness == pytest.approx(tuple(chosen / MARGIN_STEP), rel=1e-15)


@pytest.mark.parametrize(("radius", "lower", "start", "expected"), [
    # off the circle inside the box: minimum-norm Gauss-Newton steps back onto it
    (1.0, 0.0, (0.5, 0.5, 0.6), None),
    # x0 beyond its upper bound: clipped onto it, held there, x1 solves 1 + x1^2 = 1.21
    (1.1, 0.0, (1.2, 0.4, 0.5), (1.0, math.sqrt(0.21), 0.5)),
    # x0 below its lower bound 0.2: clipped onto it, x1 solves 0.04 + x1^2 = 0.64
    (0.8, 0.2, (0.1, 0.7, 0.5), (0.2, math.sqrt(0.6), 0.5)),
])
def test_the_projection_onto_the_set(radius, lower, start, expected):
    from sso._shafts.exact_optima import _project

    residuals = _circle(radius)
    lower_bounds = np.array([lower, 0.0, 0.0])
    x = _project(residuals, np.array(start), lower_bounds, np.ones(3))
    assert x is not None
    assert abs(residuals(x.tolist())[0]) ** 2 <= 1e-20
    assert np.all(x >= lower_bounds) and np.all(x <= 1.0)
    if expected is None:
        # the minimum-norm steps move along the gradient (x0 = x1 by symmetry) and x2 alone
        assert x[0] == pytest.approx(x[1], abs=1e-15)
        assert x[0] == pytest.approx(1.0 / math.sqrt(2.0), abs=1e-10)
        assert x[2] == pytest.approx(0.5, abs=1e-12)
    else:
        np.testing.assert_allclose(x, expected, atol=1e-10)
        assert x[0] == expected[0]  # held on its bound exactly


def test_a_projection_that_cannot_reach_the_set_gives_none():
    from sso._shafts.exact_optima import _project

    # R = 1.5 lies outside the unit box (x0^2 + x1^2 <= 2 < 2.25)
    assert _project(_circle(1.5), np.array([0.9, 0.9, 0.5]), np.zeros(3), np.ones(3)) is None
