"""``polar.png`` and ``cartesian.png``: input and output speed over one revolution.

matplotlib is imported inside :func:`render_plots` only (Agg canvas, no pyplot
state), so a run without plots never loads it.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from typing import Any, Literal

import numpy as np

from sso._shafts.curves import ComparedDesign

WIDTH_PX = 1000
HEIGHT_PX = 700
DPI = 100
STYLES = {
    "initial": {"color": "#d62728", "linestyle": "-", "linewidth": 2.0},
    "optimum": {"color": "#1f77b4", "linestyle": "-", "linewidth": 2.4},
    "reference": {"color": "#2ca02c", "linestyle": "-.", "linewidth": 2.0},
}
INPUT_STYLE = {"color": "black", "linestyle": "--", "linewidth": 1.2, "zorder": 3}
# A peak-to-peak speed deviation below this fraction of the input speed is round-off:
# plotting it would show noise that differs from machine to machine.
ROUND_OFF = 1e-9


def render_plots(designs: Sequence[ComparedDesign], name: str,
                 heading: str) -> dict[str, bytes]:
    """PNG images of the speed curves the designs carry, keyed by file name.

    Parameters
    ----------
    designs : sequence of ComparedDesign
        The designs, each with its speed curve (one input speed for all).
    name : str
        The case's name (titles).
    heading : str
        The second line of the titles: model, option and input speed.

    Returns
    -------
    dict of str to bytes
        ``"polar.png"`` and ``"cartesian.png"``, each ``WIDTH_PX`` x ``HEIGHT_PX``.
    """
    figures = speed_figures(SpeedPlot(tuple(designs), name, heading))
    return {file: _png(figure) for file, figure in figures.items()}


def speed_figures(plot: SpeedPlot) -> dict[str, Any]:
    """The figures of :func:`render_plots`, keyed by file name."""
    return {"polar.png": polar_figure(plot), "cartesian.png": _cartesian(plot)}


class SpeedPlot:
    """The designs of one report, with what every plot of them reads."""

    def __init__(self, designs: tuple[ComparedDesign, ...], name: str, heading: str) -> None:
        self.designs = designs
        self.name = name
        self.heading = heading
        self.input_angle_deg = designs[0].input_angle_deg
        self.input_speed_rpm = designs[0].evaluation.input_speed_rpm

    def title(self, what: str) -> str:
        return f"{self.name}: {what}\n{self.heading}"

    def optimum(self) -> ComparedDesign | None:
        return next((design for design in self.designs if design.role == "optimum"), None)


def _new_figure(layout: Literal["constrained"] | None = None) -> Any:
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    return Figure(figsize=(WIDTH_PX / DPI, HEIGHT_PX / DPI), dpi=DPI, layout=layout)


LONG_LABEL = 55
"""Legend entries longer than this (characters) go one to a row, shorter ones two."""


def legend_below(figure: Any, axes: Any, title: str | None = None) -> Any:
    """The legend of ``axes``' curves (each label once) in a strip of its own below the
    plots: inside the figure and off every curve, however many entries it has.

    ``figure`` must use the constrained layout (``_new_figure("constrained")``), which
    shrinks the plots to make room for the strip.
    """
    entries: dict[str, Any] = {}
    for panel in np.atleast_1d(axes):
        for handle, label in zip(*panel.get_legend_handles_labels(), strict=True):
            entries.setdefault(label, handle)
    columns = 1 if max((len(label) for label in entries), default=0) > LONG_LABEL else 2
    return figure.legend(list(entries.values()), list(entries), loc="outside lower center",
                         ncols=min(columns, max(len(entries), 1)), fontsize="small",
                         title=title, title_fontsize="small", alignment="left")


def _png(figure: Any) -> bytes:
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=DPI)
    return buffer.getvalue()


def _legend_label(design: ComparedDesign) -> str:
    evaluation = design.evaluation
    return (f"{design.label}: {evaluation.speed_min_rpm:.4g} to "
            f"{evaluation.speed_max_rpm:.4g} rpm, RE {evaluation.residual_error:.3g}")


def _plot_speeds(axes: Any, angle: np.ndarray, plot: SpeedPlot) -> tuple[float, float]:
    """Draw the input speed and every design's output speed; return the speed range (rpm)."""
    axes.plot(angle, np.full_like(angle, plot.input_speed_rpm),
              label=f"input shaft: {plot.input_speed_rpm:g} rpm", **INPUT_STYLE)
    for design in plot.designs:
        axes.plot(angle, design.output_speed_rpm, label=_legend_label(design),
                  **STYLES[design.role])
    every_speed = np.concatenate([*(design.output_speed_rpm for design in plot.designs),
                                  [plot.input_speed_rpm]])
    return float(every_speed.min()), float(every_speed.max())


def _cartesian(plot: SpeedPlot) -> Any:
    figure = _new_figure()
    optimum = plot.optimum()
    if optimum is not None:
        speeds, zoom = figure.subplots(2, 1, sharex=True, height_ratios=(3, 2))
    else:
        speeds, zoom = figure.subplots(1, 1), None
    angle = plot.input_angle_deg
    low, high = _plot_speeds(speeds, angle, plot)
    spread = max(high - low, 0.02 * plot.input_speed_rpm)
    speeds.set_ylim(low - 0.05 * spread, high + 0.75 * spread)
    speeds.set_ylabel("shaft speed (rpm)")
    speeds.set_title(plot.title("shaft speeds over one input revolution"))
    speeds.legend(loc="upper right", fontsize="small", framealpha=0.9)
    speeds.grid(True, alpha=0.4)
    axis_with_angles = speeds
    if zoom is not None and optimum is not None:
        deviation = optimum.output_speed_rpm - plot.input_speed_rpm
        if np.ptp(deviation) < ROUND_OFF * plot.input_speed_rpm:
            title = (f"zoom on the optimum: output minus input speed is below round-off "
                     f"({ROUND_OFF:g} of the input speed), drawn as 0")
            deviation = np.zeros_like(deviation)
        else:
            title = ("zoom on the optimum: output minus input speed, peak to peak "
                     f"{np.ptp(deviation):.3g} rpm")
        zoom.axhline(0.0, **INPUT_STYLE)
        zoom.plot(angle, deviation, **STYLES["optimum"])
        zoom.set_ylabel("output - input (rpm)")
        zoom.set_title(title, fontsize="medium")
        zoom.grid(True, alpha=0.4)
        zoom.ticklabel_format(axis="y", style="sci", scilimits=(-3, 4), useOffset=False)
        axis_with_angles = zoom
    axis_with_angles.set_xlabel("input shaft angle (deg)")
    axis_with_angles.set_xlim(0.0, 360.0)
    axis_with_angles.set_xticks(np.arange(0.0, 361.0, 45.0))
    figure.tight_layout()
    return figure


def polar_figure(plot: SpeedPlot) -> Any:
    """The figure of ``polar.png``: speeds around one input revolution, the legend and
    how to read the axes below it."""
    figure = _new_figure("constrained")
    axes = figure.add_subplot(projection="polar")
    low, high = _plot_speeds(axes, np.radians(plot.input_angle_deg), plot)
    # The radius starts at 0: a scale from the least speed would magnify the ripple
    # (the cartesian plot zooms on it, and says so).
    margin = max(0.15 * (high - low), 0.02 * plot.input_speed_rpm)
    axes.set_rlim(0.0, high + margin)
    axes.set_thetagrids(np.arange(0, 360, 45),
                        labels=[f"{angle} deg" for angle in range(0, 360, 45)])
    axes.set_rlabel_position(22.5)
    axes.tick_params(axis="y", labelsize="small")
    axes.grid(True, alpha=0.5)
    figure.suptitle(plot.title("speeds around one input revolution"))
    legend_below(figure, axes, title="angle: input shaft angle (deg), counter-clockwise from 0; "
                 f"radius: shaft speed (rpm), from 0 at the centre (speeds {low:.4g} to "
                 f"{high:.4g} rpm)")
    return figure
