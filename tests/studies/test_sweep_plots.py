"""Sweep plots a reviewer reads at a glance (issue 35, item 8): axes named in words
with their unit, not by the raw key, and a column sweep's % and deg figures plotted
beside RE."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import sso
from sso._studies.report import (
    SWEEP_FIGURES_PLOT,
    _figures_figure,
    _sweep_figure,
    axis_label,
    render_sweep,
)

ROOT = Path(__file__).resolve().parents[2]
TRUCK = ROOT / "cases" / "column_truck_three_joints.toml"


@pytest.mark.parametrize("path, label", [
    ("hardpoints.points_mm[2][2]", "P2 z (mm)"),
    ("hardpoints.positions.tilt_up.points_mm[0][1]", "P0 y at tilt_up (mm)"),
    ("design.beta_deg[0]", "beta[0] (deg)"),
    ("input_speed_rpm", "input speed (rpm)"),
    ("limits.speed_fluctuation_percent", "speed fluctuation (%)"),
    ("solver.starts", "starts"),
])
def test_a_swept_key_reads_in_words_with_its_unit(path, label):
    assert axis_label(path) == label


def test_a_column_sweep_plots_its_percent_and_degree_figures():
    heights = [1234.3, 1244.3]  # the upper joint's box in z (cases/column_truck_three_joints)
    result = sso.sweep(TRUCK, {"hardpoints.points_mm[1][2]": heights}, action="evaluate",
                       workers=1)
    assert SWEEP_FIGURES_PLOT in render_sweep(result, ("png",))
    figure = _figures_figure(result)
    assert [axes.get_xlabel() for axes in figure.axes] == ["P1 z (mm)", "P1 z (mm)"]
    assert [axes.get_ylabel() for axes in figure.axes] == [
        "speed-ratio fluctuation, lock to lock (%)",
        "largest |transmission error|, lock to lock (deg)"]
    for axes, column in zip(figure.axes, ("speed_fluctuation_percent",
                                          "largest_transmission_error_deg"), strict=True):
        (line,) = axes.get_lines()
        np.testing.assert_array_equal(line.get_xdata(), heights)
        np.testing.assert_array_equal(line.get_ydata(), result.numbers(column))
    assert _sweep_figure(result).axes[0].get_xlabel() == "P1 z (mm)"


def test_a_shaft_series_sweep_has_no_steering_figures_plot():
    result = sso.sweep(ROOT / "cases" / "paper_option1_exact.toml",
                       {"design.beta_deg[0]": [10.0, 20.0]}, action="evaluate", workers=1)
    assert SWEEP_FIGURES_PLOT not in render_sweep(result, ("png",))
