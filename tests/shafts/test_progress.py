"""A long multi-start run shows a progress bar with the time left, on a terminal only."""

from __future__ import annotations

import io
import sys
import warnings

import sso


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def _optimise_with_stderr(monkeypatch, stream, starts):
    monkeypatch.delenv("CI", raising=False)
    monkeypatch.setattr(sys, "stderr", stream)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        # without screening, every solver runs from every start (the bar's runs)
        return sso.optimise(sso.ShaftSeries([30.0, 40.0], [90.0]), starts=starts,
                            screen_starts=False)


def test_a_long_multistart_run_draws_runs_done_and_time_left(monkeypatch):
    terminal = Terminal()
    _optimise_with_stderr(monkeypatch, terminal, starts=50)  # 100 runs: two solvers
    drawn = terminal.getvalue()
    assert "100/100 runs" in drawn
    assert " left" in drawn and "runs/s" in drawn


def test_no_bar_off_a_terminal_or_for_a_short_run(monkeypatch):
    pipe = io.StringIO()
    _optimise_with_stderr(monkeypatch, pipe, starts=50)
    assert pipe.getvalue() == ""
    terminal = Terminal()
    _optimise_with_stderr(monkeypatch, terminal, starts=8)
    assert terminal.getvalue() == ""
