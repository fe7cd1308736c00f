"""The end-of-sweep report reads the sweep's columns: the same choices as row by row, and
bounded work for a large sweep (failures listed up to a limit, plot points sampled)."""

from __future__ import annotations

import numpy as np

import sso
from sso._studies.report import MOST_DRAWN_POINTS, REPORT_ROWS, _sweep_figure, render_sweep

ONE_JOINT = {"design": {"beta_deg": [20.0]}, "input_speed_rpm": 30.0}
THREE_JOINTS = {"design": {"beta_deg": [20.0, 20.0, 20.0], "phase_deg": [90.0, 90.0]}}


def test_the_lowest_re_order_is_the_order_of_sorting_the_rows():
    # Refused values (above 90 deg) fail; the reference is the row-by-row sort the report
    # used before: failed last, an empty RE as 0, ties in point order.
    values = [35.0, 95.0, 10.0, 20.0, 100.0, 10.0, 0.0]
    result = sso.sweep(ONE_JOINT, {"design.beta_deg[0]": values}, action="evaluate",
                       workers=1, progress=False)
    expected = sorted(range(len(values)), key=lambda index: (
        result.rows[index]["status"] != "ok", result.rows[index]["residual_error"] or 0.0))
    assert result.lowest_re_order().tolist() == expected == [6, 2, 5, 3, 0, 1, 4]
    assert result.failed_points().tolist() == [1, 4]
    assert result.numbers("residual_error")[1] != result.numbers("residual_error")[1]  # NaN


def test_a_report_lists_the_first_failures_and_counts_the_rest():
    values = [20.0, *(91.0 + index for index in range(REPORT_ROWS + 7))]
    result = sso.sweep(ONE_JOINT, {"design.beta_deg[0]": values}, action="evaluate",
                       workers=1, progress=False)
    report = render_sweep(result, ("md",))["report.md"].decode("utf-8")
    failures = report.split("## Failed points", 1)[1]
    assert failures.count("is outside the allowed range") == REPORT_ROWS
    assert "... and 7 more failed points (every one is in sweep.csv)." in failures
    assert f"{REPORT_ROWS + 7} failed" in report


def test_each_panel_of_a_large_sweep_draws_a_sample_and_every_lowest_value():
    axis = {"start": 10.0, "stop": 40.0, "num": 30}
    result = sso.sweep(THREE_JOINTS, {f"design.beta_deg[{joint}]": axis for joint in range(3)},
                       action="evaluate", workers=1, progress=False)
    assert len(result.rows) == 27_000 > MOST_DRAWN_POINTS
    figure = _sweep_figure(result)
    assert f"at most {MOST_DRAWN_POINTS:,} points drawn a panel" in figure._suptitle.get_text()
    errors = np.maximum(result.numbers("residual_error"), 1e-15)
    for joint, axes in enumerate(figure.axes[:3]):
        lowest, *points = [line for line in axes.lines
                           if not line.get_label().startswith("round-off floor")]
        assert sum(len(line.get_xdata()) for line in points) == MOST_DRAWN_POINTS
        # The lowest RE at each of the 30 values, from every point (not the sample).
        x = result.numbers(f"design.beta_deg[{joint}]")
        reference = [errors[x == value].min() for value in np.unique(x)]
        np.testing.assert_allclose(lowest.get_ydata(), reference, rtol=0, atol=0)


def test_exact_cancellations_tie_and_the_first_point_is_the_lowest():
    # Two equal joints phased 90 deg apart cancel exactly at any angle; their RE is
    # round-off of different sizes (1.6e-34 at 30 deg, 1.8e-36 at 10 deg), which prints
    # as "< 1e-15" alike: the first such point is the sweep's lowest, whatever round-off
    # the solvers or the platform leave.
    values = [30.0, 20.0, 10.0]
    result = sso.sweep({"design": {"beta_deg": [20.0, 20.0], "phase_deg": [90.0]}},
                       {"design.beta_deg[0]": values, "design.beta_deg[1]": values},
                       action="evaluate", workers=1, progress=False)
    errors = result.numbers("residual_error")
    assert errors[8] < errors[0] < 1e-30  # round-off alone would rank point 8 first
    assert result.best["point"] == 0
    assert result.lowest_re_order().tolist()[:3] == [0, 4, 8]
    assert "lowest RE < 1e-15 at point 0" in result.summary()
