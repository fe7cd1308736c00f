"""The driveline report's plots are written, one PNG each."""

from __future__ import annotations

from driveline.driveline_cases import truck_two_piece

from sso._driveline.figures import analyse_driveline
from sso._reports.driveline_plots import CAPTIONS, driveline_plots


def test_every_plot_is_a_png_with_a_caption() -> None:
    plots = driveline_plots(analyse_driveline(truck_two_piece(), phasing=False))
    assert set(plots) == set(CAPTIONS)
    assert all(data.startswith(b"\x89PNG\r\n\x1a\n") and len(data) > 10_000
               for data in plots.values())
