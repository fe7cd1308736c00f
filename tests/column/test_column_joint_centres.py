"""Joint positions as design variables: IPOPT and SLSQP on the points, cross-checked.

Reference values: the independent 3D cross-and-yoke simulation (tests/column/
cross_and_yoke.py) for RE at given points, the closed-form least RE of
``sso.can_cancel`` for the angle-bound optimum, and the phasing optimum of the
given points (``optimise_phasing``).
"""

from __future__ import annotations

import numpy as np
import pytest
from column_cases import load, random_column
from cross_and_yoke import residual_error as simulated_residual_error

from sso._column.cancel import can_cancel
from sso._column.geometry import ColumnGeometry
from sso._column.joint_centres import column_residual_error, optimise_joint_centres

TRUCK = np.asarray(load("truck_three_joints")["points_mm"])
CAR = np.asarray(load("car_intermediate_shaft")["points_mm"])


def boxes(points: np.ndarray, half_width_mm: float) -> list:
    return [[list(point - half_width_mm), list(point + half_width_mm)] for point in points[1:-1]]


def assert_feasible(result, tolerance: float = 1e-8) -> None:
    """Every bound, checked on the optimum's own geometry (not the NLP's constraints)."""
    points = np.asarray(result.points_mm)
    for joint, (low, high) in enumerate(result.joint_boxes_mm, start=1):
        assert np.all(points[joint] >= np.asarray(low) - tolerance * 1e3)
        assert np.all(points[joint] <= np.asarray(high) + tolerance * 1e3)
    beta = np.radians(result.geometry.beta_deg)
    for value, (low, high) in zip(beta, result.beta_bounds_deg, strict=False):
        assert np.cos(value) <= np.cos(np.radians(low)) + tolerance
        assert np.cos(value) >= np.cos(np.radians(high)) - tolerance
    for length, (low, high) in zip(result.geometry.shaft_length_mm,
                                   result.shaft_length_bounds_mm, strict=True):
        assert low - tolerance * 1e3 <= length <= high + tolerance * 1e3
    assert np.allclose(points[[0, -1]], np.asarray(result.initial.points_mm)[[0, -1]], rtol=0,
                       atol=0)


@pytest.mark.parametrize("joints", [2, 3, 4, 5, 6])  # docs/column.md: 2 to 6 joints
def test_graph_residual_error_matches_the_3d_simulation(joints):
    rng = np.random.default_rng(140 + joints)
    for _ in range(4):
        points = random_column(rng, joints)
        delta_deg = rng.uniform(-90.0, 90.0, joints - 1)
        value = column_residual_error(np, list(points), np.radians(delta_deg))
        assert value == pytest.approx(simulated_residual_error(points, delta_deg), rel=1e-9)


def test_fixed_in_phase_truck_moves_its_joints_to_a_lower_re_within_the_boxes():
    geometry = ColumnGeometry(TRUCK)
    result = optimise_joint_centres(geometry, joint_boxes_mm=boxes(TRUCK, 5.0),
                                      beta_bounds_deg=(5.0, 20.0), yoke_phase_deg=[0.0, 0.0])
    assert result.success, result.message
    assert result.crosscheck.agree
    assert result.yoke_phase_deg == (0.0, 0.0)
    # In phase at the given points: 4.86e-3 (test_column_phasing, 3D simulation).
    assert result.initial_re == pytest.approx(simulated_residual_error(TRUCK, [0.0, 0.0]),
                                              rel=1e-9)
    assert result.fun < 0.5 * result.initial_re
    assert result.fun == pytest.approx(
        simulated_residual_error(np.asarray(result.points_mm), [0.0, 0.0]), rel=1e-9)
    assert_feasible(result)
    # The boxes bind: some coordinate sits on its box face.
    moved = np.abs(np.asarray(result.points_mm)[1:-1] - TRUCK[1:-1])
    assert np.isclose(moved, 5.0, atol=1e-6).any()
    gap = abs(result.solutions["ipopt"].fun - result.solutions["slsqp"].fun)
    assert gap <= 1e-6 * result.fun


def test_free_phasing_reaches_the_closed_form_least_re_of_the_bound_angles():
    # Angle bounds that forbid cancelling: cos 19.5 < cos 9.5 cos 13.5. The least RE
    # over every phasing is cosh(l_3 - l_1 - l_2) - 1 with l = -ln cos(beta),
    # smallest with the largest joint at its lower bound and the others at their
    # upper bounds; the 10 mm boxes allow those angles.
    geometry = ColumnGeometry(TRUCK)
    bounds = [(9.0, 9.5), (13.0, 13.5), (19.5, 20.0)]
    assert not can_cancel([9.5, 13.5, 19.5]).possible
    expected = can_cancel([9.5, 13.5, 19.5]).minimum_residual_error
    result = optimise_joint_centres(geometry, joint_boxes_mm=boxes(TRUCK, 10.0),
                                      beta_bounds_deg=bounds)
    assert result.success, result.message
    assert result.fun == pytest.approx(expected, rel=1e-7)
    assert result.geometry.beta_deg == pytest.approx((9.5, 13.5, 19.5), abs=1e-6)
    assert result.fun <= result.initial_re
    assert result.fun <= result.fixed_points_re
    assert result.fun == pytest.approx(
        simulated_residual_error(np.asarray(result.points_mm), result.yoke_phase_deg), rel=1e-9)
    assert_feasible(result)


def test_free_phasing_car_column_cancels_by_equalising_its_angles():
    # Two joints cancel exactly when their angles are equal (can_cancel); the car
    # column's 24.0 / 24.5 deg can be equalised within 10 mm boxes.
    geometry = ColumnGeometry(CAR)
    result = optimise_joint_centres(geometry, joint_boxes_mm=boxes(CAR, 10.0),
                                      beta_bounds_deg=(10.0, 30.0))
    assert result.success, result.message
    assert result.initial_re == pytest.approx(result.fixed_points_re, rel=1e-9)
    assert result.fixed_points_re > 1e-6
    assert result.fun < 1e-15
    beta_first, beta_second = result.geometry.beta_deg
    assert beta_first == pytest.approx(beta_second, abs=1e-5)
    assert_feasible(result)


def test_pinned_boxes_give_back_the_given_points():
    geometry = ColumnGeometry(TRUCK)
    result = optimise_joint_centres(geometry, joint_boxes_mm=boxes(TRUCK, 0.0),
                                      beta_bounds_deg=(5.0, 25.0), yoke_phase_deg=[10.0, -80.0],
                                      solvers="ipopt", starts=1)
    assert result.points_mm == geometry.points_mm
    assert result.fun == pytest.approx(simulated_residual_error(TRUCK, [10.0, -80.0]), rel=1e-9)


@pytest.mark.parametrize("options, message", [
    ({"beta_bounds_deg": (0.0, 20.0)}, r"beta_bounds_deg\[0\] lower = 0 .*straight joint"),
    ({"joint_boxes_mm": boxes(TRUCK, 5.0)[:2]}, "joint_boxes_mm has 2 boxes; the column has 3"),
    ({"joint_boxes_mm": [[[0, 0, 0], [1, 1, 1]]] * 3}, r"points_mm\[1\] x = .* lies outside"),
    ({"shaft_length_bounds_mm": (0.0, 900.0)}, r"shaft_length_bounds_mm\[0\] lower = 0"),
    ({"yoke_phase_deg": [0.0]}, "yoke_phase_deg has 1 entries"),
])
def test_bad_input_is_refused_naming_the_field(options, message):
    arguments = {"joint_boxes_mm": boxes(TRUCK, 5.0), **options}
    with pytest.raises(ValueError, match=message):
        optimise_joint_centres(ColumnGeometry(TRUCK), **arguments)


def test_a_straight_joint_at_the_start_is_refused():
    # P2 on the line P1-P3 (joint 2 straight): its bend plane is undefined there.
    points = [[0.0, 0.0, 0.0], [300.0, 0.0, 0.0], [500.0, 60.0, 0.0], [700.0, 120.0, 0.0],
              [900.0, 120.0, 80.0]]
    geometry = ColumnGeometry(points)
    assert geometry.straight_joints == (False, True, False)
    with pytest.raises(ValueError, match=r"joint 2 \(points_mm\[2\]\) is straight"):
        optimise_joint_centres(geometry, joint_boxes_mm=boxes(np.asarray(points), 5.0))
