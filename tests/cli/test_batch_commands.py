"""``sso sweep`` and ``sso tolerance`` run as a user runs them (subprocess)."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

CASE = Path("cases/steering_column.toml").resolve()
SWEEP = f"""
case = "{CASE}"
action = "evaluate"
[axes]
"design.beta_deg[0]" = {{ start = 10, stop = 30, num = 3 }}
input_speed_rpm = [20, 40]
"""


def sso_command(*arguments, cwd):
    return subprocess.run([sys.executable, "-m", "sso.cli", *map(str, arguments)], cwd=cwd,
                          capture_output=True, text=True, timeout=300)


def test_sso_sweep_writes_the_sweep_and_resumes_it(tmp_path):
    (tmp_path / "map.toml").write_text(SWEEP)
    first = sso_command("sweep", "map.toml", "--workers", "1", "--quiet", cwd=tmp_path)
    assert first.returncode == 0, first.stderr
    assert first.stderr == ""  # --quiet, and not a terminal: no progress bar
    assert "sweep: 6 points (6 computed" in first.stdout
    folder = tmp_path / "results" / "map"
    assert {path.name for path in folder.iterdir()} == {
        "sweep.csv", "sweep.json", "report.md", "report.html", "sweep_re.png", "sso-files.json"}
    again = sso_command("sweep", "map.toml", "--workers", "1", cwd=tmp_path)
    assert again.returncode == 2
    assert "already holds a sweep" in again.stderr and "Traceback" not in again.stderr
    resumed = sso_command("sweep", "map.toml", "--resume", "--no-plots", cwd=tmp_path)
    assert resumed.returncode == 0, resumed.stderr
    assert "0 computed" in resumed.stdout and "6 from an earlier run" in resumed.stdout


@pytest.mark.parametrize("text, message", [
    (SWEEP.replace("[axes]", "acton = 'x'\n[axes]"), "unknown key acton; did you mean action?"),
    (SWEEP.replace("input_speed_rpm = [20, 40]", "input_speed = [20, 40]"),
     "did you mean 'input_speed_rpm'?"),
    (SWEEP.replace('case = "', 'case = "missing-'), "cannot read the case file"),
    (SWEEP.replace("[axes]", "mode = 'grid'\n[axes]"), "mode = 'grid' is not one of"),
])
def test_sso_sweep_refuses_bad_sweep_files_with_exit_2(tmp_path, text, message):
    (tmp_path / "bad.toml").write_text(text)
    completed = sso_command("sweep", "bad.toml", "--no-plots", cwd=tmp_path)
    assert completed.returncode == 2
    assert message in completed.stderr and "Traceback" not in completed.stderr


def test_sso_tolerance_reads_the_case_tolerance_table(tmp_path):
    case = tmp_path / "column.toml"
    case.write_text(CASE.read_text() + "\n[tolerance]\nbeta_deg = 0.2\nsamples = 300\n"
                    "seed = 4\n")
    completed = sso_command("tolerance", case, "--no-plots", "--quiet", cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    summary = json.loads((tmp_path / "results" / "steering_column" /
                          "tolerance.json").read_text())
    assert (summary["samples"], summary["seed"]) == (300, 4)
    assert summary["beta_tolerance_deg"] == [0.2, 0.2]
    assert "tolerance: 300 samples (normal, seed 4)" in completed.stdout


def test_sso_tolerance_studies_the_optimum_and_says_so(tmp_path):
    case = tmp_path / "column.toml"
    case.write_text(CASE.read_text() + "\n[tolerance]\nsamples = 200\n")
    optimum = sso_command("tolerance", case, "--no-plots", "--quiet", cwd=tmp_path)
    assert optimum.returncode == 0, optimum.stderr
    folder = tmp_path / "results" / "steering_column"
    report = (folder / "report.md").read_text()
    assert "Design studied: the optimum (" in report and "column.toml, optimised first" in report
    study = json.loads((folder / "tolerance.json").read_text())
    # The optimum cancels the column's fluctuation: its RE is far below the start's.
    start = sso_command("tolerance", case, "--at", "start", "--no-plots", "--quiet",
                        "--out", tmp_path / "start", cwd=tmp_path)
    assert start.returncode == 0, start.stderr
    at_start = json.loads((tmp_path / "start" / "steering_column" / "tolerance.json").read_text())
    assert "the design as given (start)" in at_start["study_of"]
    assert study["nominal"]["residual_error"] < 1e-3 * at_start["nominal"]["residual_error"]


def test_sso_tolerance_reads_the_optimum_from_a_result_file(tmp_path):
    case = tmp_path / "column.toml"
    case.write_text(CASE.read_text() + "\n[tolerance]\nsamples = 100\n")
    run = sso_command("run", case, "--no-plots", "--quiet", "--out", tmp_path / "run",
                      cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    result = tmp_path / "run" / "steering_column" / "result.json"
    document = json.loads(result.read_text())
    study = sso_command("tolerance", case, "--result", result, "--no-plots", "--quiet",
                        cwd=tmp_path)
    assert study.returncode == 0, study.stderr
    summary = json.loads((tmp_path / "results" / "steering_column" /
                          "tolerance.json").read_text())
    optimum = document["optimisation"]["best"]["series"]
    assert summary["design"]["beta_deg"] == optimum["beta_deg"]
    assert "read from" in summary["study_of"]
    both = sso_command("tolerance", case, "--result", result, "--at", "start", cwd=tmp_path)
    assert both.returncode == 2 and "use one of them" in both.stderr


def test_sso_sweep_refuses_a_mechanism_case_with_exit_2(tmp_path):
    mechanism = Path("cases/mechanisms/fourbar_crank2.toml").resolve()
    (tmp_path / "bad.toml").write_text(f'case = "{mechanism}"\n[axes]\ninput_speed_rpm = [1, 2]\n')
    completed = sso_command("sweep", "bad.toml", cwd=tmp_path)
    assert completed.returncode == 2
    assert ("kind = 'fourbar': sso sweep and sso tolerance work on shaft_series and column cases"
            in completed.stderr)
    assert "Traceback" not in completed.stderr
