"""Excitation figures: the published calibration, the manual's sign rules, and the 3D simulation."""

from __future__ import annotations

import numpy as np
import pytest
from column_cases import planar_points
from cross_and_yoke import speed_ratio as simulated_speed_ratio

import sso
from sso._column.excitation import equivalent_angles, excitation_table
from sso._column.geometry import ColumnGeometry

# Calibration published with an open-source driveline calculator (formulas from SAE
# AE-7), as the calibration case: four joints 5, 4, 3, 2 deg, planar, 2500 rpm, first
# driveshaft crossed (yokes 90 deg apart), the other two in phase.
CALIBRATION_POINTS = planar_points([5.0, -4.0, 3.0, -2.0])
CALIBRATION_YOKES = (90.0, 0.0, 0.0)


def test_published_calibration_to_printed_precision():
    geometry = ColumnGeometry(CALIBRATION_POINTS)
    assert geometry.beta_deg == pytest.approx((5.0, 4.0, 3.0, 2.0), abs=1e-12)
    series = geometry.series(CALIBRATION_YOKES)
    angles = equivalent_angles(series)
    assert round(angles.drive_deg, 2) == 9.90
    assert round(angles.coast_deg, 2) == 3.16
    assert round(angles.torsional_deg, 2) == 6.00
    (row,) = excitation_table(series, [2500.0], vehicle="car")
    assert round(row.drive_rad_s2) == 2026
    assert round(row.coast_rad_s2) == 209
    assert round(row.torsional_rad_s2) == 749
    # Exact model (docs/column.md, excitation): cos beta_eq = c1 c2 c4 / c3, beta_eq = 5.998 deg,
    # omega^2 sin^2 beta_eq = 748.4, output acceleration amplitude 752.5 rad/s^2.
    c1, c2, c3, c4 = np.cos(np.radians([5.0, 4.0, 3.0, 2.0]))
    assert angles.exact_deg == pytest.approx(np.degrees(np.arccos(c1 * c2 * c4 / c3)), abs=1e-9)
    assert round(angles.exact_deg, 3) == 5.998
    assert round(row.exact_torsional_rad_s2, 1) == 748.4
    assert round(row.exact_output_accel_rad_s2, 1) == 752.5
    assert not row.within_limits  # drive 2026 > 1000 and torsional 749 > 300 for a car


def test_exact_output_acceleration_matches_the_3d_simulation():
    # Largest |d(ratio)/d theta| of the simulated column (central differences on a
    # fine grid, refined around the peak), times omega^2.
    geometry = ColumnGeometry(CALIBRATION_POINTS)
    theta = np.linspace(0.0, np.pi, 20001)
    step = 1e-5
    reference = geometry.bend_normals[0]

    def slope(angles):
        return (simulated_speed_ratio(CALIBRATION_POINTS, CALIBRATION_YOKES, angles + step,
                                      reference)
                - simulated_speed_ratio(CALIBRATION_POINTS, CALIBRATION_YOKES, angles - step,
                                        reference)) / (2 * step)

    peak = theta[np.argmax(np.abs(slope(theta)))]
    fine = peak + np.linspace(-2e-4, 2e-4, 4001)
    omega = 2500.0 * 2 * np.pi / 60
    expected = omega**2 * np.max(np.abs(slope(fine)))
    (row,) = excitation_table(geometry.series(CALIBRATION_YOKES), [2500.0])
    assert row.exact_output_accel_rad_s2 == pytest.approx(expected, rel=1e-6)


def test_one_driveshaft_follows_the_manuals_rules():
    # Two joints, planar, in phase: drive = front joint, coast = rear joint,
    # torsional = sqrt(|b1^2 - b2^2|); crossed: torsional = sqrt(b1^2 + b2^2).
    in_phase = ColumnGeometry(planar_points([6.0, -3.0])).series([0.0])
    angles = equivalent_angles(in_phase)
    assert angles.drive_deg == pytest.approx(6.0, abs=1e-12)
    assert angles.coast_deg == pytest.approx(3.0, abs=1e-12)
    assert angles.torsional_deg == pytest.approx(np.sqrt(36.0 - 9.0), abs=1e-12)
    crossed = ColumnGeometry(planar_points([6.0, -3.0])).series([90.0])
    assert equivalent_angles(crossed).torsional_deg == pytest.approx(np.sqrt(45.0), abs=1e-12)
    c1, c2 = np.cos(np.radians([6.0, 3.0]))
    assert angles.exact_deg == pytest.approx(np.degrees(np.arccos(c1 / c2)), abs=1e-9)


def test_rows_scale_with_speed_squared_and_use_the_vehicle_limits():
    series = sso.ShaftSeries([5.0, 4.0, 3.0, 2.0], [0.0, 90.0, 90.0])
    rows = excitation_table(series, [1000.0, 2000.0, 2100.0], vehicle="truck")
    assert rows[1].torsional_rad_s2 == pytest.approx(4 * rows[0].torsional_rad_s2, rel=1e-12)
    assert rows[1].exact_output_accel_rad_s2 == pytest.approx(
        4 * rows[0].exact_output_accel_rad_s2, rel=1e-12)
    assert (rows[0].inertial_limit_rad_s2, rows[0].torsional_limit_rad_s2) == (2000.0, 500.0)
    # Torsional 749 rad/s^2 at 2500 rpm scales to 479 at 2000 rpm (under the truck's
    # 500) and 528 at 2100 rpm (over it); drive stays under 2000 at both.
    assert rows[0].within_limits and rows[1].within_limits
    assert not rows[2].within_limits
    assert rows[2].drive_rad_s2 < 2000.0 and rows[2].torsional_rad_s2 > 500.0
    car = excitation_table(series, [1000.0], vehicle="car")[0]
    assert (car.inertial_limit_rad_s2, car.torsional_limit_rad_s2) == (1000.0, 300.0)


def test_a_steering_column_is_never_judged_by_the_driveline_limits():
    # The row at 2100 rpm is outside the truck limits as a driveline (above); as a
    # steering column the same figures carry no limit and no verdict.
    series = sso.ShaftSeries([5.0, 4.0, 3.0, 2.0], [0.0, 90.0, 90.0])
    driveline = excitation_table(series, [20.0, 2100.0], vehicle="truck")
    steering = excitation_table(series, [20.0, 2100.0], vehicle="truck", application="steering")
    for judged, unjudged in zip(driveline, steering, strict=True):
        assert unjudged.within_limits is None and unjudged.inertial_limit_rad_s2 is None
        assert unjudged.torsional_limit_rad_s2 is None
        assert unjudged.torsional_rad_s2 == judged.torsional_rad_s2
    assert driveline[0].within_limits and not driveline[1].within_limits


@pytest.mark.parametrize("kwargs, error, message", [
    ({"input_speed_rpm": []}, ValueError, "input_speed_rpm is empty"),
    ({"input_speed_rpm": [1000.0, -5.0]}, ValueError, r"input_speed_rpm\[1\] = -5"),
    ({"input_speed_rpm": [1000.0], "vehicle": "bus"}, ValueError, "vehicle = 'bus'"),
    ({"input_speed_rpm": [1000.0], "application": "boat"}, ValueError, "application = 'boat'"),
])
def test_bad_input_is_refused(kwargs, error, message):
    series = sso.ShaftSeries([5.0, 4.0], [90.0])
    with pytest.raises(error, match=message):
        excitation_table(series, **kwargs)
    with pytest.raises(TypeError, match="ShaftSeries"):
        equivalent_angles([5.0, 4.0])
