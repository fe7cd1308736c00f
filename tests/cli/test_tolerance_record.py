"""A tolerance study's memory and record (issue 34 items 5 and 6).

Item 5: the memory estimate that guards ``sso tolerance`` is within 2x of the peak the
real command reaches, measured here (``getrusage(RUSAGE_CHILDREN).ru_maxrss`` of a
process that runs it and nothing else), from 10,000 to 1,000,000 samples. Item 6:
what the study writes, ``sso report`` reads back: ``result.json`` holds the study's
settings and summary (kilobytes at any sample count) and the samples stay in
``tolerance.csv``; reading back draws the samples again from the seed and checks the
saved summary against them.

The modules under test: sso/_studies/tolerance_samples.py and sso/_studies/saved_samples.py.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from test_cli import sso

from sso._cases.schema import load_case
from sso._cli.saved_results import shipped_schema
from sso._studies.tolerance_study import study_estimate

ROOT = Path(__file__).resolve().parents[2]
EXACT = ROOT / "cases" / "paper_option1_exact.toml"
PAPER = ROOT / "cases" / "paper_option1_paper.toml"
# Runs one command as a child and prints the child's peak resident memory (MB).
MEASURE = """
import json, resource, subprocess, sys
completed = subprocess.run(sys.argv[1:], capture_output=True, text=True)
print(json.dumps({"returncode": completed.returncode, "stderr": completed.stderr,
                  "peak_mb": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024}))
"""
RECORD_BYTES = 10_000  # result.json of a study: settings and summary only


def _peak_mb(*command, cwd) -> dict:
    completed = subprocess.run([sys.executable, "-c", MEASURE, sys.executable, "-m", "sso._cli",
                                *map(str, command)], cwd=cwd, capture_output=True, text=True,
                               timeout=600, check=True)
    return json.loads(completed.stdout)


def _estimate_mb(case_path: Path, samples: int) -> float:
    case = load_case(case_path)
    quadrature = (case.quadrature_rtol, case.quadrature_atol)
    return study_estimate(case.series(), samples, quadrature).memory_mb


def _study(case_path: Path, samples: int, folder: Path) -> tuple[dict, Path]:
    measured = _peak_mb("tolerance", case_path, "--at", "start", "--samples", samples,
                        "--workers", "1", "--out", "out", "--quiet", "--memory-limit", "100000",
                        cwd=folder)
    assert measured["returncode"] == 0, measured["stderr"]
    return measured, folder / "out" / case_path.stem


def _within_twice(measured_mb: float, estimate_mb: float) -> None:
    assert estimate_mb / 2 <= measured_mb <= 2 * estimate_mb, (measured_mb, estimate_mb)


@pytest.mark.parametrize("case_path, samples", [(EXACT, 10_000), (EXACT, 100_000),
                                                (PAPER, 10_000)])
def test_the_estimate_is_within_twice_the_measured_peak(tmp_path, case_path, samples):
    measured, report = _study(case_path, samples, tmp_path)
    _within_twice(measured["peak_mb"], _estimate_mb(case_path, samples))
    assert (report / "result.json").stat().st_size < RECORD_BYTES


@pytest.mark.slowest
def test_a_million_sample_study_is_read_back_by_sso_report_within_its_estimate(tmp_path):
    # The command: 1,000,000 samples, one worker, a limit of 1,000 MB. It
    # estimated 488 MB and peaked at 1.44 GB writing a 208 MB result.json that sso
    # report (100 MB at most) refused. About 26 s on 2 busy cores: the study and the
    # report each draw, evaluate and write a million samples.
    estimate = _estimate_mb(EXACT, 1_000_000)
    assert estimate <= 1000.0
    measured, report = _study(EXACT, 1_000_000, tmp_path)
    _within_twice(measured["peak_mb"], estimate)
    assert (report / "result.json").stat().st_size < RECORD_BYTES
    with open(report / "tolerance.csv", "rb") as handle:
        assert sum(1 for _ in handle) == 1_000_001  # the header and every sample
    written = (report / "report.md").read_bytes()
    again = _peak_mb("report", report / "result.json", cwd=tmp_path)
    assert again["returncode"] == 0, again["stderr"]
    _within_twice(again["peak_mb"], estimate)
    # The samples drawn again from the seed give the same report, byte for byte.
    assert (report / "report.md").read_bytes() == written


@pytest.fixture(scope="module")
def small_study(tmp_path_factory):
    folder = tmp_path_factory.mktemp("study")
    completed = sso("tolerance", EXACT, "--at", "start", "--samples", "2000", "--workers", "1",
                    "--out", "out", "--quiet", cwd=folder)
    assert completed.returncode == 0, completed.stderr
    return json.loads((folder / "out" / EXACT.stem / "result.json").read_text())


@pytest.mark.parametrize("edit, message", [
    (lambda saved: saved["summary"]["percentiles"]["residual_error"].update({"95": 1e-9}),
     "result.summary.percentiles.residual_error.95 = 1e-09 is not the figure of the samples "
     "drawn again from the study's seed"),
    (lambda saved: saved.update(seed=1), "result.summary.percentiles.residual_error.5 = "),
    (lambda saved: saved["summary"]["max"].update(fluctuation=-1.0),
     "result.summary.max.fluctuation = -1.0 is not the figure"),
    (lambda saved: saved.update(samples=0), "result.samples = 0; allowed: a whole number >= 1"),
    (lambda saved: saved.update(reflected_samples=7), "result.reflected_samples = 7; the samples "
                                                      "drawn again from the study's seed "
                                                      "reflect 0"),
    (lambda saved: saved["nominal"].update(residual_error=0.5),
     "nominal.residual_error = 0.5 is not the figure of design"),
    (lambda saved: saved.pop("summary"), "result.summary is missing"),
])
def test_an_edited_study_record_is_refused_naming_the_field(small_study, tmp_path, edit,
                                                            message):
    _refused(json.loads(json.dumps(small_study)), edit, message, tmp_path)


def _refused(saved: dict, edit, message: str, folder: Path) -> None:
    """``sso report`` of ``saved`` after ``edit``: exit 2 with ``message``."""
    edit(saved)
    path = folder / "edited" / "result.json"
    path.parent.mkdir()
    path.write_text(json.dumps(saved), encoding="utf-8")
    completed = sso("report", path, "--out", folder / "report", cwd=folder)
    assert completed.returncode == 2, completed.stdout
    assert message in completed.stderr
    assert "Traceback" not in completed.stderr


COLUMN = ROOT / "cases" / "column_truck_three_joints.toml"


@pytest.fixture(scope="module")
def column_study(tmp_path_factory):
    folder = tmp_path_factory.mktemp("column_study")
    completed = sso("tolerance", COLUMN, "--samples", "2000", "--workers", "1", "--out", "out",
                    "--quiet", cwd=folder)
    assert completed.returncode == 0, completed.stderr
    return folder / "out" / COLUMN.stem


def test_a_column_study_keeps_its_samples_in_its_table_and_reads_back(column_study):
    # The record holds the built columns' settings and summary; tolerance.csv the 2,000
    # samples; sso report draws them again and writes the same report.
    record = column_study / "result.json"
    assert record.stat().st_size < RECORD_BYTES
    assert "beta_deg" not in json.loads(record.read_text())
    with open(column_study / "tolerance.csv", "rb") as handle:
        assert sum(1 for _ in handle) == 2001
    written = (column_study / "report.md").read_bytes()
    again = sso("report", record, cwd=column_study)
    assert again.returncode == 0, again.stderr
    assert (column_study / "report.md").read_bytes() == written


@pytest.mark.parametrize("edit, message", [
    (lambda saved: saved["nominal"].update(residual_error=1e-3),
     "nominal.residual_error = 0.001 is not the figure of the nominal column, computed again"),
    (lambda saved: saved["summary"]["mean"].update(residual_error=1e-3),
     "summary.mean.residual_error = 0.001 is not the figure of the samples drawn again"),
    (lambda saved: saved.update(hardpoint_mm=0.25), "summary.percentiles.residual_error.5 = "),
])
def test_an_edited_column_study_record_is_refused(column_study, tmp_path, edit, message):
    _refused(json.loads((column_study / "result.json").read_text()), edit, message, tmp_path)


def test_a_study_record_meets_the_shipped_schema(small_study, column_study):
    jsonschema = pytest.importorskip("jsonschema")
    schema = shipped_schema()
    jsonschema.validate(small_study, schema)
    jsonschema.validate(json.loads((column_study / "result.json").read_text()), schema)
