"""The scene of a column's interactive 3D view, built from the parts of its run.

Reference values: the shipped three-position truck case (cases/
column_truck_three_positions.toml) and its hardpoints; a box of +-5 mm around each joint.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from sso._cases.schema import load_case, parse_case
from sso._reports.column_scene import column_scene
from sso._run.column import run_column


def test_the_column_scene_draws_positions_boxes_and_names_every_shaft():
    # The shipped three-position truck case (its positions only), with a box around
    # each joint, analysed as built: the scene is built from the run's parts
    # (geometry, robust positions, the case's joint boxes), without running a solver.
    shipped = load_case(Path(__file__).resolve().parents[2] / "cases"
                        / "column_truck_three_positions.toml").to_dict()
    points = shipped["hardpoints"]["points_mm"]
    case = parse_case({"kind": "column", "name": "boxed", "hardpoints": shipped["hardpoints"],
                       "joint_boxes": {"min_mm": [[c - 5.0 for c in p] for p in points[1:-1]],
                                       "max_mm": [[c + 5.0 for c in p] for p in points[1:-1]]}},
                      "boxed")
    scene = column_scene(run_column(case, optimising=False))
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
