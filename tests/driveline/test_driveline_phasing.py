"""The yoke phasing recommended for the excitation limits (issue 36, acceptance)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from driveline_cases import TRUCK_TUBE, compound_pickup, planar_one_piece, truck_two_piece
from driveline_vector_model import VectorDriveline

from sso._column.geometry import ColumnGeometry
from sso._driveline.excitation import excitations
from sso._driveline.figures import DrivelineResult, analyse_driveline
from sso._driveline.layout_box import LayoutBox
from sso._driveline.model import Driveline
from sso._driveline.phasing import MARGIN_TOLERANCE, recommend_phasing
from sso._driveline.tube import Tube


def test_compound_pickup_phase_cancels_the_axle_excitation() -> None:
    # Two true angles of 3.04 deg whose planes are 82.06 deg apart: in phase the pinion's
    # peak acceleration at 3,500 rpm is about 750 rad/s^2 (the figure); the phase
    # that lines up the two planes' effects (delta = gamma) cancels it.
    driveline = compound_pickup()
    in_phase = excitations(driveline.geometry, (0.0,), 3500.0).torsional_rad_s2
    assert in_phase == pytest.approx(750.0, rel=0.02)
    advice = recommend_phasing(driveline)
    (phase,) = advice.yoke_phase_deg
    assert phase == pytest.approx(driveline.geometry.plane_angle_deg[0], abs=0.5)
    phased = excitations(driveline.geometry, advice.yoke_phase_deg, 3500.0).torsional_rad_s2
    assert phased < 0.01 * in_phase


def test_planar_equal_angles_in_phase_is_recommended() -> None:
    advice = recommend_phasing(planar_one_piece())
    (phase,) = advice.yoke_phase_deg
    assert abs(phase) < 1e-3
    assert advice.trades == ()


def test_a_free_pinion_on_a_planar_one_piece_is_set_for_equal_angles_in_phase() -> None:
    # Textbook (Spicer J3311; Meritor MM-96147): a planar one-piece shaft cancels with equal
    # joint angles and its yokes in phase. Fitted with the pinion 1 deg nose up under a
    # gearbox 3 deg nose up (joints 3 and 1 deg), shims allowing 0 to 4 deg.
    driveline = Driveline.from_measurements(
        gearbox_slope_deg=3.0, shaft_slope_deg=[0.0], shaft_length_mm=[1400.0],
        pinion_slope_deg=1.0, tubes=(Tube(88.9, 2.1),), max_shaft_speed_rpm=5000.0,
        torque_n_m=800.0)
    result = analyse_driveline(driveline, layout=LayoutBox(pinion_slope_deg=(0.0, 4.0)))
    advice, layout = result.phasing, result.layout
    assert advice is not None and layout is not None
    assert advice.yoke_phase_deg == (0.0,)
    assert advice.pinion_slope_deg == pytest.approx(3.0, abs=1e-3)
    # the laid-out points judged by the independent vector model: equal angles, and the
    # pinion (shaft 2 with the gearbox at constant speed) without acceleration
    vector = VectorDriveline([list(point) for point in layout.driveline.points_mm],
                             list(advice.yoke_phase_deg))
    first, second = vector.joint_angles_deg()
    assert first - second == pytest.approx(0.0, abs=1e-3)
    drive, _ = vector.peaks(5000.0)
    assert drive[-1] < 1.0  # rad/s^2; 668 as fitted
    # the axle no longer feels the shaft: 668 rad/s^2 as fitted (over the 300 limit)
    torsional = [row for row in advice.rows if row.figure == "torsional"]
    assert torsional[0].given_rad_s2 == pytest.approx(668.4, rel=1e-3)
    assert torsional[0].recommended_rad_s2 < 1.0
    # and the trade is said: the coast excitation rises with the pinion joint's angle
    assert [(row.position, row.figure) for row in advice.trades] == [("design", "inertia coast")]
    assert layout.passed
    assert DrivelineResult.from_dict(result.to_dict()) == result  # the layout is recorded


def _brute_force_heights(driveline: Driveline, low_mm: float, high_mm: float
                         ) -> tuple[float, tuple[float, float]]:
    """The criterion (phasing.CRITERION) by plain scan: each textbook phasing of the two
    propshafts and the centre-bearing joint moved up by h, written as points here."""
    limits = np.array([driveline.inertia_limit_rad_s2, driveline.inertia_limit_rad_s2,
                       driveline.torsional_limit_rad_s2])

    def ratios(height_mm: float, phasing: tuple[float, float]) -> np.ndarray:
        rows = []
        for geometry in driveline.named_geometries().values():
            points = [list(point) for point in geometry.points_mm]
            points[2][2] += height_mm
            found = excitations(ColumnGeometry(points), phasing,
                                driveline.max_shaft_speed_rpm, samples=512, refine=False)
            rows.append((found.inertia_drive_rad_s2, found.inertia_coast_rad_s2,
                         found.torsional_rad_s2))
        ratio: np.ndarray = np.array(rows) / limits
        return ratio

    def scan(heights: np.ndarray) -> list[tuple[float, float, float, tuple[float, float]]]:
        return [(float(np.max(ratio)), float(ratio[0, 2]), float(height), phasing)
                for phasing in itertools.product((0.0, 90.0), repeat=2)
                for height in heights for ratio in [ratios(float(height), phasing)]]

    coarse = scan(np.linspace(low_mm, high_mm, 41))
    allowed = min(row[0] for row in coarse) + MARGIN_TOLERANCE
    _, _, height, phasing = min((row for row in coarse if row[0] <= allowed),
                                key=lambda row: row[1])
    fine = scan(np.arange(height - 1.5, height + 1.5, 0.01))
    fine = [row for row in fine if row[3] == phasing and low_mm <= row[2] <= high_mm]
    allowed = min(allowed, min(row[0] for row in fine) + MARGIN_TOLERANCE)
    _, _, height, _ = min((row for row in fine if row[0] <= allowed), key=lambda row: row[1])
    return height, phasing


def test_a_centre_bearing_height_in_its_box_agrees_with_a_brute_force_scan() -> None:
    # The truck two-piece with its gearbox 5 deg nose up: the gearbox joint's drive
    # excitation (which no phasing changes) is least with the centre bearing at the bottom
    # of its box; the second tier then raises it while that excitation stays within 0.02 of
    # its least ratio, for less torsional excitation.
    driveline = Driveline.from_measurements(
        gearbox_slope_deg=5.0, shaft_slope_deg=[0.0, 2.5], shaft_length_mm=[1200.0, 1400.0],
        pinion_slope_deg=-1.5, tubes=(TRUCK_TUBE, TRUCK_TUBE), max_shaft_speed_rpm=2500.0,
        torque_n_m=3000.0, centre_bearing_mm=(80.0,))
    advice = recommend_phasing(driveline, LayoutBox(centre_bearing_height_mm=((-10.0, 30.0),)))
    height, phasing = _brute_force_heights(driveline, -10.0, 30.0)
    (chosen,) = advice.centre_bearing_height_mm
    assert chosen == pytest.approx(height, abs=0.02)  # the scan's step is 0.01 mm
    assert -9.0 < chosen < -7.0  # inside its box: the criterion, not a bound, sets it
    difference = np.mod(np.subtract(advice.yoke_phase_deg, phasing) + 90.0, 180.0) - 90.0
    np.testing.assert_allclose(difference, 0.0, atol=0.5)
    assert advice.worst_ratio_recommended < advice.worst_ratio_given


def test_of_two_mirror_phasings_of_a_planar_driveline_the_positive_one_is_said() -> None:
    # A planar driveline seen from the other side is the same driveline with every yoke
    # phasing negated: the same figures, so the advice must pick one by a stated rule.
    driveline = truck_two_piece(positions={"laden": {"pinion_slope_deg": -0.5}})
    advice = recommend_phasing(driveline)
    mirror = tuple(-delta for delta in advice.yoke_phase_deg)
    said = excitations(driveline.geometry, advice.yoke_phase_deg, 2500.0)
    mirrored = excitations(driveline.geometry, mirror, 2500.0)
    assert mirrored.torsional_rad_s2 == pytest.approx(said.torsional_rad_s2, rel=1e-9)
    assert mirrored.inertia_drive_rad_s2 == pytest.approx(said.inertia_drive_rad_s2, rel=1e-9)
    turned = [delta for delta in advice.yoke_phase_deg if abs(delta) > 1e-6]
    assert turned and 0.0 < turned[0] < 90.0  # here (67.1, 13.6) rather than its mirror


def test_of_two_pinion_slopes_that_cancel_alike_the_side_fitted_is_kept() -> None:
    # Gearbox 3 deg nose up, shaft level: a pinion 3 deg nose up or 3 deg nose down both
    # make equal 3 deg joints. Fitted 1 deg nose up in a box of -45 to 45 deg, the pinion
    # stays nose up.
    driveline = Driveline.from_measurements(
        gearbox_slope_deg=3.0, shaft_slope_deg=[0.0], shaft_length_mm=[1400.0],
        pinion_slope_deg=1.0, tubes=(Tube(88.9, 2.1),), max_shaft_speed_rpm=5000.0,
        torque_n_m=800.0)
    advice = recommend_phasing(driveline, LayoutBox(pinion_slope_deg=(-45.0, 45.0)))
    assert advice.pinion_slope_deg == pytest.approx(3.0, abs=1e-3)
    assert advice.yoke_phase_deg == (0.0,)
