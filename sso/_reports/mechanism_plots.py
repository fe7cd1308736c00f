"""Plots of a mechanism result: link positions, coupler curve, motion against crank angle.

Drawn from the run alone (:class:`sso._run.mechanism_run.MechanismRun`): each
linkage's curves every :data:`~sso._run.mechanism_run.CURVE_STEP_DEG`, with the
tabulated crank angles marked on them, and its positions at the plotted angles;
nothing is recomputed. matplotlib
is imported inside :func:`render_mechanism_plots` only (through
:func:`sso._reports.plots._new_figure`), so a run without plots never loads it.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from sso._limits import TRANSMISSION_BAND_DEG
from sso._linkages.mechanisms import FourBar, QuickReturn, SliderCrank
from sso._linkages.registry import Mechanism, Panel, linkage_of
from sso._linkages.table import MechanismTable
from sso._reports.plots import _new_figure, _png
from sso._run.mechanism_run import LinkageCurves, MechanismRun, revolution_stop_deg

LINK_COLOURS = {"crank": "#d62728", "coupler": "#1f77b4", "rocker": "#2ca02c",
                "rod": "#1f77b4", "slider_link": "#9467bd"}
COLUMN_COLOURS = ("#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#d62728")
ROLE_LINESTYLES = {"given": "-", "initial": "--", "optimum": "-"}
ROLE_LABELS = {"given": "", "initial": "initial", "optimum": "optimum"}
BAND_COLOUR = "#2ca02c"
BAND_TOLERANCE_DEG = 1e-6
"""An optimum on its bound is inside the band up to the solver's tolerance."""


def render_mechanism_plots(run: MechanismRun) -> dict[str, bytes]:
    """PNG images of a mechanism run, keyed by file name.

    Returns
    -------
    dict of str to bytes
        ``linkage.png`` and, by mechanism, ``angular_motion.png`` and
        ``transmission_angle.png`` (four-bar, quick-return), ``piston_motion.png``
        and ``rod_motion.png`` (slider-crank), ``slider_motion.png`` (quick-return).
    """
    return {name: _png(figure) for name, figure in mechanism_figures(run).items()}


def mechanism_figures(run: MechanismRun) -> dict[str, Any]:
    """The figures of :func:`render_mechanism_plots`, keyed by file name."""
    linkage = linkage_of(run.linkages[0].mechanism)
    figures = {"linkage.png": _linkage_plot(run)}
    for file_name, title, panels in linkage.series_plots:
        figures[file_name] = _series_plot(run, title, panels)
    if linkage.transmission_plot:
        figures["transmission_angle.png"] = _transmission_plot(run)
    return figures


def _column(table: MechanismTable, column: str) -> np.ndarray | None:
    """A column, or ``"left-right"``: the difference of two columns; None if absent."""
    names = column.split("-")
    if any(name not in table.columns for name in names):
        return None
    values = np.asarray(table[names[0]], dtype=float)
    return values - np.asarray(table[names[1]], dtype=float) if len(names) == 2 else values


def _title(run: MechanismRun, what: str) -> str:
    case = run.case
    speed = f"crank {case.crank_speed_rad_s:g} rad/s"
    if case.crank_accel_rad_s2:
        speed += f", {case.crank_accel_rad_s2:g} rad/s$^2$"
    return f"{case.name}: {what}\n{_linkage_text(run)}\n{speed}"


def _linkage_text(run: MechanismRun) -> str:
    parts = []
    for linkage in run.linkages:
        lengths = _lengths(linkage.mechanism)
        prefix = f"{ROLE_LABELS[linkage.role]}: " if ROLE_LABELS[linkage.role] else ""
        parts.append(f"{prefix}{lengths} ({run.case.length_unit})")
    return "\n".join(parts)


def _role_label(role: str, label: str) -> str:
    return f"{label} ({ROLE_LABELS[role]})" if ROLE_LABELS[role] else label


def _angle_axis(axes: Any, run: MechanismRun) -> None:
    start, stop = run.case.values["drive.start_deg"], revolution_stop_deg(run.case)
    axes.set_xlabel("crank angle (deg, counter-clockwise from +x)")
    axes.set_xlim(start, stop)
    span = stop - start
    step = 45.0 if span > 180 else 30.0 if span > 60 else max(span / 6.0, 1.0)
    axes.set_xticks(np.arange(start, stop + 1e-9, step))


def _series_plot(run: MechanismRun, title: str, panels: tuple[Panel, ...]) -> Any:
    figure = _new_figure()
    if len(panels) > 3:
        figure.set_size_inches(figure.get_size_inches()[0], 9.0)
    axes_list = figure.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    for axes, (y_label, columns) in zip(axes_list, panels, strict=True):
        for colour, (column, label, *linestyle) in zip(COLUMN_COLOURS, columns, strict=False):
            for linkage in run.linkages:
                dense, tabulated = _column(linkage.curve, column), _column(linkage.table, column)
                if dense is None:
                    continue
                axes.plot(linkage.curve["crank_angle_deg"], dense, color=colour,
                          linestyle=linestyle[0] if linestyle else ROLE_LINESTYLES[linkage.role],
                          linewidth=1.8, label=_role_label(linkage.role, label))
                axes.plot(linkage.table["crank_angle_deg"], tabulated, "o", color=colour,
                          markersize=3.5)
        axes.set_ylabel(y_label.format(length=run.case.length_unit))
        low, high = axes.get_ylim()
        if low < 0.0 < high:
            axes.axhline(0.0, color="black", linewidth=0.6)
        axes.grid(True, alpha=0.4)
        axes.legend(loc="best", fontsize="small", framealpha=0.9)
    axes_list[0].set_title(_title(run, title) + "\nlines: every 1 deg; dots: the table's "
                           "crank angles", fontsize="medium")
    _angle_axis(axes_list[-1], run)
    figure.tight_layout()
    return figure


def _transmission_plot(run: MechanismRun) -> Any:
    figure = _new_figure()
    axes = figure.subplots(1, 1)
    values_of_case = run.case.values
    low, high = (values_of_case["bounds.transmission_angle_deg"]
                 if "bounds.transmission_angle_deg" in values_of_case
                 else TRANSMISSION_BAND_DEG)
    axes.axhspan(low, high, color=BAND_COLOUR, alpha=0.15,
                 label=f"recommended band [{low:g}, {high:g}] deg")
    for bound in (low, high):
        axes.axhline(bound, color=BAND_COLOUR, linewidth=1.0)
    for colour, linkage in zip(COLUMN_COLOURS, run.linkages, strict=False):
        role = linkage.role
        angle = linkage.curve["crank_angle_deg"]
        values = linkage.curve["transmission_angle_deg"]
        lowest = int(np.nanargmin(values))
        highest = int(np.nanargmax(values))
        label = (f"transmission angle: min {values[lowest]:.2f} deg (crank {angle[lowest]:g} "
                 f"deg), max {values[highest]:.2f} deg (crank {angle[highest]:g} deg)")
        axes.plot(angle, values, color=colour, linestyle=ROLE_LINESTYLES[role], linewidth=2.0,
                  label=_role_label(role, label))
        axes.plot(linkage.table["crank_angle_deg"], linkage.table["transmission_angle_deg"],
                  "o", color=colour, markersize=3.5)
        outside = (values < low - BAND_TOLERANCE_DEG) | (values > high + BAND_TOLERANCE_DEG)
        if outside.any():
            axes.plot(angle[outside], values[outside], ".", color="#d62728", markersize=3,
                      label=_role_label(role, "outside the band"))
    axes.set_ylim(0.0, 180.0)
    axes.set_yticks(np.arange(0.0, 181.0, 20.0))
    axes.set_ylabel("transmission angle at B (deg)")
    axes.set_title(_title(run, "transmission angle over the crank revolution"),
                   fontsize="medium")
    axes.grid(True, alpha=0.4)
    axes.legend(loc="upper right", fontsize="small", framealpha=0.9)
    _angle_axis(axes, run)
    figure.tight_layout()
    return figure


# ---------------------------------------------------------------- link positions

def _linkage_plot(run: MechanismRun) -> Any:
    figure = _new_figure()
    axes_list = figure.subplots(1, len(run.linkages), squeeze=False)[0]
    plotted: Sequence[float] = run.case.values["plots.crank_angles_deg"]
    for axes, linkage in zip(axes_list, run.linkages, strict=True):
        snapshots = linkage.positions
        DRAWINGS[linkage_of(linkage.mechanism).drawing](axes, linkage, snapshots)
        for index, angle in enumerate(plotted):
            if _assembled(snapshots, index):
                axes.annotate(f"{angle:g}°", (snapshots["joint_a_x"][index],
                                               snapshots["joint_a_y"][index]),
                              textcoords="offset points", xytext=(4, 4), fontsize="x-small",
                              color=LINK_COLOURS["crank"])
        axes.set_aspect("equal", adjustable="datalim")
        axes.grid(True, alpha=0.3)
        axes.set_xlabel(f"x ({run.case.length_unit})")
        axes.set_ylabel(f"y ({run.case.length_unit})")
        role = linkage.role
        heading = f"{ROLE_LABELS[role]} linkage" if ROLE_LABELS[role] else "linkage"
        swing = linkage.swing_deg
        swing_text = f"\nrocker swing {swing:.2f} deg" if swing is not None else ""
        axes.set_title(f"{heading}: {_lengths(linkage.mechanism)}{swing_text}", fontsize="small")
    figure.legend(*axes_list[0].get_legend_handles_labels(), loc="lower center", ncol=5,
                  fontsize="small", framealpha=0.9)
    angles_text = ", ".join(f"{angle:g}" for angle in plotted)
    figure.suptitle(f"{run.case.name}: link positions at crank angles "
                    f"{angles_text} deg (fading with angle)", fontsize="medium")
    figure.tight_layout(rect=(0.0, 0.09, 1.0, 1.0))
    return figure


def _lengths(mechanism: Mechanism) -> str:
    return ", ".join(f"{name} {value:.4g}" for name, value in vars(mechanism).items()
                     if not isinstance(value, str))


def _assembled(table: MechanismTable, index: int) -> bool:
    return bool(np.isfinite(table["joint_a_x"][index]) and np.isfinite(
        table["piston_position"][index] if "piston_position" in table.columns
        else table["joint_b_x"][index]))


def _alphas(count: int) -> np.ndarray:
    return np.linspace(1.0, 0.35, count) if count > 1 else np.ones(1)


def _draw_link(axes: Any, start: complex, end: complex, name: str, alpha: float,
               label: str | None) -> None:
    axes.plot([start.real, end.real], [start.imag, end.imag], "-o", color=LINK_COLOURS[name],
              alpha=alpha, linewidth=2.2, markersize=4, label=label)


def _draw_pivot(axes: Any, point: complex, label: str) -> None:
    axes.plot(point.real, point.imag, "^", color="black", markersize=11)
    axes.annotate(label, (point.real, point.imag), textcoords="offset points",
                  xytext=(0, -16), ha="center", fontsize="small")


def _point(table: MechanismTable, joint: str, index: int) -> complex:
    return complex(table[f"{joint}_x"][index], table[f"{joint}_y"][index])


def _draw_fourbar_like(axes: Any, curve: LinkageCurves, snapshots: MechanismTable) -> None:
    mechanism = curve.mechanism
    if not isinstance(mechanism, FourBar | QuickReturn):
        raise TypeError(f"the four-bar drawing needs a FourBar or QuickReturn, not {mechanism!r}")
    quick_return = isinstance(mechanism, QuickReturn)
    ground_pivot = complex(mechanism.ground, 0.0)
    _draw_pivot(axes, 0j, "O$_2$" if quick_return else "O$_A$")
    _draw_pivot(axes, ground_pivot, "O$_4$" if quick_return else "O$_B$")
    axes.plot([0.0, mechanism.ground], [0.0, 0.0], color="black", linewidth=0.8,
              linestyle=":", label=f"ground {mechanism.ground:.4g}")
    dense = curve.curve
    axes.plot(dense["joint_a_x"], dense["joint_a_y"], color="grey", linewidth=0.8,
              linestyle="--", label="path of A")
    axes.plot(dense["joint_b_x"], dense["joint_b_y"], color="grey", linewidth=0.8,
              linestyle="-.", label="path of B")
    if "coupler_point_x" in dense.columns:
        axes.plot(dense["coupler_point_x"], dense["coupler_point_y"], color="#ff7f0e",
                  linewidth=2.0, label="coupler curve (path of coupler point P)")
    if quick_return:
        axes.axhline(0.0, color="black", linewidth=0.8, label="slider line y = 0")
    for index, alpha in enumerate(_alphas(len(snapshots))):
        if not _assembled(snapshots, index):
            continue
        first = index == 0
        joint_a, joint_b = _point(snapshots, "joint_a", index), _point(snapshots, "joint_b", index)
        _draw_link(axes, 0j, joint_a, "crank", alpha, "crank" if first else None)
        _draw_link(axes, joint_a, joint_b, "coupler", alpha, "coupler" if first else None)
        _draw_link(axes, ground_pivot, joint_b, "rocker", alpha, "rocker" if first else None)
        if "coupler_point_x" in snapshots.columns:
            point = _point(snapshots, "coupler_point", index)
            axes.fill([joint_a.real, point.real, joint_b.real],
                      [joint_a.imag, point.imag, joint_b.imag], color=LINK_COLOURS["coupler"],
                      alpha=0.12 * alpha)
            axes.plot(point.real, point.imag, "s", color="#ff7f0e", alpha=alpha, markersize=5,
                      label="coupler point P" if first else None)
        if isinstance(mechanism, QuickReturn):
            joint_c = _point(snapshots, "joint_c", index)
            _draw_link(axes, joint_b, joint_c, "slider_link", alpha,
                       "slider link BC" if first else None)
            _draw_block(axes, joint_c, 0.06 * mechanism.slider_link, alpha, first)


def _draw_block(axes: Any, centre: complex, size: float, alpha: float, first: bool) -> None:
    from matplotlib.patches import Rectangle

    axes.add_patch(Rectangle((centre.real - size, centre.imag - 0.5 * size), 2 * size, size,
                             facecolor="#bbbbbb", edgecolor="black", alpha=alpha,
                             label="slider" if first else None))


def _draw_joints(axes: Any, curve: LinkageCurves, snapshots: MechanismTable) -> None:
    """Any mechanism: the crank, and the path and positions of every tabulated joint."""
    columns = curve.curve.columns
    joints = sorted(name[:-2] for name in columns
                    if name.startswith("joint_") and name.endswith("_x")
                    and f"{name[:-2]}_y" in columns)
    _draw_pivot(axes, 0j, "O")
    for joint in joints:
        axes.plot(curve.curve[f"{joint}_x"], curve.curve[f"{joint}_y"], color="grey",
                  linewidth=0.8, linestyle="--", label=f"path of {joint[6:].upper()}")
    for index, alpha in enumerate(_alphas(len(snapshots))):
        if not _assembled(snapshots, index):
            continue
        _draw_link(axes, 0j, _point(snapshots, "joint_a", index), "crank", alpha,
                   "crank" if index == 0 else None)
        for joint in joints:
            point = _point(snapshots, joint, index)
            axes.plot(point.real, point.imag, "o", color="black", alpha=alpha, markersize=4)


def _draw_slider_crank(axes: Any, curve: LinkageCurves, snapshots: MechanismTable) -> None:
    mechanism = curve.mechanism
    if not isinstance(mechanism, SliderCrank):
        raise TypeError(f"the slider-crank drawing needs a SliderCrank, not {mechanism!r}")
    _draw_pivot(axes, 0j, "O")
    axes.axhline(mechanism.offset, color="black", linewidth=0.8,
                 label=f"slider line y = {mechanism.offset:g}")
    dense = curve.curve
    axes.plot(dense["joint_a_x"], dense["joint_a_y"], color="grey", linewidth=0.8,
              linestyle="--", label="path of A")
    for index, alpha in enumerate(_alphas(len(snapshots))):
        if not _assembled(snapshots, index):
            continue
        first = index == 0
        joint_a = _point(snapshots, "joint_a", index)
        piston = complex(snapshots["piston_position"][index], mechanism.offset)
        _draw_link(axes, 0j, joint_a, "crank", alpha, "crank" if first else None)
        _draw_link(axes, joint_a, piston, "rod", alpha, "connecting rod" if first else None)
        _draw_block(axes, piston, 0.06 * mechanism.rod, alpha, first)


# How linkage.png draws each registry entry's ``drawing``.
DRAWINGS: dict[str, Callable[[Any, LinkageCurves, MechanismTable], None]] = {
    "joints": _draw_joints,
    "fourbar_like": _draw_fourbar_like,
    "slider_crank": _draw_slider_crank,
}
