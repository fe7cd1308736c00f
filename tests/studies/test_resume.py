"""Resuming a sweep that was really interrupted: a process killed mid-run."""

import subprocess
import sys
import time

import sso
from sso._studies.table import TIME_COLUMNS, read_rows

# Option 3 on three joints with two solvers and four starts: tens of ms per point,
# so the run is still going when the first chunk lands on disk.
BASE = {"design": {"beta_deg": [30.0, 40.0, 50.0], "phase_deg": [90.0, 90.0]},
        "bounds": {"beta_deg": [10.0, 40.0]}, "solver": {"starts": 4}}
AXES = {"design.beta_deg[0]": {"start": 10.0, "stop": 40.0, "num": 4},
        "design.beta_deg[1]": {"start": 10.0, "stop": 40.0, "num": 5}}
POINTS = 20
RUN = """
import sys
import sso
sso.sweep({base!r}, {axes!r}, out_dir=sys.argv[1], workers=1, chunk_size=1, plots=False)
"""
KILL_DEADLINE_S = 120.0


def _without_times(rows):
    return [{key: value for key, value in row.items() if key not in TIME_COLUMNS}
            for row in rows]


def test_a_killed_sweep_resumes_to_the_file_an_uninterrupted_run_writes(tmp_path):
    interrupted = tmp_path / "interrupted"
    process = subprocess.Popen([sys.executable, "-c", RUN.format(base=BASE, axes=AXES),
                                str(interrupted)])
    csv_path = interrupted / "sweep.csv"
    deadline = time.monotonic() + KILL_DEADLINE_S
    try:
        while not (csv_path.exists() and read_rows(csv_path)) and process.poll() is None:
            assert time.monotonic() < deadline, "the sweep wrote no chunk in time"
            time.sleep(0.002)
    finally:
        process.kill()
        process.wait()
    done_before = read_rows(csv_path)
    assert 1 <= len(done_before) < POINTS, "the run was not interrupted mid-way"

    resumed = sso.sweep(BASE, AXES, out_dir=interrupted, workers=1, chunk_size=3,
                        plots=False, resume=True)
    assert resumed.resumed == len(done_before)
    assert resumed.computed == POINTS - len(done_before)
    uninterrupted = sso.sweep(BASE, AXES, out_dir=tmp_path / "whole", workers=1, plots=False)

    resumed_rows = read_rows(csv_path)
    assert len(resumed_rows) == POINTS
    # The points done before the kill (the first ones: one process, in order) are
    # kept exactly as they were written, wall times included.
    assert resumed_rows[:len(done_before)] == done_before
    # Same file as the uninterrupted run, cell for cell, apart from wall times.
    assert _without_times(resumed_rows) == _without_times(read_rows(tmp_path / "whole" /
                                                                    "sweep.csv"))
    assert [row["point"] for row in resumed.rows] == list(range(POINTS))
    assert all(row["status"] == "ok" for row in uninterrupted.rows)


def test_resuming_a_finished_sweep_computes_nothing(tmp_path):
    axes = {"design.beta_deg[0]": [10.0, 20.0]}
    first = sso.sweep(BASE, axes, action="evaluate", out_dir=tmp_path, workers=1, plots=False)
    text = (tmp_path / "sweep.csv").read_text()
    again = sso.sweep(BASE, axes, action="evaluate", out_dir=tmp_path, workers=1,
                      plots=False, resume=True)
    assert again.computed == 0 and again.resumed == 2
    assert (tmp_path / "sweep.csv").read_text() == text
    assert again.rows == first.rows
