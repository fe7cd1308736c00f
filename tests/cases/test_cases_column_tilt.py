"""The [tilt] table of a column case: P0 turned about the pivot, its defaults, its errors."""

import numpy as np
import pytest

from sso.cases.schema import CaseError, load_case, parse_case
from sso.column.geometry import ColumnGeometry

TRUCK = "cases/column_truck_three_joints.toml"


def _document(**tilt):
    document = load_case(TRUCK).to_dict()
    document["tilt"] = tilt
    return document


def test_a_tilt_about_the_first_bend_normal_through_p1_changes_the_first_angle_by_the_tilt():
    # Turning the input shaft in its own bend plane about the joint's centre opens or
    # closes the joint by exactly the tilt; the other joints do not move.
    given = ColumnGeometry(load_case(TRUCK).values["hardpoints.points_mm"])
    normal = given.bend_normals[0].tolist()
    tilted = parse_case(_document(angle_deg=3.0, axis=normal), "tilted").geometry()
    assert tilted.beta_deg[0] == pytest.approx(given.beta_deg[0] - 3.0, abs=1e-12)
    assert tilted.beta_deg[1:] == pytest.approx(given.beta_deg[1:], abs=1e-12)
    assert tilted.points_mm[1:] == given.points_mm[1:]


def test_the_defaults_are_the_lateral_axis_through_p1_and_survive_a_round_trip():
    case = parse_case(_document(angle_deg=-4.0), "tilted")
    assert case.values["tilt.axis"] == (0.0, 1.0, 0.0)
    assert case.values["tilt.through_mm"] == (-1690.3, 328.7, 1239.3)
    again = parse_case(case.to_dict(), "tilted")
    assert again.geometry() == case.geometry()
    # About y through P1: the distance from P0 to P1 and P0's y stay; P0 moves.
    p0, p1 = np.asarray(case.geometry().points_mm[0]), np.asarray(case.geometry().points_mm[1])
    given = np.asarray(load_case(TRUCK).values["hardpoints.points_mm"][0])
    assert np.linalg.norm(p0 - p1) == pytest.approx(np.linalg.norm(given - p1), rel=1e-14)
    assert p0[1] == given[1] and not np.allclose(p0, given)


@pytest.mark.parametrize("tilt, match", [
    ({"angle_deg": 91.0}, r"tilt.angle_deg = 91 is outside the allowed range \[-90, 90\]"),
    ({"axis": [1.0, 0.0, 0.0]}, r"tilt.angle_deg is missing: give \[-90, 90\]"),
    ({"angle_deg": 5.0, "axis": [0.0, 0.0, 0.0]}, r"tilt.axis = \[0.0, 0.0, 0.0\] has no "
                                                   "direction"),
    ({"angle_deg": 5.0, "axis": [1.0, 0.0]}, r"tilt.axis = \[1.0, 0.0\] must be a list of 3 to 3"),
    ({"angle_deg": 89.0, "through_mm": [0.0, 0.0, 0.0]}, r"tilted by tilt.angle_deg = 89: "),
])
def test_a_bad_tilt_names_the_key_and_its_range(tilt, match):
    with pytest.raises(CaseError, match=match):
        parse_case(_document(**tilt), "tilted")
