"""Plots of a column's robust phasing: positions, tolerance study, phase errors, feel.

Drawn from the run's robust part alone (:class:`sso._run.column_robust.ColumnRobustPart`),
on the figures of :mod:`sso._reports.plots`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from sso._column.positions import PositionsResult
from sso._reports.plots import _new_figure, legend_below
from sso._run.column import ColumnRun
from sso._run.column_robust import ColumnRobustPart, FeelPart, PositionsPart, TolerancesPart

DESIGN_COLOURS = {"nominal": "#1f77b4", "as_built": "#7f7f7f", "positions": "#2ca02c",
                  "robust": "#d62728", "on_centre": "#9467bd"}
# A log axis cannot show a cancelled RE (~1e-26): such values are drawn on this floor.
RE_FLOOR = 1e-12


def robust_figures(run: ColumnRun) -> dict[str, Any]:
    """The figures of the robust part, keyed by file name (none without one)."""
    robust = run.robust
    if robust is None:
        return {}
    figures = {}
    if robust.positions is not None and robust.positions.result is not None:
        figures["positions.png"] = _positions(robust, robust.positions, robust.positions.result)
    if robust.tolerances is not None:
        figures["tolerance_study.png"] = _tolerance_study(robust, robust.tolerances)
    figures["phase_error.png"] = phase_error_figure(robust)
    if robust.feel is not None:
        figures["steering_feel.png"] = _steering_feel(robust, robust.feel)
    return figures


def _colour(role: str) -> str:
    return DESIGN_COLOURS.get(role, "#8c564b")


def _positions(robust: ColumnRobustPart, positions: PositionsPart,
               result: PositionsResult) -> Any:
    figure = _new_figure("constrained")
    axes = figure.add_subplot()
    names = list(positions.geometries)
    bars = [(f"{name}'s own optimum", single.position_re, "#bbbbbb", hatch)
            for (name, single), hatch in zip(result.single_position.items(),
                                             ("", "//", "oo", "xx", "--"), strict=False)]
    bars += [(design.label, design.positions.position_re, _colour(design.role), "")
             for design in robust.designs if design.positions is not None]
    width = 0.8 / len(bars)
    for index, (label, values, colour, hatch) in enumerate(bars):
        heights = [max(values[name], RE_FLOOR) for name in names]
        axes.bar(np.arange(len(names)) + (index - (len(bars) - 1) / 2) * width, heights, width,
                 color=colour, hatch=hatch, edgecolor="black", linewidth=0.5, label=label)
    worst = result.worst_re
    axes.axhline(worst, color="#2ca02c", linestyle=":", linewidth=1.2,
                 label=f"shared phasing's worst RE {worst:.3g}")
    axes.set_xticks(np.arange(len(names)), names)
    axes.set_yscale("log")
    axes.set_ylabel(f"RE (values below {RE_FLOOR:g} drawn at it)")
    axes.set_title("RE at every position: each position's own optimum\nagainst the designs "
                   "compared", fontsize=10)
    axes.grid(True, axis="y", which="both", alpha=0.3)
    legend_below(figure, axes)
    return figure


def _tolerance_study(robust: ColumnRobustPart, tolerances: TolerancesPart) -> Any:
    figure = _new_figure("constrained")
    axes = figure.add_subplot()
    by_role = {design.role: design for design in robust.designs}
    for role, values in tolerances.samples_re.items():
        design = by_role[role]
        study = design.study
        assert study is not None  # every design has its study where the case has tolerances
        sorted_values = np.asarray(values)
        fraction = np.arange(1, len(sorted_values) + 1) / len(sorted_values)
        p95 = study.p95
        axes.step(sorted_values, fraction, where="post", color=_colour(role), linewidth=1.8,
                  label=f"{design.label}: p50 {study.p50:.3g}, p95 {p95:.3g}")
        axes.plot([p95], [0.95], marker="o", color=_colour(role))
    axes.axhline(0.95, color="black", linestyle=":", linewidth=1.0)
    axes.set_xscale("log")
    axes.set_xlabel("RE of a built column")
    axes.set_ylabel("fraction of the sample at or below")
    settings = tolerances.tolerances
    axes.set_title(f"Tolerance study: {settings.samples} columns, hardpoints "
                   f"{settings.hardpoint_mm:g} mm, yoke phasing {settings.yoke_phase_deg:g} "
                   f"deg ({settings.distribution}, seed {settings.seed})", fontsize=10)
    axes.grid(True, which="both", alpha=0.3)
    legend_below(figure, axes)
    return figure


def phase_error_figure(robust: ColumnRobustPart) -> Any:
    """The figure of ``phase_error.png``, its legend in a strip below the panels."""
    figure = _new_figure("constrained")
    curves = robust.phase_error.curves
    errors = np.asarray(robust.phase_error.errors_deg)
    names = list(next(iter(curves.values())))
    limit = robust.band_re_limit
    labels = {design.role: design.label for design in robust.designs}
    grid = figure.subplots(1, len(names), sharey=True, squeeze=False)[0]
    for axes, name in zip(grid, names, strict=True):
        for role, by_name in curves.items():
            axes.plot(errors, by_name[name], color=_colour(role), linewidth=1.8,
                      label=labels[role])
        if limit is not None:
            axes.axhline(limit, color="black", linestyle=":", linewidth=1.2,
                         label=f"band.re_limit {limit:g}")
        shaft = int(name.split("[")[1].rstrip("]")) + 1
        axes.set_xlabel(f"error of delta_{shaft} (deg)")
        axes.set_title(f"intermediate shaft {shaft}", fontsize=10)
        axes.grid(True, alpha=0.3)
    grid[0].set_ylabel("RE (other phasings at nominal)")
    legend_below(figure, grid[0])
    figure.suptitle("RE against each yoke phasing's error")
    return figure


def _steering_feel(robust: ColumnRobustPart, feel: FeelPart) -> Any:
    figure = _new_figure()
    wheel = np.asarray(feel.wheel_deg)
    window, lock = feel.window_deg, feel.lock_deg
    labels = {design.role: design.label for design in robust.designs}
    panels = (("left lock", -lock), ("on-centre", 0.0), ("right lock", lock))
    grid = figure.subplots(1, 3, sharey=True)
    for axes, (title, middle) in zip(grid, panels, strict=True):
        inside = np.abs(wheel - middle) <= 2.0 * window
        for role, ratio in feel.ratio.items():
            axes.plot(wheel[inside], np.asarray(ratio)[inside], color=_colour(role),
                      linewidth=1.6, label=labels[role])
        axes.axvspan(middle - window, middle + window, color="#ffdd88", alpha=0.35)
        axes.set_title(f"{title} ({middle:+g} deg)", fontsize=10)
        axes.grid(True, alpha=0.3)
    grid[0].set_ylabel("speed ratio, output / input")
    figure.supxlabel("steering-wheel angle from straight ahead (deg)", y=0.13, fontsize=10)
    figure.subplots_adjust(bottom=0.22)
    handles, names = grid[0].get_legend_handles_labels()
    figure.legend(handles, names, fontsize=8, loc="lower center", ncol=2)
    figure.suptitle(f"Steering feel: straight ahead at theta = {feel.straight_ahead_deg:g}"
                    f" deg, windows +-{window:g} deg")
    return figure
