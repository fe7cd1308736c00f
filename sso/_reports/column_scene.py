"""The scene of a column's interactive 3D view (:mod:`sso._reports.view3d`), from its run.

Drawn: the shafts (named as everywhere else: input shaft, intermediate shafts from
1, output shaft), the joints with their operating angles, the end points, each
joint's bend plane (an orange patch), the named tilt positions (dashed), the joint
boxes and the moved column when the case has them.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from sso._column.geometry import ColumnGeometry, shaft_name
from sso._reports.column_plots import POSITION_COLOURS, bend_patches, position_geometries
from sso._run.column import ColumnRun

SHAFT_COLOUR = "#1f77b4"
PLANE_COLOUR = "#ff7f0e"
BOX_COLOUR = "#2ca02c"
# The first view looks along the points' best-fit plane normal, turned a little so
# the bends show as bends (as column_3d.png does).
VIEW_TILT_DEG = 15.0
VIEW_TURN_DEG = 20.0
MAX_PITCH_DEG = 60.0


def column_scene(run: ColumnRun) -> dict[str, Any]:
    """The scene of a column run (items in mm, centre, radius, first view)."""
    geometry = run.geometry
    points = np.asarray(geometry.points_mm, dtype=float)
    items = _column_items(points, geometry)
    for index, (name, column) in enumerate(position_geometries(run).items()):
        items.append(_line(column.points_mm, POSITION_COLOURS[index % len(POSITION_COLOURS)],
                           2.0, True, f"position {name} (hardpoints.positions.{name})"))
    for joint, (low, high) in enumerate(run.case.joint_boxes_mm, start=1):
        items += [_line(edge, BOX_COLOUR, 1.0, False, f"box of joint {joint} (joint_boxes)")
                  for edge in _box_edges(low, high)]
    moved = run.joint_centres
    if moved is not None:
        items.append(_line(moved.points_mm, BOX_COLOUR, 2.5, True,
                           "the column with its joints moved within their boxes"))
    # Fit everything drawn, bend-plane patches included.
    stacked = np.array([point for item in items
                        for point in (item["points"] if "points" in item else [item["at"]])])
    centre = (stacked.max(axis=0) + stacked.min(axis=0)) / 2.0
    radius = float(np.linalg.norm(stacked - centre, axis=1).max())
    yaw_deg, pitch_deg = _first_view(points)
    return {"items": items, "centre": centre.tolist(), "radius": max(radius, 1e-9),
            "yaw_deg": yaw_deg, "pitch_deg": pitch_deg}


def _column_items(points: np.ndarray, geometry: ColumnGeometry) -> list[dict[str, Any]]:
    shafts = len(points) - 1
    lengths = geometry.shaft_length_mm
    gammas = geometry.plane_angle_deg
    items = [_line(points[[shaft, shaft + 1]], SHAFT_COLOUR, 4.0, False,
                   f"{shaft_name(shaft, shafts)} (P{shaft} to P{shaft + 1}), "
                   f"{lengths[shaft]:.1f} mm")
             for shaft in range(shafts)]
    for joint, patch in enumerate(bend_patches(points, geometry.bend_normals), start=1):
        turned = (f"; bend plane {joint + 1} turned by gamma_{joint} = "
                  f"{gammas[joint - 1]:.2f} deg about intermediate shaft {joint}"
                  if joint <= len(gammas) else "")
        items.append({"kind": "face", "points": patch.tolist(), "colour": PLANE_COLOUR,
                      "alpha": 0.3, "name": f"bend plane of joint {joint}{turned}"})
    for index, point in enumerate(points):
        if index in (0, len(points) - 1):
            side = "input" if index == 0 else "output"
            items.append(_point(point, 4.0, f"P{index}: a point on the {side} shaft's axis",
                                f"P{index}"))
        else:
            straight = " (straight)" if geometry.straight_joints[index - 1] else ""
            items.append(_point(point, 6.0, f"joint {index} (P{index}): operating angle "
                                f"{geometry.beta_deg[index - 1]:.2f} deg{straight}",
                                f"joint {index}"))
    return items


def _line(points: Any, colour: str, width: float, dash: bool, name: str) -> dict[str, Any]:
    return {"kind": "line", "points": np.asarray(points, dtype=float).tolist(), "colour": colour,
            "width": width, "dash": dash, "name": name}


def _point(at: np.ndarray, size: float, name: str, label: str) -> dict[str, Any]:
    return {"kind": "point", "at": at.tolist(), "colour": SHAFT_COLOUR, "size": size,
            "name": name, "label": label}


def _box_edges(low: Sequence[float], high: Sequence[float]) -> list[np.ndarray]:
    corners = np.array([[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1])
                        for z in (low[2], high[2])], dtype=float)
    return [corners[[first, second]] for first in range(8) for second in range(first + 1, 8)
            if bin(first ^ second).count("1") == 1]


def _first_view(points: np.ndarray) -> tuple[float, float]:
    """Yaw and pitch (deg) of a view along the best-fit plane's normal, turned a little.

    The view's depth direction is ``(cos p sin y, cos p cos y, sin p)``.
    """
    normal = np.linalg.svd(points - points.mean(axis=0))[2][-1]
    if normal[2] < 0:
        normal = -normal
    pitch = math.degrees(math.asin(min(1.0, max(-1.0, float(normal[2])))))
    yaw = math.degrees(math.atan2(float(normal[0]), float(normal[1])))
    return yaw + VIEW_TURN_DEG, min(pitch, MAX_PITCH_DEG) + VIEW_TILT_DEG
