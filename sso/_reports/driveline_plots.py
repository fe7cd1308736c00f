"""The plots of a driveline's report: the layout in side and plan view, one revolution of
every shaft's speed and acceleration, excitation against speed with the limits, bearing
loads over a revolution, and critical speed against the operating range.

Each figure is drawn from the result alone (the driveline it holds and its figures).
"""

from __future__ import annotations

import io
from typing import Any

import numpy as np

from sso._driveline.excitation import speed_and_acceleration
from sso._driveline.figures import DrivelineResult

WIDTH_IN, HEIGHT_IN, DPI = 9.0, 5.0, 100
LAYOUT_FILE = "driveline_layout.png"
REVOLUTION_FILE = "shaft_speed_acceleration.png"
EXCITATION_FILE = "excitation_vs_speed.png"
BEARING_FILE = "bearing_loads.png"
CRITICAL_FILE = "critical_speed.png"
CAPTIONS = {
    LAYOUT_FILE: "Side view (x forward, z up) and plan view (y left) of the joint centres, "
                 "gearbox ahead, pinion behind",
    REVOLUTION_FILE: "Speed and angular acceleration of each propshaft and the pinion over "
                     "one revolution of the gearbox at the maximum shaft speed",
    EXCITATION_FILE: "Excitations of the design position against shaft speed, with the limits",
    BEARING_FILE: "Radial bearing loads over one revolution of the gearbox at the torque",
    CRITICAL_FILE: "Each propshaft's critical and safe speed against the operating range",
}


def _figure(rows: int = 1) -> Any:
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    return Figure(figsize=(WIDTH_IN, HEIGHT_IN * (1 if rows == 1 else 1.5)), dpi=DPI)


def _finished(figure: Any, legend: Any, *others: Any) -> bytes:
    """The figure's PNG, with the legend on ``legend`` and a grid on every panel."""
    legend.legend()
    for axes in (legend, *others):
        axes.grid(True)
    return _png(figure)


def _png(figure: Any) -> bytes:
    buffer = io.BytesIO()
    figure.tight_layout()
    figure.savefig(buffer, format="png", dpi=DPI)
    return buffer.getvalue()


def driveline_plots(result: DrivelineResult) -> dict[str, bytes]:
    """Every plot of the report, by file name (PNG bytes)."""
    plots = {LAYOUT_FILE: _layout(result), REVOLUTION_FILE: _revolution(result),
             EXCITATION_FILE: _excitation(result), BEARING_FILE: _bearings(result)}
    if result.tubes:
        plots[CRITICAL_FILE] = _critical(result)
    return plots


def _layout(result: DrivelineResult) -> bytes:
    figure = _figure(rows=2)
    side, plan = figure.subplots(2, 1)
    for name, geometry in result.driveline.named_geometries().items():
        points = np.asarray(geometry.points_mm)
        side.plot(points[:, 0], points[:, 2], marker="o", label=name)
        plan.plot(points[:, 0], points[:, 1], marker="o", label=name)
    side.set(title="side view", xlabel="x (mm, forward)", ylabel="z (mm, up)")
    plan.set(title="plan view", xlabel="x (mm, forward)", ylabel="y (mm, left)")
    return _finished(figure, side, plan)


def _revolution(result: DrivelineResult) -> bytes:
    driveline = result.driveline
    theta = np.radians(np.arange(0.0, 360.5, 0.5))
    speed, acceleration = speed_and_acceleration(driveline.geometry, driveline.phasing_deg,
                                                 driveline.max_shaft_speed_rpm, theta)
    figure = _figure(rows=2)
    top, bottom = figure.subplots(2, 1, sharex=True)
    names = [f"propshaft {k}" for k in range(1, driveline.joint_count)] + ["pinion"]
    for index, name in enumerate(names):
        top.plot(np.degrees(theta), speed[index], label=name)
        bottom.plot(np.degrees(theta), acceleration[index], label=name)
    top.set(ylabel="speed (rpm)", title=f"gearbox at {driveline.max_shaft_speed_rpm:g} rpm")
    bottom.set(xlabel="gearbox angle (deg)", ylabel="angular acceleration (rad/s^2)")
    return _finished(figure, top, bottom)


def _excitation(result: DrivelineResult) -> bytes:
    driveline = result.driveline
    design = result.positions[0]
    top = driveline.max_shaft_speed_rpm
    speed = np.linspace(0.0, 1.2 * top, 200)
    scale = (speed / top) ** 2  # every excitation grows with the speed squared
    figure = _figure()
    axes = figure.subplots()
    for label, value in (("inertia, drive", design.inertia_drive_rad_s2),
                         ("inertia, coast", design.inertia_coast_rad_s2),
                         ("torsional", design.torsional_rad_s2)):
        axes.plot(speed, value * scale, label=label)
    axes.axhline(driveline.inertia_limit_rad_s2, color="k", linestyle="--",
                 label=f"inertia limit {driveline.inertia_limit_rad_s2:g}")
    axes.axhline(driveline.torsional_limit_rad_s2, color="r", linestyle="--",
                 label=f"torsional limit {driveline.torsional_limit_rad_s2:g}")
    axes.axvline(top, color="grey", linestyle=":", label="maximum shaft speed")
    axes.set(xlabel="shaft speed (rpm)", ylabel="excitation (rad/s^2)")
    return _finished(figure, axes)


def _bearings(result: DrivelineResult) -> bytes:
    figure = _figure()
    axes = figure.subplots()
    for curve in result.loads.bearings:
        axes.plot(result.loads.theta_deg, curve.force_n, label=curve.name)
    axes.set(xlabel="gearbox angle (deg)", ylabel="radial load (N)",
             title=f"torque {result.driveline.torque_n_m:g} N m")
    return _finished(figure, axes)


def _critical(result: DrivelineResult) -> bytes:
    figure = _figure()
    axes = figure.subplots()
    names = [f"propshaft {k}" for k in range(1, len(result.tubes) + 1)]
    positions = np.arange(len(names))
    axes.bar(positions - 0.2, [tube.critical_speed_rpm for tube in result.tubes], 0.4,
             label="critical speed")
    axes.bar(positions + 0.2, [tube.safe_speed_rpm for tube in result.tubes], 0.4,
             label="safe speed")
    axes.axhline(result.driveline.max_shaft_speed_rpm, color="r", linestyle="--",
                 label="maximum shaft speed")
    axes.set_xticks(positions, names)
    axes.set(ylabel="speed (rpm)")
    axes.legend()
    axes.grid(True, axis="y")
    return _png(figure)

