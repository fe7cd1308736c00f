"""Where a column leaves practice: each note names the point and says why, with its source.

Reference values are the geometry itself: the truck column of
tests/data/columns/truck_three_joints.json (9.2, 13.3, 19.9 deg; shafts of 150 to
520 mm), the same points in metres, and planar columns bent by chosen angles.
"""

from __future__ import annotations

import numpy as np
import pytest
from column_cases import load, planar_points

import sso
from sso._column.geometry import ColumnGeometry, shaft_name
from sso._column.practice import practice_notes

TRUCK = np.asarray(load("truck_three_joints")["points_mm"])


def test_the_truck_column_is_within_practice():
    assert practice_notes(ColumnGeometry(TRUCK)) == ()


def test_hardpoints_in_metres_are_noted_with_the_shortest_shaft():
    (note,) = practice_notes(ColumnGeometry(TRUCK / 1000.0))
    lengths = np.linalg.norm(np.diff(TRUCK, axis=0), axis=1) / 1000.0
    assert note.key == "points_mm"
    assert f"is {lengths.min():.3g} mm long: the hardpoints look like metres" in note.reason
    assert "output shaft, P3 to P4" in note.reason  # the truck's shortest shaft (150 mm)
    assert "plausibility" in note.source


def test_a_joint_below_half_a_degree_is_noted_with_brinelling():
    (note,) = practice_notes(ColumnGeometry(planar_points([0.3, -12.0])))
    assert note.key == "points_mm[1]"
    assert note.reason == "joint 1 runs at 0.3 deg, below about 0.5 deg"
    assert "brinell" in note.source and "Spicer" in note.source
    assert note.text.startswith("points_mm[1]: joint 1 runs at 0.3 deg")


def test_a_straight_joint_and_a_joint_above_the_makers_limit_are_noted():
    notes = practice_notes(ColumnGeometry(planar_points([0.0, 12.0, 40.0])))
    assert [note.key for note in notes] == ["points_mm[1]", "points_mm[3]"]
    assert "joint 1 is straight (0 deg)" in notes[0].reason
    assert notes[1].reason == "joint 3 runs at 40 deg, above the maker's limit of 35 deg"
    assert practice_notes(ColumnGeometry(planar_points([20.0, 40.0])),
                          max_operating_angle_deg=45.0) == ()


@pytest.mark.parametrize("index, shafts, name", [
    (0, 4, "input shaft"), (1, 4, "intermediate shaft 1"), (2, 4, "intermediate shaft 2"),
    (3, 4, "output shaft"),
])
def test_shafts_are_named_with_the_intermediate_ones_from_1(index, shafts, name):
    assert shaft_name(index, shafts) == name


@pytest.mark.parametrize("points, reason", [
    (TRUCK / 1000.0, "the hardpoints look like metres"),
    (planar_points([0.3, -12.0]), "joint 1 runs at 0.3 deg, below about 0.5 deg"),
])
def test_optimise_warns_at_the_callers_line_with_the_reason(points, reason):
    with pytest.warns(sso.PracticeWarning, match=reason) as caught:
        result = sso.optimise(ColumnGeometry(points))
    assert result.success
    assert caught[0].filename == __file__


def test_optimise_of_named_positions_warns_naming_the_position():
    # Two positions of a planar column, one with a 0.3 deg first joint.
    positions = {"up": ColumnGeometry(planar_points([0.3, -12.0])),
                 "down": ColumnGeometry(planar_points([2.0, -12.0]))}
    with pytest.warns(sso.PracticeWarning) as caught:
        sso.optimise(positions)
    texts = [str(warning.message) for warning in caught
             if issubclass(warning.category, sso.PracticeWarning)]
    assert texts == ["['up'].points_mm[1]: joint 1 runs at 0.3 deg, below about 0.5 deg ("
                     + practice_notes(positions["up"])[0].source + ")"]
