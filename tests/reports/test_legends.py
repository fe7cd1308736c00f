"""Every plot's legend lies inside its figure and off its curves (issue 35, item 8),
checked from the saved figure's artist extents: each legend's window extent within
the figure's, and no drawn point of any curve inside it.

The figures are those the reports save for the shipped cases whose plots had
legends over their curves or cut off: steering.png's legend of eight assemblies and
phase_error.png (cases/column_truck_three_positions.toml), excitation.png with its
limits (cases/column_truck_trade.toml) and polar.png
(cases/paper_option3_exact.toml, whose legend read "25 to" at the figure's edge).
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pytest

import sso
from sso._reports.column_plots import excitation_figure
from sso._reports.column_robust_plots import phase_error_figure
from sso._reports.column_steering_plots import steering_figure
from sso._reports.plots import SpeedPlot, polar_figure

CASES = Path(__file__).resolve().parents[2] / "cases"


@pytest.fixture(scope="module")
def positions():
    return sso.run_case(CASES / "column_truck_three_positions.toml")


def assert_legends_clear(figure) -> int:
    """Save ``figure``, then check every legend against the figure and the curves;
    returns the number of legend entries checked."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(figure)  # the canvas the report's savefig draws on
    figure.savefig(io.BytesIO(), format="png", dpi=figure.dpi)
    renderer = canvas.get_renderer()
    legends = [*figure.legends, *(axes.get_legend() for axes in figure.axes
                                  if axes.get_legend() is not None)]
    assert legends
    whole = figure.bbox
    entries = 0
    for legend in legends:
        box = legend.get_window_extent(renderer)
        assert whole.x0 - 0.5 <= box.x0 and box.x1 <= whole.x1 + 0.5, (box, whole)
        assert whole.y0 - 0.5 <= box.y0 and box.y1 <= whole.y1 + 0.5, (box, whole)
        for axes in figure.axes:
            for line in axes.get_lines():
                points = line.get_transform().transform(np.asarray(line.get_xydata()))
                inside = ((points[:, 0] > box.x0) & (points[:, 0] < box.x1)
                          & (points[:, 1] > box.y0) & (points[:, 1] < box.y1))
                assert not inside.any(), f"{line.get_label()!r} runs under the legend"
        entries += len(legend.get_texts())
    return entries


def test_the_steering_legend_of_every_assembly_is_clear(positions):
    assert assert_legends_clear(steering_figure(positions.steering)) == len(
        positions.steering.designs)


def test_the_phase_error_legend_is_clear(positions):
    assert positions.robust is not None
    assert assert_legends_clear(phase_error_figure(positions.robust)) >= 2


def test_each_excitation_panel_has_its_own_limit_and_a_clear_legend():
    run = sso.run_case(CASES / "column_truck_trade.toml")
    figure = excitation_figure(run)
    # 2 assemblies x 4 figures, and the two limits (truck: 2000 and 500 rad/s^2)
    assert assert_legends_clear(figure) == 10
    limits = [[line.get_ydata()[0] for line in axes.get_lines() if "limit" in line.get_label()]
              for axes in figure.axes]
    assert limits == [[2000.0], [500.0]]
    inertial = {line.get_label().split(",")[0] for line in figure.axes[0].get_lines()}
    assert inertial == {"drive (SAE AE-7)", "coast (SAE AE-7)", "inertial limit (truck): 2000 "
                        "rad/s^2"}


def test_the_polar_legend_is_whole_and_clear():
    run = sso.run_case(CASES / "paper_option3_exact.toml")
    figure = polar_figure(SpeedPlot(tuple(run.designs), "paper_option3_exact",
                                    "exact model, option 3 (both), input 25 rpm"))
    assert assert_legends_clear(figure) == 1 + len(run.designs)  # the input shaft too


def test_every_plot_of_the_column_reports_has_clear_legends(positions):
    from sso._reports.column_plots import column_figures

    driveline = sso.run_case(CASES / "column_truck_trade.toml")
    figures = {**{f"driveline {name}": figure
                  for name, figure in column_figures(driveline).items()},
               **column_figures(positions)}
    assert {"steering.png", "excitation.png", "positions.png", "tolerance_study.png",
            "phase_error.png", "steering_feel.png", "column_3d.png"} <= set(figures)
    failures = {}
    for name, figure in figures.items():
        try:
            assert_legends_clear(figure)
        except AssertionError as error:
            failures[name] = str(error).splitlines()[0]
    assert failures == {}


def test_every_plot_of_a_shaft_series_report_has_clear_legends():
    from sso._reports.plots import speed_figures

    run = sso.run_case(CASES / "paper_option3_exact.toml")
    for figure in speed_figures(SpeedPlot(tuple(run.designs), "paper_option3_exact",
                                          "exact model, option 3 (both), input 25 rpm")).values():
        assert assert_legends_clear(figure) == 1 + len(run.designs)


@pytest.mark.parametrize("case", ["fourbar_crank2", "quickreturn", "slidercrank_r2_0p050m",
                                  "fourbar_swing_design"])
def test_every_plot_of_a_mechanism_report_has_clear_legends(case):
    from sso._reports.mechanism_plots import mechanism_figures

    run = sso.run_case(CASES / "mechanisms" / f"{case}.toml")
    failures = {}
    for name, figure in mechanism_figures(run).items():
        try:
            assert_legends_clear(figure)
        except AssertionError as error:
            failures[name] = str(error).splitlines()[0]
    assert failures == {}


def test_the_sweep_and_tolerance_study_plots_have_clear_legends():
    from sso._studies.report import _figures_figure, _sweep_figure, _tolerance_figure

    study = sso.tolerance_study(CASES / "paper_option3_exact.toml", samples=500, workers=1)
    assert assert_legends_clear(_tolerance_figure(study)) == 1  # nominal
    sweep = sso.sweep(CASES / "column_truck_three_joints.toml",
                      {"hardpoints.points_mm[1][2]": [1234.3, 1244.3],
                       "hardpoints.points_mm[2][2]": [868.8, 878.8]},
                      action="evaluate", workers=1)
    assert assert_legends_clear(_sweep_figure(sweep)) >= 2
    assert assert_legends_clear(_figures_figure(sweep)) == 2  # one line per P2 z value
