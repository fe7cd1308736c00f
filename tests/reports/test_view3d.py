"""The interactive 3D view's HTML: self-contained, escaped, and drawn from the scene.

The browser test (test_column_view_browser.py) runs it; these need no browser.
"""

from __future__ import annotations

import json
import re

import pytest

from sso.reports.view3d import scene_html

SCENE = {"items": [{"kind": "point", "at": [0.0, 0.0, 0.0], "colour": "#000000", "size": 4.0,
                    "name": "a </script><b> name", "label": "P0"}],
         "centre": [0.0, 0.0, 0.0], "radius": 1.0, "yaw_deg": 10.0, "pitch_deg": 20.0}


def test_nothing_in_the_scene_or_caption_can_close_its_script():
    text = scene_html(SCENE, "a </script><b> caption", "view-1")
    assert "</script><b>" not in text
    assert "a &lt;/script&gt;&lt;b&gt; caption" in text
    data = text.split('id="view-1-data">')[1].split("</script>")[0]
    assert json.loads(data) == SCENE


def test_the_view_asks_no_host_for_anything():
    text = scene_html(SCENE, "caption", "view-1")
    assert re.search(r"https?:|//[a-z]|src=|import\(|fetch\(|XMLHttpRequest", text) is None


def test_the_column_scene_draws_positions_boxes_and_names_every_shaft():
    # The shipped three-position truck case, with a box around each joint: the scene
    # is built from the document's parts the report has (geometry, robust positions,
    # case joint boxes), without running a solver.
    from pathlib import Path

    from sso.cases.schema import load_case
    from sso.reports.column_scene import column_scene

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
