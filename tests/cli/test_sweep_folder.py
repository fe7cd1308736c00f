"""A sweep's folder holds one sweep: the reproductions of the data-loss report, each run
as a user runs it (``sso sweep`` in a subprocess), ending with exit 2 and a clear
message, or with a correct result, and with every file sso did not write still there."""

from __future__ import annotations

import shutil
import subprocess
import sys
import time
from pathlib import Path

from sso._studies.table import read_rows

CASE = Path("cases/paper_option1_exact.toml").resolve()
SMALL = f"""
case = "{CASE}"
action = "evaluate"
name = "same"
[axes]
"design.beta_deg[0]" = {{ start = 10, stop = 30, num = 20 }}
"""
LARGE = SMALL.replace("num = 20", "num = 200")
# Optimised with both solvers from 4 starts, one point per task: seconds in all, so a
# second sweep can be started while the first one runs.
SLOW = f"""
case = "{CASE}"
name = "same"
chunk_size = 1
[axes]
"design.beta_deg[0]" = {{ start = 10, stop = 30, num = 120 }}
"solver.starts" = [8]
"""


def sso(*arguments, cwd):
    return subprocess.run([sys.executable, "-m", "sso._cli", *map(str, arguments)], cwd=cwd,
                          capture_output=True, text=True, timeout=300)


def _sweep_file(folder, name, text):
    (folder / name).write_text(text)
    return name


def test_resume_refuses_the_rows_of_another_sweep_of_the_same_name(tmp_path):
    large = sso("sweep", _sweep_file(tmp_path, "large.toml", LARGE), "--workers", "1",
                "--no-plots", "--out", "big", cwd=tmp_path)
    assert large.returncode == 0, large.stderr
    small = sso("sweep", _sweep_file(tmp_path, "small.toml", SMALL), "--workers", "1",
                "--no-plots", cwd=tmp_path)
    assert small.returncode == 0, small.stderr
    shutil.copy(tmp_path / "big" / "same" / "sweep.csv", tmp_path / "results" / "same")
    resumed = sso("sweep", "small.toml", "--resume", "--no-plots", cwd=tmp_path)
    assert resumed.returncode == 2
    assert "line 2 belongs to another sweep (sweep_hash" in resumed.stderr
    assert "Traceback" not in resumed.stderr


def test_resume_refuses_a_row_with_a_negative_point(tmp_path):
    # The reproduction: a row of point -1 was accepted ("21 points" for a 20-point
    # sweep).
    first = sso("sweep", _sweep_file(tmp_path, "small.toml", SMALL), "--workers", "1",
                "--no-plots", cwd=tmp_path)
    assert first.returncode == 0, first.stderr
    csv_path = tmp_path / "results" / "same" / "sweep.csv"
    lines = csv_path.read_text().splitlines(keepends=True)
    lines[1] = "-1" + lines[1][lines[1].index(","):]
    csv_path.write_text("".join(lines))
    before = csv_path.read_bytes()
    resumed = sso("sweep", "small.toml", "--resume", "--no-plots", cwd=tmp_path)
    assert resumed.returncode == 2
    assert "line 2: point '-1' is outside this sweep's points [0, 19]" in resumed.stderr
    assert "Traceback" not in resumed.stderr
    assert csv_path.read_bytes() == before  # the user's file is left as it was


def test_a_truncated_sweep_csv_resumes_to_the_whole_sweep(tmp_path):
    first = sso("sweep", _sweep_file(tmp_path, "small.toml", SMALL), "--workers", "1",
                "--no-plots", cwd=tmp_path)
    assert first.returncode == 0, first.stderr
    csv_path = tmp_path / "results" / "same" / "sweep.csv"
    whole = read_rows(csv_path)
    csv_path.write_bytes(csv_path.read_bytes()[:-300])  # cut inside a row
    resumed = sso("sweep", "small.toml", "--resume", "--no-plots", cwd=tmp_path)
    assert resumed.returncode == 0, resumed.stderr
    assert "from an earlier run" in resumed.stdout

    def without_times(rows):
        return sorted(({k: v for k, v in row.items() if k != "time_s"} for row in rows),
                      key=lambda row: int(row["point"]))

    assert without_times(read_rows(csv_path)) == without_times(whole)


def test_a_sweep_never_shares_the_folder_of_a_case_or_the_user_s_files(tmp_path):
    run = sso("run", CASE, "--out", "results", "--no-plots", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    case_folder = tmp_path / "results" / "paper_option1_exact"
    before = {path.name: path.read_bytes() for path in case_folder.iterdir()}
    clash = SMALL.replace('name = "same"', 'name = "paper_option1_exact"')
    swept = sso("sweep", _sweep_file(tmp_path, "clash.toml", clash), "--no-plots", cwd=tmp_path)
    assert swept.returncode == 2
    assert "holds a case report written by sso: a sweep and a case report never share a " \
        "folder" in swept.stderr
    assert {path.name: path.read_bytes() for path in case_folder.iterdir()} == before
    mine = tmp_path / "results" / "same"
    mine.mkdir()
    (mine / "thesis.md").write_text("notes")
    swept = sso("sweep", _sweep_file(tmp_path, "small.toml", SMALL), "--no-plots", cwd=tmp_path)
    assert swept.returncode == 2 and "holds thesis.md, which sso did not write" in \
        swept.stderr
    assert (mine / "thesis.md").read_text() == "notes"


def test_two_sweeps_of_the_same_name_started_together_never_share_the_folder(tmp_path):
    _sweep_file(tmp_path, "slow.toml", SLOW)
    command = [sys.executable, "-m", "sso._cli", "sweep", "slow.toml", "--workers", "1",
               "--no-plots", "--quiet"]
    first = subprocess.Popen(command, cwd=tmp_path, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
    csv_path = tmp_path / "results" / "same" / "sweep.csv"
    deadline = time.monotonic() + 120
    try:
        while not (csv_path.exists() and read_rows(csv_path)):
            assert first.poll() is None and time.monotonic() < deadline
            time.sleep(0.01)
        second = sso("sweep", "slow.toml", "--workers", "1", "--no-plots", "--resume",
                     cwd=tmp_path)
        assert second.returncode == 2
        assert f"is in use: process {first.pid} holds its lock" in second.stderr
        first_code = first.wait(timeout=300)
    finally:
        if first.poll() is None:
            first.kill()
            first.wait()
    rows = read_rows(csv_path)
    assert sorted(int(row["point"]) for row in rows) == list(range(120))
    # The first sweep's exit code is its verdict on its points: 1 when a point's solvers
    # disagree or did not converge (the real cross-check finds such points on this grid).
    assert first_code == (1 if any(row["success"] != "true" for row in rows) else 0)
