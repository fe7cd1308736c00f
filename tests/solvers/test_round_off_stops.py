"""Stops at round-off tested by moving one variable at a time (sso._solvers.round_off_stops).

References are closed-form sums of squares whose minima are known: ``(x0 - 1)^2 +
(x1 + 2)^2`` (minimum at (1, -2)) and a narrow valley ``(1e8 (x0 - x1))^2 + (x0 - 3)^2``.
"""

from __future__ import annotations

import numpy as np
import pytest

from sso._solvers import round_off_stops


def bowl(point):
    return (point[0] - 1.0) ** 2 + (point[1] + 2.0) ** 2


def bowl_rows(points, rows):
    return (points[:, 0] - 1.0) ** 2 + (points[:, 1] + 2.0) ** 2


LOWER, UPPER = [-10.0, -10.0], [10.0, 10.0]


def test_a_minimum_holds_and_costs_every_probe():
    holds, evaluations = round_off_stops.holds(bowl, [1.0, -2.0], 0.0, LOWER, UPPER)
    assert holds
    assert evaluations == 2 * 2 * len(round_off_stops.PROBE_STEPS)


def test_a_point_off_the_minimum_is_refuted_by_the_first_improving_move():
    # 1e-3 from the minimum in x0: the move of 1e-3 towards it lowers the sum to 0.
    holds, evaluations = round_off_stops.holds(bowl, [1.001, -2.0], 1e-6, LOWER, UPPER)
    assert not holds
    assert evaluations <= 2 * len(round_off_stops.PROBE_STEPS)


def test_moves_outside_the_bounds_are_not_tried():
    # On the bound x0 = 2 of [2, 10], the only improving move leaves the bounds.
    holds, _ = round_off_stops.holds(bowl, [2.0, -2.0], 1.0, [2.0, -10.0], UPPER)
    assert holds


def test_a_decrease_below_the_fraction_does_not_refute():
    # 1 + (x0 - 1)^2 at x0 = 1 + 1e-6: the best move (1e-6) lowers the sum by 1e-12 of it.
    def raised(point):
        return 1.0 + (point[0] - 1.0) ** 2

    point = [1.0 + 1e-6, 0.0]
    assert round_off_stops.holds(raised, point, raised(point), LOWER, UPPER)[0]
    point = [1.0 + 1e-2, 0.0]  # here a move of 1e-3 lowers it by 2e-5 of it: refuted
    assert not round_off_stops.holds(raised, point, raised(point), LOWER, UPPER)[0]


def test_the_batched_test_agrees_with_the_single_one():
    x = np.array([[1.0, -2.0], [1.001, -2.0], [2.0, -2.0], [1.0, -2.5]])
    fun = bowl_rows(x, None)
    lower, upper = np.array([-10.0, -10.0]), np.array([10.0, 10.0])
    rows = np.arange(len(x))
    refuted = round_off_stops.refuted(bowl_rows, x, fun, lower, upper, rows)
    single = [not round_off_stops.holds(bowl, list(point), value, LOWER, UPPER)[0]
              for point, value in zip(x.tolist(), fun.tolist(), strict=True)]
    assert refuted.tolist() == single == [False, True, True, True]
    # Only the rows asked for are tested.
    assert round_off_stops.refuted(bowl_rows, x, fun, lower, upper, rows[:1]).tolist() == [False]


@pytest.mark.parametrize("x0", [3.0, 3.0 + 1e-7])
def test_a_narrow_valley_s_floor_holds_only_where_no_single_move_helps(x0):
    # Along the valley floor x0 = x1 the sum is (x0 - 3)^2; a move of one variable leaves
    # the floor and costs (1e8 step)^2, far more than it saves: each such point holds,
    # although only (3, 3) is the minimum. The test refutes stops, it does not find minima.
    def valley(point):
        return (1e8 * (point[0] - point[1])) ** 2 + (point[0] - 3.0) ** 2

    point = [x0, x0]
    assert round_off_stops.holds(valley, point, valley(point), LOWER, UPPER)[0]
