"""``steering.png``: speed ratio, torque ratio and transmission error from lock to lock.

Drawn from the run's :class:`sso.SteeringAssessment` alone, on the figures of
:mod:`sso._reports.plots`.
"""

from __future__ import annotations

from typing import Any

from sso._column.steering_criteria import SteeringAssessment
from sso._reports.plots import _new_figure, _png, legend_below

# Assemblies often coincide (as built = best on the splines): a dash each keeps every
# one visible.
LINESTYLES = ("-", "--", "-.", ":")
CURVES = (("speed_ratio", "speed ratio out / in"),
          ("torque_ratio", "torque ratio T_out / T_in"),
          ("transmission_error_deg", "transmission error (deg)"))


def steering_plot(steering: SteeringAssessment) -> bytes:
    """PNG of the steering curves of every assembly (one line each) against wheel angle."""
    return _png(steering_figure(steering))


def steering_figure(steering: SteeringAssessment) -> Any:
    """The figure of :func:`steering_plot`, its legend in a strip below the panels."""
    figure = _new_figure("constrained")
    axes = figure.subplots(len(CURVES), 1, sharex=True)
    for index, design in enumerate(steering.designs):
        figures = design.range
        for panel, (name, _) in zip(axes, CURVES, strict=True):
            panel.plot(figures.wheel_angle_deg, getattr(figures, name), linewidth=1.6,
                       linestyle=LINESTYLES[index % len(LINESTYLES)], label=design.label)
    for panel, (_, label) in zip(axes, CURVES, strict=True):
        panel.set_ylabel(label, fontsize=8)
        panel.grid(True, alpha=0.3)
    axes[-1].set_xlabel("steering-wheel angle from straight ahead (deg; + clockwise as the "
                        "driver sees it)")
    axes[0].set_title(f"Lock to lock (+-{steering.lock_deg:g} deg): every assembly compared",
                      fontsize=10)
    legend_below(figure, axes[0])
    return figure
