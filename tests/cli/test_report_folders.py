"""The ``sso`` command deletes or replaces only files it wrote, run as a user runs it.

Each test is a reproduction of a way reports used to delete a user's files or leave
debris: a project folder holding a result.json beside the user's notes; a sweep and
a case of the same name; two runs into one folder at once; a report folder that is a
symbolic link; an ``--out`` path of 1,100 parts. Each ends with a clear exit 2 or a
correct report, and every file sso did not write is still there, unchanged.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from slow_case import slow_case

from sso._files import FOLDER_MANIFEST

ROOT = Path(__file__).resolve().parents[2]
CASE = ROOT / "cases" / "paper_option1_exact.toml"
PAPER_CASE = ROOT / "cases" / "paper_option1_paper.toml"
SWEEP = f"""\
name = "paper_option1_paper"
case = "{PAPER_CASE}"
action = "evaluate"

[axes]
input_speed_rpm = [10, 20]
"""
def sso(*arguments: object, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "sso._cli", *map(str, arguments)], cwd=cwd,
                          capture_output=True, text=True, timeout=600)


def contents(folder: Path) -> dict[str, bytes]:
    return {path.name: path.read_bytes() for path in folder.iterdir()}


def names(folder: Path) -> list[str]:
    return sorted(path.name for path in folder.iterdir())


@pytest.fixture(scope="module")
def result_json(tmp_path_factory: pytest.TempPathFactory) -> bytes:
    """A result.json written by ``sso evaluate``."""
    folder = tmp_path_factory.mktemp("run")
    completed = sso("evaluate", CASE, "--out", "out", "--no-plots", "--quiet", cwd=folder)
    assert completed.returncode == 0, completed.stderr
    return (folder / "out" / "paper_option1_exact" / "result.json").read_bytes()


def test_a_report_is_not_written_over_a_project_s_files(tmp_path, result_json):
    project = tmp_path / "myproject"
    project.mkdir()
    mine = {"result.json": result_json, "thesis.md": b"notes\n", "measurements.csv": b"t,x\n",
            "photo_of_rig.png": b"\x89PNG\r\n", "config.json": b"{}\n"}
    for name, data in mine.items():
        (project / name).write_bytes(data)
    completed = sso("report", "myproject/result.json", "--no-plots", cwd=tmp_path)
    assert completed.returncode == 2
    assert ("error: myproject/result.json: cannot write the report: myproject holds "
            "config.json, measurements.csv, photo_of_rig.png, thesis.md, which sso did not "
            f"write (it has no {FOLDER_MANIFEST})") in completed.stderr
    assert "Traceback" not in completed.stderr
    assert contents(project) == mine


def test_a_result_json_alone_in_its_folder_is_reported_there(tmp_path, result_json):
    (tmp_path / "copy").mkdir()
    (tmp_path / "copy" / "result.json").write_bytes(result_json)
    completed = sso("report", "copy/result.json", "--no-plots", cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    assert names(tmp_path / "copy") == ["report.html", "report.md", "result.json", "speeds.csv",
                                        FOLDER_MANIFEST]
    (tmp_path / "copy" / "notes.txt").write_text("mine")  # added later: never deleted
    again = sso("report", "copy/result.json", "--no-plots", cwd=tmp_path)
    assert again.returncode == 2 and "holds notes.txt, which sso did not write" in again.stderr
    assert (tmp_path / "copy" / "notes.txt").read_text() == "mine"


def test_a_sweep_and_a_case_of_one_name_never_share_a_folder(tmp_path):
    (tmp_path / "sweep.toml").write_text(SWEEP)
    swept = sso("sweep", "sweep.toml", "--workers", "1", "--no-plots", "--quiet", cwd=tmp_path)
    assert swept.returncode == 0, swept.stderr
    folder = tmp_path / "results" / "paper_option1_paper"
    sweep_files = contents(folder)
    assert {"sweep.csv", "sweep.json"} <= set(sweep_files)
    run = sso("run", PAPER_CASE, "--no-plots", "--quiet", cwd=tmp_path)
    assert run.returncode == 2
    assert ("results/paper_option1_paper holds a sweep written by sso: a case report and a "
            "sweep never share a folder") in run.stderr
    assert contents(folder) == sweep_files
    # And the other way round: a case's report is not replaced by a sweep.
    shutil.rmtree(folder)
    run = sso("run", PAPER_CASE, "--no-plots", "--quiet", cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    report_files = contents(folder)
    swept = sso("sweep", "sweep.toml", "--workers", "1", "--no-plots", "--quiet", cwd=tmp_path)
    assert swept.returncode == 2
    assert "holds a case report written by sso: a sweep and a case report" in swept.stderr
    assert contents(folder) == report_files


def test_a_second_run_into_a_folder_being_written_is_refused(tmp_path):
    (tmp_path / "slow.toml").write_text(slow_case("ipopt", starts=150))
    first = subprocess.Popen([sys.executable, "-m", "sso._cli", "run", "slow.toml", "--no-plots"],
                             cwd=tmp_path, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True)
    assert first.stdout is not None
    assert "solving" in first.stdout.readline()
    second = sso("run", "slow.toml", "--no-plots", cwd=tmp_path)
    still_solving = first.poll() is None
    stdout, stderr = first.communicate(timeout=600)
    assert first.returncode == 0, stderr
    assert still_solving, "the first run ended before the second started: make it slower"
    assert second.returncode == 2
    assert (f"error: slow: cannot write the report into results/slow: results/slow is in use: "
            f"process {first.pid} holds its lock .sso-lock-slow to write the report of slow "
            "there") in second.stderr
    assert names(tmp_path / "results") == ["slow"]  # no lock file, no temporary folder
    assert names(tmp_path / "results" / "slow") == ["report.html", "report.md", "result.json",
                                                    "speeds.csv", FOLDER_MANIFEST]


def test_two_runs_racing_for_one_folder_leave_one_whole_report_and_no_debris(tmp_path):
    runs = [subprocess.Popen([sys.executable, "-m", "sso._cli", "evaluate", CASE, "--no-plots",
                              "--quiet"], cwd=tmp_path, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True) for _ in range(4)]
    outcomes = [(run.wait(timeout=600), run.communicate()[1]) for run in runs]
    for code, stderr in outcomes:  # each wrote the report, or was refused while another did
        assert code == 0 or (code == 2 and "holds its lock" in stderr), stderr
    assert any(code == 0 for code, _ in outcomes)
    assert names(tmp_path / "results") == ["paper_option1_exact"]
    assert names(tmp_path / "results" / "paper_option1_exact") == [
        "report.html", "report.md", "result.json", "speeds.csv", FOLDER_MANIFEST]


def test_a_report_folder_that_is_a_link_is_written_through_it(tmp_path):
    first = sso("evaluate", CASE, "--out", "disk", "--no-plots", "--quiet", cwd=tmp_path)
    assert first.returncode == 0, first.stderr
    (tmp_path / "results").mkdir()
    link = tmp_path / "results" / "paper_option1_exact"
    link.symlink_to(tmp_path / "disk" / "paper_option1_exact", target_is_directory=True)
    again = sso("run", CASE, "--no-plots", "--quiet", cwd=tmp_path)
    assert again.returncode == 0, again.stderr
    assert link.is_symlink()
    assert '"mode": "optimise"' in (link / "result.json").read_text()
    assert names(tmp_path / "results") == ["paper_option1_exact"]
    assert names(tmp_path / "disk") == ["paper_option1_exact"]


def test_a_sweep_into_a_linked_folder_ends(tmp_path):
    (tmp_path / "sweep.toml").write_text(SWEEP)
    (tmp_path / "disk" / "sweep").mkdir(parents=True)
    (tmp_path / "results").mkdir()
    (tmp_path / "results" / "paper_option1_paper").symlink_to(tmp_path / "disk" / "sweep")
    swept = sso("sweep", "sweep.toml", "--workers", "1", "--no-plots", "--quiet", cwd=tmp_path)
    assert swept.returncode == 0, swept.stderr
    assert names(tmp_path / "disk" / "sweep") == ["report.html", "report.md", FOLDER_MANIFEST,
                                                  "sweep.csv", "sweep.json"]
    assert names(tmp_path / "results") == ["paper_option1_paper"]


def test_an_out_path_of_1100_parts_is_written(tmp_path):
    deep = Path(*["p"] * 1100)
    try:
        completed = sso("evaluate", CASE, "--out", deep, "--no-plots", "--quiet", cwd=tmp_path)
        assert completed.returncode == 0, completed.stderr[-2000:]
        assert (tmp_path / deep / "paper_option1_exact" / "result.json").is_file()
    finally:  # shutil.rmtree (and pytest's clean-up) would recurse 1,100 levels deep
        subprocess.run(["rm", "-rf", str(tmp_path / "p")], check=True, timeout=60)


def test_an_out_path_too_long_for_the_system_is_refused_with_exit_2(tmp_path):
    completed = sso("evaluate", CASE, "--out", Path(*["q"] * 2100), "--no-plots", "--quiet",
                    cwd=tmp_path)
    assert completed.returncode == 2
    assert "cannot write the report into q/q/q" in completed.stderr
    assert completed.stderr.rstrip().endswith("File name too long")
    assert "Traceback" not in completed.stderr
    assert names(tmp_path) == []
