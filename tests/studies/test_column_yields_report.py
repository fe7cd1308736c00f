"""The yields and sensitivity in a column tolerance study's report: the limits on the
histograms, the bar chart's bars, and its legend inside the figure and off the bars."""

from __future__ import annotations

import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg

import sso
from sso._studies.column_tolerance_report import _histograms
from sso._studies.column_yields_report import sensitivity_figure, yield_parts
from sso._studies.report import _figure

CAR = sso.ColumnGeometry([[-950.0, 360.0, 780.0], [-717.9, 296.7, 569.0],
                          [-660.0, 250.0, 430.0], [-610.0, 275.0, 300.0],
                          [-590.0, 300.0, 190.0]])


@pytest.fixture(scope="module")
def study():
    return sso.tolerance_study(
        (CAR, (-80.0, -60.0)), samples=400, progress=False, workers=1,
        tolerances=sso.Tolerances(hardpoint_mm=0.5, yoke_phase_deg=1.0),
        limits=sso.SteeringLimits(speed_fluctuation_percent=2.0, transmission_error_deg=0.5))


def test_the_limits_are_drawn_on_the_histograms(study):
    figure = _histograms(study)
    drawn = {axes.get_xlabel(): [line for line in axes.get_lines()
                                 if line.get_label().startswith("limit ")]
             for axes in figure.axes}
    (fluctuation,) = drawn["speed-ratio fluctuation, lock to lock (%)"]
    (error,) = drawn["largest |transmission error|, lock to lock (deg)"]
    assert list(fluctuation.get_xdata()) == [2.0, 2.0] and list(error.get_xdata()) == [0.5, 0.5]
    assert fluctuation.get_label() == (
        f"limit 2 %, yield {100 * study.yields.limits[0].fraction:.1f} %")
    assert drawn["residual error RE (dimensionless)"] == []  # no limit on RE


def test_the_bar_chart_draws_the_largest_indices_with_its_legend_inside(study):
    figure = sensitivity_figure(study, _figure)
    (axes,) = figure.axes
    names = [label.get_text() for label in axes.get_yticklabels()]
    for found, bars in zip(study.sensitivity, axes.containers, strict=True):
        indices = {item.tolerance: item.index for item in found.contributions}
        assert [bar.get_width() for bar in bars] == [indices[name] for name in names]
    # the top of the chart is the tolerance with the largest index of any figure
    largest = max((item.index, item.tolerance) for found in study.sensitivity
                  for item in found.contributions)
    assert names[-1] == largest[1]
    canvas = FigureCanvasAgg(figure)  # as the report saves it (Agg)
    canvas.draw()
    renderer = canvas.get_renderer()
    legend = axes.get_legend().get_window_extent(renderer)
    frame = figure.bbox
    assert frame.x0 <= legend.x0 and legend.x1 <= frame.x1
    assert frame.y0 <= legend.y0 and legend.y1 <= frame.y1
    for bars in axes.containers:  # off the bars
        for bar in bars:
            assert not bar.get_window_extent(renderer).overlaps(legend)


def test_without_a_required_yield_the_summary_judges_nothing(study):
    lines = [part for part in yield_parts(study) if isinstance(part, str)]
    assert lines[0].startswith("  verdict: yield of all limits together ")
    assert lines[0].endswith("no required yield set ([limits] yield): the yield is reported, "
                             "not judged")
    assert study.yields.verdict == "not judged" and study.yields.signed_off
