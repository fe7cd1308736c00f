"""The scene of a column's interactive 3D view, built from the parts of its document.

Reference values: the shipped three-position truck case (cases/
column_truck_three_positions.toml) and its hardpoints; a box of +-5 mm around each joint.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from sso._cases.schema import load_case
from sso._reports.column_scene import column_scene


def test_the_column_scene_draws_positions_boxes_and_names_every_shaft():
    # The shipped three-position truck case, with a box around each joint: the scene
    # is built from the document's parts the report has (geometry, robust positions,
    # case joint boxes), without running a solver.
    case = load_case(Path(__file__).resolve().parents[2] / "cases"
                     / "column_truck_three_positions.toml")
    geometry = case.geometry()
    points = case.values["hardpoints.points_mm"]
    document = {
        "geometry": {**geometry.to_dict(), "straight_joints": list(geometry.straight_joints),
                     "bend_normals": geometry.bend_normals.tolist()},
        "robust": {"positions": {"geometry": {name: column.to_dict() for name, column
                                              in case.positions().items()}}},
        "case": {"joint_boxes": {"min_mm": [[c - 5.0 for c in p] for p in points[1:-1]],
                                 "max_mm": [[c + 5.0 for c in p] for p in points[1:-1]]}},
    }
    scene = column_scene(document)
    names = [item["name"] for item in scene["items"]]
    assert [name for name in names if name.startswith("position ")] == [
        f"position {name} (hardpoints.positions.{name})" for name in case.positions()]
    assert names.count("box of joint 2 (joint_boxes)") == 12
    assert [name.split(" (")[0] for name in names[:4]] == [
        "input shaft", "intermediate shaft 1", "intermediate shaft 2", "output shaft"]
    assert sum(name.startswith("bend plane of joint") for name in names) == 3
    every = [point for item in scene["items"] for point in item.get("points", [item.get("at")])]
    distances = [sum((a - c) ** 2 for a, c in zip(point, scene["centre"], strict=True)) ** 0.5
                 for point in every]
    assert max(distances) == pytest.approx(scene["radius"], rel=1e-12)
