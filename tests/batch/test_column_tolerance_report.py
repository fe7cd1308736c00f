"""The report of a column's tolerance study: every sample in tolerance.csv, the
percentiles in report.md, the saved result read back equal."""

import csv
import json
from dataclasses import replace

import numpy as np
import pytest

import sso
from sso.cases.schema import load_case

GEOMETRY = load_case("cases/column_truck_three_joints.toml").geometry()


def test_the_report_holds_every_sample_and_the_percentiles(tmp_path):
    result = sso.tolerance_study((GEOMETRY, (10.0, -80.0)), samples=25, seed=5, workers=1,
                                 tolerances=sso.Tolerances(hardpoint_mm=1.0, yoke_phase_deg=2.0),
                                 out_dir=tmp_path / "study", progress=False)
    names = {path.name for path in result.files}
    assert names == {"result.json", "tolerance.csv", "report.md", "report.html",
                     "tolerance_histogram.png"}
    with open(tmp_path / "study" / "tolerance.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == 25
    assert [float(row["residual_error"]) for row in rows] == pytest.approx(
        result.residual_error.tolist(), rel=1e-5)  # 6 digits
    assert [float(row["yoke_phase_error_deg[1]"]) for row in rows] == pytest.approx(
        result.yoke_phase_error_deg[:, 1].tolist(), rel=1e-5)
    markdown = (tmp_path / "study" / "report.md").read_text()
    p95 = np.percentile(result.speed_fluctuation_percent, 95.0)
    assert "| speed-ratio fluctuation, lock to lock (%) |" in markdown
    assert sso.display.format_number(p95) in markdown
    assert "every coordinate of every hardpoint 1 mm, each yoke phasing 2 deg" in markdown
    saved = json.loads((tmp_path / "study" / "result.json").read_text())
    assert sso.ColumnToleranceResult.from_dict(saved) == replace(result, files=())
