"""best_spline_teeth against brute force over every tooth with the 3D simulation."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from column_cases import load, planar_points, random_column
from cross_and_yoke import residual_error as simulated_residual_error
from cross_and_yoke import rotate

from sso._column.geometry import ColumnGeometry
from sso._column.splines import best_spline_teeth


def test_enumeration_matches_brute_force_over_every_tooth_in_the_3d_simulation():
    # Truck column, 12-tooth splines: all 12 x 12 tooth positions (each assembly
    # twice, 180 deg apart) simulated in 3D; the best must be what the search reports.
    points = np.asarray(load("truck_three_joints")["points_mm"])
    geometry = ColumnGeometry(points)
    result = best_spline_teeth(geometry, 12)
    simulated = {offsets: simulated_residual_error(points, np.array(offsets) * 30.0, samples=128)
                 for offsets in itertools.product(range(12), repeat=2)}
    lowest = min(simulated.values())
    assert result.method == "enumeration"
    assert result.residual_error == pytest.approx(lowest, rel=1e-9)
    wrapped = tuple(offset % 12 for offset in result.tooth_offset)
    assert simulated[wrapped] == pytest.approx(lowest, rel=1e-9)
    assert result.continuous_residual_error <= result.residual_error
    assert result.loss == pytest.approx(result.residual_error - result.continuous_residual_error)
    assert result.assemblies_evaluated == 36  # 6 distinct positions per 12-tooth shaft


@pytest.mark.parametrize("seed, joints, teeth", [(0, 4, 24), (1, 5, 18), (2, 4, [15, 20, 11]),
                                                 (3, 3, 36), (4, 5, 13)])
def test_branch_and_bound_finds_what_enumeration_finds(seed, joints, teeth):
    geometry = ColumnGeometry(random_column(np.random.default_rng(seed), joints))
    enumerated = best_spline_teeth(geometry, teeth, method="enumeration")
    bounded = best_spline_teeth(geometry, teeth, method="branch_and_bound")
    assert bounded.residual_error == enumerated.residual_error
    assert bounded.ties == enumerated.ties
    assert bounded.tooth_offset == enumerated.tooth_offset


def test_truck_column_on_36_tooth_splines():
    # 36 teeth = 10 deg steps; the continuous optimum (delta = 10.0, -80.0 deg,
    # test_column_phasing) sits almost on a tooth, so the loss is tiny.
    geometry = ColumnGeometry(load("truck_three_joints")["points_mm"])
    result = best_spline_teeth(geometry, load("truck_three_joints")["spline_teeth"])
    assert result.tooth_offset == (1, -8)
    assert result.yoke_phase_deg == pytest.approx((10.0, -80.0))
    assert 0.0 <= result.loss < 1e-9
    assert result.instructions[1].text == (
        "Intermediate shaft 2 (joint 2 to joint 3, 36 teeth), yoke at joint 3: 8 teeth "
        "(80.0 deg) anticlockwise from the in-phase position, looking along the shaft from "
        "joint 2 towards joint 3.")
    assert "1 tooth (10.0 deg) clockwise" in result.assembly_text()


def test_positive_offset_is_clockwise_looking_from_joint_k_to_joint_k_plus_1():
    # The words of the instruction: a right-hand turn about u, seen by a viewer who
    # looks along u, goes clockwise (negative angle in the viewer's screen frame).
    axis = np.array([0.2, -0.4, 0.9])
    axis /= np.linalg.norm(axis)
    pin = np.cross(axis, [1.0, 0.0, 0.0])
    pin /= np.linalg.norm(pin)
    turned = rotate(axis, np.radians([10.0]), pin[None, :])[0]
    screen_x, screen_y = pin, np.cross(-axis, pin)
    assert np.arctan2(turned @ screen_y, turned @ screen_x) < 0


def test_mirror_symmetric_column_reports_both_tied_assemblies():
    # Planar (gamma = 0 or 180) and able to cancel (10, 12, 14 deg): phasings +d and
    # -d are mirrors with equal RE, so on a symmetric tooth grid teeth j and -j tie.
    geometry = ColumnGeometry(planar_points([10.0, 12.0, -14.0]))
    assert geometry.beta_deg == pytest.approx((10.0, 12.0, 14.0))
    result = best_spline_teeth(geometry, 36)
    assert len(result.ties) == 2
    assert result.ties[1] == tuple(-value for value in result.ties[0])


def test_straight_middle_joint_ties_every_split_of_the_phasing():
    # Joint 2 straight: only delta_1 + delta_2 matters, so every split of the best
    # sum ties.
    geometry = ColumnGeometry([[-300, 60, 0], [0, 0, 0], [300, 0, 0], [600, 0, 0], [900, 90, 0]])
    result = best_spline_teeth(geometry, 36)
    sums = {sum(tie) % 18 for tie in result.ties}
    assert len(result.ties) == 18 and len(sums) == 1


@pytest.mark.parametrize("teeth, message", [
    (0, r"teeth = 0 is outside the allowed range \[1, 1000\]"),
    ([36], "teeth has 1 entries; the column has 2 intermediate shafts"),
    ([36, 2.5], r"teeth\[1\] = 2.5 must be a whole number"),
    (True, "teeth"),
])
def test_bad_teeth_are_refused(teeth, message):
    geometry = ColumnGeometry(load("truck_three_joints")["points_mm"])
    with pytest.raises(ValueError, match=message):
        best_spline_teeth(geometry, teeth)


def test_bad_method_and_single_joint_are_refused():
    geometry = ColumnGeometry(load("truck_three_joints")["points_mm"])
    with pytest.raises(ValueError, match="method = 'guess'"):
        best_spline_teeth(geometry, 36, method="guess")
    with pytest.raises(ValueError, match="1 joint"):
        best_spline_teeth(ColumnGeometry([[0, 0, 0], [100, 0, 0], [200, 30, 0]]), 36)


def test_auto_switches_to_branch_and_bound_above_the_enumeration_limit():
    # 6 joints on 24-tooth splines: 12^5 = 248,832 assemblies > 200,000.
    geometry = ColumnGeometry(random_column(np.random.default_rng(6), 6))
    automatic = best_spline_teeth(geometry, 24)
    assert automatic.method == "branch_and_bound"
    enumerated = best_spline_teeth(geometry, 24, method="enumeration")
    assert enumerated.assemblies_evaluated == 12**5
    assert automatic.residual_error == enumerated.residual_error
    assert automatic.tooth_offset == enumerated.tooth_offset
