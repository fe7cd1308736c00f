"""Plots of a column case run: ``column_3d.png`` (the column in space) and ``excitation.png``.

Drawn from the run alone (:class:`sso._run.column.ColumnRun`), on the figures of
:mod:`sso._reports.plots` (matplotlib imported on first use, Agg canvas, no pyplot
state).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from sso._column.geometry import ColumnGeometry
from sso._reports.plots import _new_figure, _png
from sso._run.column import ColumnRun

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


def render_column_plots(run: ColumnRun) -> dict[str, bytes]:
    """PNG images of a column run, keyed by file name.

    Returns
    -------
    dict of str to bytes
        ``"column_3d.png"``, ``"excitation.png"``, ``"steering.png"``, and the robust part's
        plots (:mod:`sso._reports.column_robust_plots`) when the run has one.
    """
    from sso._reports.column_robust_plots import render_robust_plots
    from sso._reports.column_steering_plots import steering_plot
    from sso._reports.column_steering_report import STEERING_PLOT

    return {"column_3d.png": _column_3d(run), "excitation.png": _excitation(run),
            STEERING_PLOT: steering_plot(run.steering), **render_robust_plots(run)}


def _column_3d(run: ColumnRun) -> bytes:
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # type: ignore[import-untyped]

    figure = _new_figure()
    axes = figure.add_subplot(projection="3d")
    geometry = run.geometry
    points = np.asarray(geometry.points_mm, dtype=float)
    moved = run.joint_centres
    _draw_column(axes, points, "#1f77b4", "given hardpoints", "-")
    patches = bend_patches(points, geometry.bend_normals)
    axes.add_collection3d(Poly3DCollection(patches, facecolors="#ff7f0e", alpha=0.3,
                                           edgecolors="#ff7f0e", linewidths=0.6))
    every = [points]
    for index, (name, column) in enumerate(position_geometries(run).items()):
        position = np.asarray(column.points_mm, dtype=float)
        axes.plot(position[:, 0], position[:, 1], position[:, 2], linestyle=":", linewidth=1.6,
                  color=POSITION_COLOURS[index % len(POSITION_COLOURS)],
                  label=f"position {name}")
        every.append(position)
    for low, high in run.case.joint_boxes_mm:
        _draw_box(axes, np.asarray(low, dtype=float), np.asarray(high, dtype=float))
    if moved is not None:
        moved_points = np.asarray(moved.points_mm, dtype=float)
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
    angles = ", ".join(f"{beta:.1f}" for beta in geometry.beta_deg)
    gammas = ", ".join(f"{gamma:.1f}" for gamma in geometry.plane_angle_deg)
    axes.set_title(f"Column: operating angles {angles} deg; bend planes (orange) turned by "
                   f"{gammas} deg", fontsize=10)
    axes.legend(loc="upper left", fontsize=9)
    return _png(figure)


def position_geometries(run: ColumnRun) -> dict[str, ColumnGeometry]:
    """The named tilt positions of the run (``[hardpoints.positions]``), or none."""
    if run.robust is None or run.robust.positions is None:
        return {}
    return run.robust.positions.geometries


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


def _excitation(run: ColumnRun) -> bytes:
    figure = _new_figure()
    axes = figure.add_subplot()
    labels = {assembly.role: assembly.label for assembly in run.assemblies}
    first = next(iter(run.excitation.values()))[0]
    vehicle = next(iter(run.excitation.values())).vehicle
    judged = first.inertial_limit_rad_s2 is not None and first.torsional_limit_rad_s2 is not None
    # A log axis cannot show 0: a cancelled figure is drawn on the floor, a millionth
    # of the largest figure (of the torsional limit where limits apply), and said to
    # be below it in the label.
    largest = max(getattr(row, name) for table in run.excitation.values() for row in table
                  for name in FIGURE_COLOURS)
    floor = 1e-6 * (first.torsional_limit_rad_s2
                    if first.torsional_limit_rad_s2 is not None else max(largest, 1e-300))
    for role, table in run.excitation.items():
        style = ROLE_STYLES["recommended" if role == run.recommended else "as_built"]
        speeds = [row.input_speed_rpm for row in table]
        for figure_name, colour in FIGURE_COLOURS.items():
            values = np.array([getattr(row, figure_name) for row in table])
            below = " (below the plot)" if np.all(values < floor) else ""
            axes.plot(speeds, np.maximum(values, floor), color=colour, **style,
                      label=f"{FIGURE_NAMES[figure_name]}, {labels[role]}{below}")
    if judged:
        axes.axhline(first.inertial_limit_rad_s2, color="black", linestyle=":",
                     linewidth=1.5, label=f"inertial limit ({vehicle})")
        axes.axhline(first.torsional_limit_rad_s2, color="grey", linestyle="-.",
                     linewidth=1.5, label=f"torsional limit ({vehicle})")
    axes.set_yscale("log")
    axes.set_xlabel("input speed (rpm)")
    axes.set_ylabel("angular acceleration excitation (rad/s^2)")
    axes.set_title("Excitation over the rpm range against the published driveline limits"
                   if judged else "Excitation over the rpm range (steering column: the "
                   "driveline limits do not apply)")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=7, loc="lower right")
    return _png(figure)
