"""``sso tolerance`` of a column case, run as a user runs it: the optimum on the splines
found first (or the assembly as built), the report folder, exit 2 for bad input."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import sso

ROOT = Path(__file__).resolve().parents[2]
TRUCK = ROOT / "cases" / "column_truck_three_joints.toml"
YOKE = (10.0, -80.0)


def _sso(*arguments, cwd):
    return subprocess.run([sys.executable, "-m", "sso", *map(str, arguments)], cwd=cwd,
                          capture_output=True, text=True, timeout=600)


def test_sso_tolerance_of_the_truck_column_exits_0_with_its_reports(tmp_path):
    done = _sso("tolerance", TRUCK, "--samples", "2000", "--out", tmp_path, "--quiet",
                "--workers", "2", cwd=ROOT)
    assert done.returncode == 0, done.stderr
    folder = tmp_path / "column_truck_three_joints"
    assert {"result.json", "tolerance.csv", "report.md", "report.html",
            "tolerance_histogram.png"} <= {path.name for path in folder.iterdir()}
    assert "the best assembly on the splines (teeth [36, 36], tooth offsets [1, -8])" \
        in done.stdout
    saved = sso.ColumnToleranceResult.from_dict(json.loads((folder / "result.json").read_text()))
    assert saved.samples == 2000 and saved.yoke_phase_deg == YOKE
    lines = (folder / "tolerance.csv").read_text().splitlines()
    assert len(lines) == 2001 and lines[0].endswith("largest_transmission_error_deg")
    start = _sso("tolerance", TRUCK, "--at", "start", "--samples", "50", "--out",
                 tmp_path / "start", "--quiet", "--workers", "1", "--no-plots", cwd=ROOT)
    assert start.returncode == 0, start.stderr
    assert "the assembly as built (phasing.yoke_phase_deg)" in start.stdout


def test_sso_tolerance_of_a_column_with_too_large_a_tolerance_exits_2(tmp_path):
    case = tmp_path / "loose.toml"
    case.write_text(TRUCK.read_text() + "\n[tolerances]\nhardpoint_mm = 100.0\n"
                    "yoke_phase_deg = 1.0\n")
    done = _sso("tolerance", case, "--at", "start", "--out", tmp_path / "out", "--quiet",
                "--workers", "1", cwd=tmp_path)
    assert done.returncode == 2
    assert "hardpoint_mm = 100 mm is too large for this column" in done.stderr
    assert "Traceback" not in done.stderr
