"""Slider-crank kinematics against the slider-crank paper (complex vs Holowenko).

Reference: tests/data/reference/slidercrank_r2_{0p050,0p075,0p100}m.csv,
slidercrank_table2_percent_difference.csv and the README beside them. In-line
slider-crank, rod r3 = 0.3 m, crank r2 = 0.05, 0.075, 0.10 m, w2 = 188.4 rad/s.
"""

import math

import numpy as np
import pytest
from reference_tables import REFERENCE
from time_derivative import assert_time_derivative

from sso._kinematics.slider_crank import solve_slider_crank
from sso._linkages.mechanisms import (
    MechanismTable,
    SliderCrank,
    slider_crank_method_difference,
)

ROD = 0.3
CRANK_SPEED = 188.4  # exactly; README: 1800 rpm = 188.496 rad/s does not reproduce
CRANKS = {0.05: "0p050", 0.075: "0p075", 0.10: "0p100"}
PAPER_ANGLES_DEG = np.arange(0.0, 361.0, 15.0)
HALF_UNIT = 0.005 + 1e-9
"""Half a unit of the 2nd decimal every column is printed to, plus float noise."""


def read_reference(crank: float) -> np.ndarray:
    return np.genfromtxt(
        REFERENCE / f"slidercrank_r2_{CRANKS[crank]}m.csv", delimiter=",", names=True
    )


def analyse_paper_rows(crank: float) -> tuple[np.ndarray, MechanismTable]:
    reference = read_reference(crank)
    table = SliderCrank(crank=crank, rod=ROD).analyse(
        reference["crank_angle_theta2_deg"], crank_speed=CRANK_SPEED
    )
    return reference, table


def angles_and_rod_speed(table: MechanismTable) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Crank angle t2 (rad), rod angle t3 (rad) and rod speed w3 (rad/s) of our table."""
    return (
        np.radians(table["crank_angle_deg"]),
        np.radians(table["rod_angle_deg"]),
        table["rod_angular_velocity_rad_s"],
    )


def paper_alpha3(crank: float, table: MechanismTable) -> np.ndarray:
    """The paper's alpha3, with cos(theta3) multiplied instead of divided (README)."""
    crank_angle, rod_angle, rod_speed = angles_and_rod_speed(table)
    return (
        crank * CRANK_SPEED**2 * np.sin(crank_angle) / ROD * np.cos(rod_angle)
        + rod_speed**2 * np.tan(rod_angle)
    )


@pytest.mark.parametrize("crank", CRANKS)
def test_rod_angle_matches_modulo_360(crank):
    # slidercrank_r2_*.csv, rod_angle_theta3_deg (OK; 360.00 at 0 and 180 but 0.00 at 360).
    reference, table = analyse_paper_rows(crank)
    wrapped = (table["rod_angle_deg"] - reference["rod_angle_theta3_deg"] + 180.0) % 360.0 - 180.0
    np.testing.assert_allclose(wrapped, 0.0, rtol=0, atol=HALF_UNIT)


@pytest.mark.parametrize("crank", CRANKS)
@pytest.mark.parametrize(
    ("column", "printed"),
    [
        ("piston_position", "piston_position_r1_m"),  # r1, printed to 2 decimals
        ("rod_angular_velocity_rad_s", "rod_angular_velocity_omega3_rad_s"),
        ("piston_velocity", "piston_velocity_complex_m_s"),
        ("piston_accel_approximate", "piston_accel_trig_m_s2"),  # correct Holowenko formula
    ],
)
def test_ok_columns_match_to_the_printed_two_decimals(crank, column, printed):
    # slidercrank_r2_*.csv, the columns the README marks OK.
    reference, table = analyse_paper_rows(crank)
    np.testing.assert_allclose(table[column], reference[printed], rtol=0, atol=HALF_UNIT)


@pytest.mark.parametrize(
    ("crank", "largest_error"), [(0.05, 166.7), (0.075, 572.8), (0.10, 1394.4)]
)
def test_printed_rod_acceleration_multiplies_by_cos_theta3_where_ours_divides(crank, largest_error):
    # slidercrank_r2_*.csv, rod_angular_accel_alpha3_rad_s2 (DEFECT): the printed values are
    # r2 w^2 sin(t2) / r3 * cos(t3) + w3^2 tan(t3); ours is r2 w^2 sin(t2) / (r3 cos(t3)) + ...
    reference, table = analyse_paper_rows(crank)
    crank_angle, rod_angle, rod_speed = angles_and_rod_speed(table)
    printed = reference["rod_angular_accel_alpha3_rad_s2"]
    np.testing.assert_allclose(paper_alpha3(crank, table), printed, rtol=0, atol=HALF_UNIT)
    correct = (
        crank * CRANK_SPEED**2 * np.sin(crank_angle) / (ROD * np.cos(rod_angle))
        + rod_speed**2 * np.tan(rod_angle)
    )
    np.testing.assert_allclose(table["rod_angular_accel_rad_s2"], correct, rtol=1e-12, atol=1e-9)
    error = np.abs(table["rod_angular_accel_rad_s2"] - printed)
    assert error.max() == pytest.approx(largest_error, abs=0.1)


@pytest.mark.parametrize(("crank", "largest_error"), [(0.05, 8.33), (0.075, 42.96), (0.10, 139.43)])
def test_printed_complex_piston_acceleration_inherits_the_wrong_alpha3(crank, largest_error):
    # slidercrank_r2_*.csv, piston_accel_complex_m_s2 (DEFECT): the correct formula
    # -r2 w^2 cos t2 - r3 a3 sin t3 - r3 w3^2 cos t3 applied to the paper's alpha3.
    reference, table = analyse_paper_rows(crank)
    crank_angle, rod_angle, rod_speed = angles_and_rod_speed(table)
    printed = reference["piston_accel_complex_m_s2"]

    def piston_accel(rod_accel: np.ndarray) -> np.ndarray:
        return (
            -crank * CRANK_SPEED**2 * np.cos(crank_angle)
            - ROD * rod_accel * np.sin(rod_angle)
            - ROD * rod_speed**2 * np.cos(rod_angle)
        )

    wrong = piston_accel(paper_alpha3(crank, table))
    np.testing.assert_allclose(wrong, printed, rtol=0, atol=HALF_UNIT)
    correct = piston_accel(table["rod_angular_accel_rad_s2"])
    np.testing.assert_allclose(table["piston_accel"], correct, rtol=1e-12, atol=1e-9)
    assert np.abs(table["piston_accel"] - printed).max() == pytest.approx(largest_error, abs=0.01)


def test_complex_piston_acceleration_at_75_deg_is_153_92_not_33_05():
    # slidercrank_r2_0p100m.csv, row 6 (75 deg), piston_accel_complex_m_s2 (README).
    reference, table = analyse_paper_rows(0.10)
    row = np.flatnonzero(reference["crank_angle_theta2_deg"] == 75.0)[0]
    assert reference["piston_accel_complex_m_s2"][row] == pytest.approx(33.05, abs=1e-9)
    assert table["piston_accel"][row] == pytest.approx(153.92, abs=0.005)


@pytest.mark.parametrize(("crank", "largest_error"), [(0.05, 0.72), (0.075, 1.61), (0.10, 2.86)])
def test_printed_series_velocity_evaluates_r2_over_2_r3_left_to_right(crank, largest_error):
    # slidercrank_r2_*.csv, piston_velocity_trig_m_s (DEFECT): printed
    # -r2 w (sin t + (r2/2)*r3 sin 2t); ours uses r2/(2 r3).
    reference, table = analyse_paper_rows(crank)
    crank_angle = np.radians(table["crank_angle_deg"])
    printed = reference["piston_velocity_trig_m_s"]

    def series_velocity(coefficient: float) -> np.ndarray:
        sine_series = np.sin(crank_angle) + coefficient * np.sin(2 * crank_angle)
        return -crank * CRANK_SPEED * sine_series

    wrong = series_velocity(crank / 2 * ROD)
    np.testing.assert_allclose(wrong, printed, rtol=0, atol=HALF_UNIT)
    correct = series_velocity(crank / (2 * ROD))
    approximate = table["piston_velocity_approximate"]
    np.testing.assert_allclose(approximate, correct, rtol=1e-12, atol=1e-12)
    assert np.abs(approximate - printed).max() == pytest.approx(largest_error, abs=0.005)


@pytest.mark.parametrize(
    ("crank", "top_speed", "at_deg"), [(0.05, 9.55, 81), (0.075, 14.54, 77), (0.10, 19.77, 74)]
)
def test_series_velocity_peaks_before_90_deg(crank, top_speed, at_deg):
    # README: the text puts the "trig" maximum at 90 deg (9.42, 14.13, 18.84 m/s), an
    # artefact of the defective formula; the correct series peaks earlier and higher.
    angles = np.arange(0.0, 180.0, 0.001)
    table = SliderCrank(crank=crank, rod=ROD).analyse(angles, crank_speed=CRANK_SPEED)
    speed = np.abs(table["piston_velocity_approximate"])
    assert speed.max() == pytest.approx(top_speed, abs=0.005)
    assert round(angles[np.argmax(speed)]) == at_deg
    assert speed.max() > crank * CRANK_SPEED + 0.1


def test_method_difference_regenerates_tabel_2_with_correct_formulas():
    # slidercrank_table2_percent_difference.csv (DEFECT: derived from the defective
    # columns). README: the recipe on correct formulas gives velocity 0.05, 0.17, 0.41 %
    # and acceleration 0.31, 1.75, 3.64 % over the paper's 25 rows.
    printed = np.genfromtxt(
        REFERENCE / "slidercrank_table2_percent_difference.csv", delimiter=",", names=True
    )
    table = slider_crank_method_difference(
        printed["crank_r2_m"], ROD, CRANK_SPEED, PAPER_ANGLES_DEG
    )
    np.testing.assert_allclose(table["crank"], [0.05, 0.075, 0.10], rtol=1e-12)
    np.testing.assert_allclose(table["rod"], ROD, rtol=1e-12)
    np.testing.assert_allclose(
        table["velocity_difference_pct"], [0.05, 0.17, 0.41], rtol=0, atol=HALF_UNIT
    )
    np.testing.assert_allclose(
        table["acceleration_difference_pct"], [0.31, 1.75, 3.64], rtol=0, atol=HALF_UNIT
    )
    assert np.all(printed["velocity_difference_pct"] - table["velocity_difference_pct"] > 8.0)
    assert np.all(printed["acceleration_difference_pct"] > table["acceleration_difference_pct"])


def test_method_difference_counts_zero_over_zero_as_zero():
    # At 0, 180 and 360 deg both piston velocities vanish (to rounding: sin(pi) != 0).
    table = slider_crank_method_difference(0.05, ROD, CRANK_SPEED, [0.0, 180.0, 360.0])
    assert table["velocity_difference_pct"][0] == 0.0


def test_method_difference_at_90_deg_has_the_closed_form_value():
    # At 90 deg the exact piston acceleration is r^2 w^2 / sqrt(L^2 - r^2) and the series
    # one r^2 w^2 / L, so they differ by 100 (1 - sqrt(1 - (r/L)^2)) %; at 0 deg they agree.
    ratio = 0.05 / ROD
    expected = 100.0 * (1.0 - math.sqrt(1.0 - ratio**2))
    only_90 = slider_crank_method_difference(0.05, ROD, CRANK_SPEED, [90.0])
    assert only_90["acceleration_difference_pct"][0] == pytest.approx(expected, rel=1e-9)
    with_0 = slider_crank_method_difference(0.05, ROD, CRANK_SPEED, [0.0, 90.0])
    assert with_0["acceleration_difference_pct"][0] == pytest.approx(expected / 2, rel=1e-9)


@pytest.mark.parametrize("offset", [0.0, 0.02, -0.03])
@pytest.mark.parametrize("crank_accel", [0.0, -40.0])
def test_velocities_and_accelerations_match_finite_differences(offset, crank_accel):
    step_deg = 0.01
    angles = np.arange(0.0, 360.0 + step_deg / 2, step_deg)
    table = SliderCrank(crank=0.1, rod=ROD, offset=offset).analyse(
        angles, crank_speed=CRANK_SPEED, crank_accel=crank_accel
    )
    drive = (math.radians(step_deg), CRANK_SPEED, crank_accel)
    rod_angle = np.unwrap(np.radians(table["rod_angle_deg"]))
    rod_speed = table["rod_angular_velocity_rad_s"]
    assert_time_derivative(rod_speed, rod_angle, *drive, speed_power=0)
    assert_time_derivative(table["rod_angular_accel_rad_s2"], rod_speed, *drive, speed_power=1)
    velocity = table["piston_velocity"]
    assert_time_derivative(velocity, table["piston_position"], *drive, speed_power=0)
    assert_time_derivative(table["piston_accel"], velocity, *drive, speed_power=1)
    if offset == 0.0:
        approximate = table["piston_velocity_approximate"]
        accel = table["piston_accel_approximate"]
        assert_time_derivative(accel, approximate, *drive, speed_power=1)


@pytest.mark.parametrize("offset", [0.0, 0.02, -0.03])
def test_piston_position_solves_the_loop(offset):
    # x = r cos t + sqrt(L^2 - (e - r sin t)^2) for a slider line at height e.
    angles = np.arange(0.0, 360.0, 5.0)
    table = SliderCrank(crank=0.1, rod=ROD, offset=offset).analyse(angles, crank_speed=1.0)
    crank_angle = np.radians(angles)
    height_to_climb = offset - 0.1 * np.sin(crank_angle)
    expected = 0.1 * np.cos(crank_angle) + np.sqrt(ROD**2 - height_to_climb**2)
    np.testing.assert_allclose(table["piston_position"], expected, rtol=1e-13)
    assert ("piston_velocity_approximate" in table.columns) == (offset == 0.0)


def test_series_is_exact_to_second_order_in_crank_over_rod():
    # The exact and series velocities differ by O((r/L)^3) r w: shrinking r/L tenfold
    # shrinks the largest gap about a thousandfold.
    angles = np.radians(np.arange(0.0, 360.0, 1.0))
    gaps = []
    for crank in (0.03, 0.003):
        motion = solve_slider_crank(crank, ROD, 0.0, angles, 1.0, 0.0)
        table = SliderCrank(crank=crank, rod=ROD).analyse(np.degrees(angles), crank_speed=1.0)
        gap = motion.piston_velocity - table["piston_velocity_approximate"]
        gaps.append(np.max(np.abs(gap)) / crank)
    assert gaps[0] / gaps[1] == pytest.approx(1000.0, rel=0.05)
