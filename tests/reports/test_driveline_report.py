"""The driveline report's words and tables (rendered from the result alone)."""

from __future__ import annotations

import csv
import io
from pathlib import Path

from sso._cases.schema import load_case
from sso._reports.driveline_report import render_driveline_run, rules_csv
from sso._run.driveline import run_driveline

TRUCK = Path(__file__).resolve().parents[2] / "cases" / "driveline_truck_two_piece.toml"


def test_report_speaks_the_trade_and_cites_each_rule() -> None:
    run = run_driveline(load_case(TRUCK), optimising=True)
    files = render_driveline_run(run, ("md", "csv", "html"))
    page = files["report.html"].decode("utf-8")
    assert "<canvas" in page and "joint 3 (pinion): true angle 4.000 deg" in page
    report = files["report.md"].decode("utf-8")
    for words in ("gearbox", "propshaft 1", "centre bearing 1", "pinion", "in phase",
                  "side-view slope", "plan-view angle", "Position: laden", "Position: wind_up",
                  "signed-square rule", "Critical speed", "pinion far (F)", "Trade:",
                  "Joint life"):
        assert words in report, words
    rows = list(csv.DictReader(io.StringIO(rules_csv(run.result))))
    assert len(rows) == len(run.result.rules)
    assert all(row["source"] for row in rows)
    failed = [row for row in rows if row["verdict"] == "FAIL"]
    assert ("torsional excitation", "design, 2500 rpm") in {(row["rule"], row["where"])
                                                           for row in failed}
    assert files["rules.csv"].decode("utf-8") == rules_csv(run.result)
