"""The vector-loop building blocks against hand-computed geometry.

References: a 3-4-5 right triangle (circles of radius 5 about 0 and 8 meet at
4 +- 3i), and a linear system whose solution is chosen first and then multiplied out.
"""

from __future__ import annotations

import numpy as np
import pytest

from sso._kinematics.vector_loop import (
    circle_circle_intersection,
    circle_horizontal_line_intersection,
    solve_real_pair,
)


def test_circles_meet_at_the_3_4_5_points_and_side_picks_left_or_right():
    left, meets = circle_circle_intersection(0.0, 5.0, 8.0, 5.0, side=1)
    right, _ = circle_circle_intersection(0.0, 5.0, 8.0, 5.0, side=-1)
    assert bool(meets)
    assert left == pytest.approx(4.0 + 3.0j, abs=1e-15)
    assert right == pytest.approx(4.0 - 3.0j, abs=1e-15)
    # Reversing the direction of the line swaps left and right.
    reversed_left, _ = circle_circle_intersection(8.0, 5.0, 0.0, 5.0, side=1)
    assert reversed_left == pytest.approx(4.0 - 3.0j, abs=1e-15)


def test_circle_intersection_is_element_wise_and_marks_misses():
    centres = np.array([8.0 * np.exp(1j * np.pi / 6), 10.0, 11.0, 0.0])
    points, meets = circle_circle_intersection(0.0, 5.0, centres, 5.0, side=1)
    assert meets.tolist() == [
        True,
        True,
        False,
        False,
    ]  # 10 touches; 11 misses; 0 coincides
    assert abs(points[0]) == pytest.approx(5.0, rel=1e-15)
    assert abs(points[0] - centres[0]) == pytest.approx(5.0, rel=1e-15)
    assert points[1] == 5.0 + 0.0j  # the tangent point, exact: the half chord is 0
    assert np.isnan(points[2]) and np.isnan(points[3])


def test_circle_meets_a_horizontal_line_at_the_larger_x():
    point, meets = circle_horizontal_line_intersection(1.0 + 1.0j, 5.0, 4.0)
    assert bool(meets) and point == pytest.approx(5.0 + 4.0j, abs=1e-15)
    points, meets = circle_horizontal_line_intersection(
        np.array([0.0, 0.0]), 5.0, np.array([5.0, 5.5])
    )
    assert meets.tolist() == [True, False]
    assert points[0] == pytest.approx(0.0 + 5.0j, abs=1e-15)
    assert np.isnan(points[1].real)


def test_solve_real_pair_recovers_the_chosen_unknowns():
    first = np.array([1.0 + 1.0j, 2.0 - 0.5j])
    second = np.array([1.0 - 2.0j, -0.3 + 1.0j])
    x_true, y_true = np.array([2.0, -1.5]), np.array([3.0, 0.25])
    known = -(x_true * first + y_true * second)
    x, y = solve_real_pair(known, first, second)
    np.testing.assert_allclose(x, x_true, rtol=1e-14)
    np.testing.assert_allclose(y, y_true, rtol=1e-14)


def test_parallel_coefficients_give_a_non_finite_dead_point():
    x, y = solve_real_pair(1.0 + 0.0j, 1.0 + 1.0j, 2.0 + 2.0j)
    assert not np.isfinite(x) and not np.isfinite(y)
