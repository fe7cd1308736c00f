"""Steering figures from lock to lock against the independent 3D cross-and-yoke simulation.

The simulation (tests/column/cross_and_yoke.py) turns the pin axes of the yokes in
space and never uses the chain matrix. Its extremes over the range are found
numerically: a dense grid, then a bounded Brent search around every grid peak, so the
reference values come from a different derivation and a different method.
"""

from __future__ import annotations

import numpy as np
import pytest
from column_cases import load, random_column
from cross_and_yoke import Simulated, extremes

from sso.column.geometry import ColumnGeometry
from sso.column.steering_range import CURVE_POINTS, steering_range


@pytest.mark.parametrize("seed, joints, lock_deg", [
    (0, 2, 540.0), (1, 3, 37.0), (2, 3, 900.0), (3, 4, 120.0), (4, 5, 1260.0), (5, 6, 65.0),
])
def test_fluctuation_and_transmission_error_are_the_3d_simulation(seed, joints, lock_deg):
    rng = np.random.default_rng(4100 + seed)
    points = random_column(rng, joints)
    geometry = ColumnGeometry(points)
    assert min(abs(gamma) for gamma in geometry.plane_angle_deg) > 1.0  # non-planar
    yoke = rng.uniform(-90.0, 90.0, joints - 1)
    centre_deg = rng.uniform(-180.0, 180.0)
    result = steering_range((geometry, yoke), lock_deg=lock_deg, straight_ahead_deg=centre_deg)
    simulated = Simulated(points, yoke, np.radians(centre_deg))
    low, high = np.radians(centre_deg - lock_deg), np.radians(centre_deg + lock_deg)

    ratio_low, ratio_high = extremes(simulated.ratio, low, high)
    assert result.speed_ratio_min == pytest.approx(ratio_low, rel=1e-9)
    assert result.speed_ratio_max == pytest.approx(ratio_high, rel=1e-9)
    assert result.speed_fluctuation_percent == pytest.approx(
        100.0 * (ratio_high - ratio_low), rel=1e-9)
    assert result.torque_fluctuation_percent == pytest.approx(
        100.0 * (1.0 / ratio_low - 1.0 / ratio_high), rel=1e-9)
    error_low, error_high = (np.degrees(value) for value in extremes(simulated.error, low, high))
    assert result.transmission_error_min_deg == pytest.approx(error_low, rel=1e-9)
    assert result.transmission_error_max_deg == pytest.approx(error_high, rel=1e-9)
    assert result.largest_transmission_error_deg == pytest.approx(
        max(-error_low, error_high), rel=1e-9)
    assert result.transmission_error_peak_to_peak_deg == pytest.approx(
        error_high - error_low, rel=1e-9)

    theta = np.radians(centre_deg + np.asarray(result.wheel_angle_deg))
    assert len(theta) == CURVE_POINTS
    np.testing.assert_allclose(result.speed_ratio, simulated.ratio(theta), rtol=0, atol=1e-12)
    np.testing.assert_allclose(result.transmission_error_deg,
                               np.degrees(simulated.error(theta)), rtol=0, atol=1e-10)
    ends = np.array([low, high])
    np.testing.assert_allclose(result.lock_speed_ratio, simulated.ratio(ends), atol=1e-12)
    np.testing.assert_allclose(result.lock_transmission_error_deg,
                               np.degrees(simulated.error(ends)), atol=1e-10)
    window = np.radians(min(result.on_centre_deg, lock_deg))
    window_low, window_high = extremes(simulated.ratio, np.radians(centre_deg) - window,
                                       np.radians(centre_deg) + window)
    assert result.on_centre_fluctuation_percent == pytest.approx(
        100.0 * (window_high - window_low), rel=1e-9)
    assert result.on_centre_speed_ratio == pytest.approx(
        simulated.ratio(np.radians([centre_deg]))[0], rel=1e-12)


def test_truck_column_over_its_lock_range():
    # The shipped truck column's best 36-tooth assembly (+1, -8 teeth: 10, -80 deg)
    # over 2.5 turns each way: the range covers whole periods, so the extremes are the
    # chain's singular-value ratio s_max / s_min and its inverse (a second derivation).
    geometry = ColumnGeometry(load("truck_three_joints")["points_mm"])
    result = steering_range((geometry, (10.0, -80.0)), lock_deg=900.0)
    singular = np.linalg.svd(np.asarray(_matrix(geometry, (10.0, -80.0))), compute_uv=False)
    assert result.speed_ratio_max == pytest.approx(singular[0] / singular[1], rel=1e-12)
    assert result.speed_ratio_min == pytest.approx(singular[1] / singular[0], rel=1e-12)
    assert result.torque_ratio == pytest.approx([1.0 / value for value in result.speed_ratio])
    assert result.transmission_error_deg[CURVE_POINTS // 2] == 0.0
    assert result.transmission_error_min_deg < 0.0 < result.transmission_error_max_deg
    assert "speed_ratio_max=1.0215" in repr(result) and "wheel_angle_deg" not in repr(result)


def _matrix(geometry: ColumnGeometry, yoke):
    from sso.column.chain_matrix import chain_matrix

    return chain_matrix(np.radians(geometry.beta_deg),
                        np.radians(geometry.phase_deg_from_yoke(yoke)))


@pytest.mark.parametrize("keywords, match", [
    ({"lock_deg": 0.0}, r"lock_deg = 0 .*\(0, 3600\]"),
    ({"lock_deg": float("nan")}, "lock_deg"),
    ({"on_centre_deg": 90.0}, r"on_centre_deg = 90 .*\(0, 90\)"),
    ({"straight_ahead_deg": float("inf")}, "straight_ahead_deg"),
])
def test_bad_options_name_the_field(keywords, match):
    geometry = ColumnGeometry(load("truck_three_joints")["points_mm"])
    with pytest.raises(ValueError, match=match):
        steering_range((geometry, (0.0, 0.0)), **keywords)
