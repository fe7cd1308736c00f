"""Plots of a column result: ``column_3d.png`` (the column in space) and ``excitation.png``.

Drawn from the result document alone, on the figures of :mod:`sso._reports.plots`
(matplotlib imported on first use, Agg canvas, no pyplot state).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from sso._reports.plots import _new_figure, _png

# Half the side of a bend-plane patch, as a fraction of the column's extent.
PATCH_FRACTION = 0.1
POSITION_COLOURS = ("#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf")
ROLE_STYLES = {"as_built": {"linestyle": "--", "linewidth": 1.4},
               "recommended": {"linestyle": "-", "linewidth": 2.2}}
FIGURE_COLOURS = {"drive_rad_s2": "#1f77b4", "coast_rad_s2": "#ff7f0e",
                  "torsional_rad_s2": "#2ca02c", "exact_output_accel_rad_s2": "#d62728"}
FIGURE_NAMES = {"drive_rad_s2": "drive (SAE AE-7)", "coast_rad_s2": "coast (SAE AE-7)",
                "torsional_rad_s2": "torsional (SAE AE-7)",
                "exact_output_accel_rad_s2": "exact output acceleration"}


def render_column_plots(document: Mapping[str, Any]) -> dict[str, bytes]:
    """PNG images of a column result, keyed by file name.

    Returns
    -------
    dict of str to bytes
        ``"column_3d.png"``, ``"excitation.png"``, ``"steering.png"``, and the robust part's plots
        (:mod:`sso._reports.column_robust_plots`) when the document has one.
    """
    from sso._reports.column_robust_plots import render_robust_plots
    from sso._reports.column_steering_plots import steering_plot
    from sso._reports.column_steering_report import STEERING_PLOT

    steering = {STEERING_PLOT: steering_plot(document)} if "steering" in document else {}
    return {"column_3d.png": _column_3d(document), "excitation.png": _excitation(document),
            **steering, **render_robust_plots(document)}


def _column_3d(document: Mapping[str, Any]) -> bytes:
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # type: ignore[import-untyped]

    figure = _new_figure()
    axes = figure.add_subplot(projection="3d")
    geometry = document["geometry"]
    points = np.asarray(geometry["points_mm"], dtype=float)
    moved = document.get("joint_positions")
    _draw_column(axes, points, "#1f77b4", "given hardpoints", "-")
    patches = bend_patches(points, geometry["bend_normals"])
    axes.add_collection3d(Poly3DCollection(patches, facecolors="#ff7f0e", alpha=0.3,
                                           edgecolors="#ff7f0e", linewidths=0.6))
    every = [points]
    positions = (document.get("robust") or {}).get("positions")
    for index, (name, entry) in enumerate((positions or {}).get("geometry", {}).items()):
        position = np.asarray(entry["points_mm"], dtype=float)
        axes.plot(position[:, 0], position[:, 1], position[:, 2], linestyle=":", linewidth=1.6,
                  color=POSITION_COLOURS[index % len(POSITION_COLOURS)],
                  label=f"position {name}")
        every.append(position)
    for low, high, _ in joint_boxes(document):
        _draw_box(axes, np.asarray(low, dtype=float), np.asarray(high, dtype=float))
    if moved is not None:
        moved_points = np.asarray(moved["points_mm"], dtype=float)
        _draw_column(axes, moved_points, "#2ca02c", "joints moved within their boxes", "--")
        every.append(moved_points)
    for index, point in enumerate(points):
        name = f"P{index}" if index in (0, len(points) - 1) else f"joint {index} (P{index})"
        axes.text(*point, f"  {name}", fontsize=9)
    _equal_aspect(axes, np.vstack(every))
    _face_the_bends(axes, points)
    axes.set_xlabel("x (mm)")
    axes.set_ylabel("y (mm)")
    axes.set_zlabel("z (mm)")
    angles = ", ".join(f"{beta:.1f}" for beta in geometry["beta_deg"])
    gammas = ", ".join(f"{gamma:.1f}" for gamma in geometry["plane_angle_deg"])
    axes.set_title(f"Column: operating angles {angles} deg; bend planes (orange) turned by "
                   f"{gammas} deg", fontsize=10)
    axes.legend(loc="upper left", fontsize=9)
    return _png(figure)


def joint_boxes(document: Mapping[str, Any]) -> list[tuple[Any, Any, int]]:
    """``(low, high, joint)`` of each box of ``[joint_boxes]`` (mm; joints from 1), or none."""
    boxes = document["case"].get("joint_boxes")
    if not boxes:
        return []
    return [(low, high, joint) for joint, (low, high)
            in enumerate(zip(boxes["min_mm"], boxes["max_mm"], strict=True), start=1)]


def _draw_column(axes: Any, points: np.ndarray, colour: str, label: str, style: str) -> None:
    axes.plot(points[:, 0], points[:, 1], points[:, 2], color=colour, linestyle=style,
              linewidth=2.5, label=label)
    axes.scatter(points[1:-1, 0], points[1:-1, 1], points[1:-1, 2], color=colour, s=45,
                 depthshade=False)
    axes.scatter(points[[0, -1], 0], points[[0, -1], 1], points[[0, -1], 2], color=colour,
                 marker="s", s=25, depthshade=False)


def bend_patches(points: np.ndarray, normals: Any) -> list[np.ndarray]:
    """A small square at each joint in its bend plane: one side along the bisector of
    the shafts before and after the joint, the other across it within the plane."""
    differences = np.diff(points, axis=0)
    directions = differences / np.linalg.norm(differences, axis=1)[:, None]
    size = PATCH_FRACTION * float(np.ptp(points, axis=0).max())
    patches = []
    for joint in range(1, len(points) - 1):
        along = directions[joint - 1] + directions[joint]
        along /= np.linalg.norm(along)
        across = np.cross(np.asarray(normals[joint - 1], dtype=float), along)
        across /= np.linalg.norm(across)
        centre = points[joint]
        patches.append(np.array([centre + size * (sign_along * along + sign_across * across)
                                 for sign_along, sign_across
                                 in ((-1, -1), (1, -1), (1, 1), (-1, 1))]))
    return patches


def _draw_box(axes: Any, low: np.ndarray, high: np.ndarray) -> None:
    corners = np.array([[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1])
                        for z in (low[2], high[2])])
    for first in range(8):
        for second in range(first + 1, 8):
            if np.count_nonzero(corners[first] != corners[second]) == 1:
                segment = corners[[first, second]]
                axes.plot(segment[:, 0], segment[:, 1], segment[:, 2], color="#2ca02c",
                          linewidth=0.6, alpha=0.6)


def _face_the_bends(axes: Any, points: np.ndarray) -> None:
    """Look along the normal of the points' best-fit plane, tilted a little, so the
    bends show as bends rather than as one line."""
    centred = points - points.mean(axis=0)
    normal = np.linalg.svd(centred)[2][-1]
    if normal[2] < 0:
        normal = -normal
    elevation = float(np.degrees(np.arcsin(np.clip(normal[2], -1.0, 1.0))))
    azimuth = float(np.degrees(np.arctan2(normal[1], normal[0])))
    axes.view_init(elev=min(max(elevation, -60.0), 60.0) + 15.0, azim=azimuth + 20.0)


def _equal_aspect(axes: Any, points: np.ndarray) -> None:
    centre = (points.max(axis=0) + points.min(axis=0)) / 2.0
    half = float(np.ptp(points, axis=0).max()) / 2.0 * 1.05
    axes.set_xlim(centre[0] - half, centre[0] + half)
    axes.set_ylim(centre[1] - half, centre[1] + half)
    axes.set_zlim(centre[2] - half, centre[2] + half)
    axes.set_box_aspect((1.0, 1.0, 1.0))


def _excitation(document: Mapping[str, Any]) -> bytes:
    figure = _new_figure()
    axes = figure.add_subplot()
    excitation = document["excitation"]
    recommended = document["recommended"]
    labels = {entry["role"]: entry["label"] for entry in document["assemblies"]}
    first = next(iter(excitation["rows"].values()))[0]
    judged = first["inertial_limit_rad_s2"] is not None
    # A log axis cannot show 0: a cancelled figure is drawn on the floor, a millionth
    # of the largest figure (of the torsional limit where limits apply), and said to
    # be below it in the label.
    largest = max(row[name] for rows in excitation["rows"].values() for row in rows
                  for name in FIGURE_COLOURS)
    floor = 1e-6 * (first["torsional_limit_rad_s2"] if judged else max(largest, 1e-300))
    for role, rows in excitation["rows"].items():
        style = ROLE_STYLES["recommended" if role == recommended else "as_built"]
        speeds = [row["input_speed_rpm"] for row in rows]
        for figure_name, colour in FIGURE_COLOURS.items():
            values = np.array([row[figure_name] for row in rows])
            below = " (below the plot)" if np.all(values < floor) else ""
            axes.plot(speeds, np.maximum(values, floor), color=colour, **style,
                      label=f"{FIGURE_NAMES[figure_name]}, {labels[role]}{below}")
    if judged:
        axes.axhline(first["inertial_limit_rad_s2"], color="black", linestyle=":",
                     linewidth=1.5, label=f"inertial limit ({excitation['vehicle']})")
        axes.axhline(first["torsional_limit_rad_s2"], color="grey", linestyle="-.",
                     linewidth=1.5, label=f"torsional limit ({excitation['vehicle']})")
    axes.set_yscale("log")
    axes.set_xlabel("input speed (rpm)")
    axes.set_ylabel("angular acceleration excitation (rad/s^2)")
    axes.set_title("Excitation over the rpm range against the published driveline limits"
                   if judged else "Excitation over the rpm range (steering column: the "
                   "driveline limits do not apply)")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=7, loc="lower right")
    return _png(figure)
