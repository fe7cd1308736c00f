"""Plots of a column's robust phasing: positions, tolerance study, phase errors, feel.

Drawn from ``document["robust"]`` alone (:mod:`sso._run.column_robust_document`),
on the figures of :mod:`sso._reports.plots`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from sso._reports.plots import _new_figure, _png

DESIGN_COLOURS = {"nominal": "#1f77b4", "as_built": "#7f7f7f", "positions": "#2ca02c",
                  "robust": "#d62728", "on_centre": "#9467bd"}
# A log axis cannot show a cancelled RE (~1e-26): such values are drawn on this floor.
RE_FLOOR = 1e-12


def render_robust_plots(document: Mapping[str, Any]) -> dict[str, bytes]:
    """PNG images of the robust part, keyed by file name (none without one)."""
    robust = document.get("robust")
    if robust is None:
        return {}
    images = {}
    if "positions" in robust and "result" in robust["positions"]:
        images["positions.png"] = _positions(robust)
    if "tolerances" in robust:
        images["tolerance_study.png"] = _tolerance_study(robust)
    images["phase_error.png"] = _phase_error(robust)
    if "feel" in robust:
        images["steering_feel.png"] = _steering_feel(robust)
    return images


def _colour(role: str) -> str:
    return DESIGN_COLOURS.get(role, "#8c564b")


def _positions(robust: Mapping[str, Any]) -> bytes:
    figure = _new_figure()
    axes = figure.add_subplot()
    positions = robust["positions"]
    names = positions["names"]
    bars = [(f"{name}'s own optimum", single["position_re"], "#bbbbbb", hatch)
            for (name, single), hatch in zip(positions["result"]["single_position"].items(),
                                             ("", "//", "oo", "xx", "--"), strict=False)]
    bars += [(entry["label"], entry["position_re"], _colour(entry["role"]), "")
             for entry in robust["designs"]]
    width = 0.8 / len(bars)
    for index, (label, values, colour, hatch) in enumerate(bars):
        heights = [max(values[name], RE_FLOOR) for name in names]
        axes.bar(np.arange(len(names)) + (index - (len(bars) - 1) / 2) * width, heights, width,
                 color=colour, hatch=hatch, edgecolor="black", linewidth=0.5, label=label)
    worst = positions["result"]["worst_re"]
    axes.axhline(worst, color="#2ca02c", linestyle=":", linewidth=1.2,
                 label=f"shared phasing's worst RE {worst:.3g}")
    axes.set_xticks(np.arange(len(names)), names)
    axes.set_yscale("log")
    axes.set_ylabel(f"RE (values below {RE_FLOOR:g} drawn at it)")
    axes.set_title("RE at every position: each position's own optimum\nagainst the designs "
                   "compared", fontsize=10)
    axes.grid(True, axis="y", which="both", alpha=0.3)
    figure.subplots_adjust(right=0.66)
    axes.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    return _png(figure)


def _tolerance_study(robust: Mapping[str, Any]) -> bytes:
    figure = _new_figure()
    axes = figure.add_subplot()
    samples = robust["tolerances"]["samples_re"]
    labels = {entry["role"]: entry for entry in robust["designs"]}
    for role, values in samples.items():
        entry = labels[role]
        sorted_values = np.asarray(values)
        fraction = np.arange(1, len(sorted_values) + 1) / len(sorted_values)
        p95 = entry["study"]["p95"]
        axes.step(sorted_values, fraction, where="post", color=_colour(role), linewidth=1.8,
                  label=f"{entry['label']}: p50 {entry['study']['p50']:.3g}, p95 {p95:.3g}")
        axes.plot([p95], [0.95], marker="o", color=_colour(role))
    axes.axhline(0.95, color="black", linestyle=":", linewidth=1.0)
    axes.set_xscale("log")
    axes.set_xlabel("RE of a built column")
    axes.set_ylabel("fraction of the sample at or below")
    settings = robust["tolerances"]["settings"]
    axes.set_title(f"Tolerance study: {settings['samples']} columns, hardpoints "
                   f"{settings['hardpoint_mm']:g} mm, yoke phasing {settings['yoke_phase_deg']:g} "
                   f"deg ({settings['distribution']}, seed {settings['seed']})", fontsize=10)
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=8, loc="upper left")
    return _png(figure)


def _phase_error(robust: Mapping[str, Any]) -> bytes:
    figure = _new_figure()
    curves = robust["phase_error"]
    errors = np.asarray(curves["errors_deg"])
    names = list(next(iter(curves["re"].values())))
    limit = robust.get("band", {}).get("re_limit")
    labels = {entry["role"]: entry["label"] for entry in robust["designs"]}
    grid = figure.subplots(1, len(names), sharey=True, squeeze=False)[0]
    for axes, name in zip(grid, names, strict=True):
        for role, by_name in curves["re"].items():
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
    grid[0].legend(fontsize=8, loc="upper center")
    figure.suptitle("RE against each yoke phasing's error")
    return _png(figure)


def _steering_feel(robust: Mapping[str, Any]) -> bytes:
    figure = _new_figure()
    feel = robust["feel"]
    settings = feel["settings"]
    wheel = np.asarray(feel["wheel_deg"])
    window, lock = settings["window_deg"], settings["lock_deg"]
    labels = {entry["role"]: entry["label"] for entry in robust["designs"]}
    panels = (("left lock", -lock), ("on-centre", 0.0), ("right lock", lock))
    grid = figure.subplots(1, 3, sharey=True)
    for axes, (title, middle) in zip(grid, panels, strict=True):
        inside = np.abs(wheel - middle) <= 2.0 * window
        for role, ratio in feel["ratio"].items():
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
    figure.suptitle(f"Steering feel: straight ahead at theta = {settings['straight_ahead_deg']:g}"
                    f" deg, windows +-{window:g} deg")
    return _png(figure)
