"""A signalled ``sso sweep`` with 2 workers leaves no process and no temporary file.

Real processes: ``python -m sso._cli sweep`` runs in a subprocess; once it has written
its first chunk, it gets SIGINT, SIGTERM or SIGKILL. Then no process it started may
remain (its pool workers and multiprocessing's resource tracker, found as its
children in /proc), no ``.sso-tmp-*`` file may remain, and ``--resume`` then
completes the sweep. How fast the sweep and its workers are gone is measured in
``benchmarks/interrupts.py --workers 2`` (the target: 5 s); here the limit is only
generous enough to tell a sweep that stops from one that hangs.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from processes import alive, children

from sso._files import TEMPORARY_PREFIX, nameless_temporaries
from sso._studies.table import read_rows

pytestmark = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc")

SWEEP = """\
name = "shutdown"
action = "optimise"
chunk_size = 1

[case]
[case.design]
beta_deg = [30.0, 40.0, 40.0]
phase_deg = [90.0, 90.0]
[case.bounds]
beta_deg = [10.0, 40.0]
[case.solver]
starts = 4

[axes]
"design.beta_deg[0]" = { start = 10.0, stop = 40.0, num = 6 }
"design.beta_deg[1]" = { start = 10.0, stop = 40.0, num = 5 }
"""
POINTS = 30
GONE_WITHIN_S = 60.0
START_DEADLINE_S = 120.0


def start_sweep(folder: Path, log_name: str, *extra: str) -> subprocess.Popen[bytes]:
    """``sso sweep`` in a subprocess; its output goes to a file (a pipe would keep a
    leftover worker's reader waiting)."""
    environment = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[2])}
    with open(folder / log_name, "wb") as log:
        return subprocess.Popen([sys.executable, "-m", "sso._cli", "sweep",
                                 str(folder / "sweep.toml"), "--workers", "2", "--no-plots",
                                 "--quiet", "--out", str(folder / "out"), *extra],
                                env=environment, stdout=log, stderr=subprocess.STDOUT)


@pytest.mark.parametrize("signal_number", [signal.SIGKILL, signal.SIGTERM, signal.SIGINT])
def test_a_signalled_sweep_leaves_nothing_behind_and_resumes(tmp_path, signal_number):
    (tmp_path / "sweep.toml").write_text(SWEEP)
    csv_path = tmp_path / "out" / "shutdown" / "sweep.csv"
    process = start_sweep(tmp_path, "run.log")
    started = set()
    deadline = time.monotonic() + START_DEADLINE_S
    try:
        while not (csv_path.exists() and read_rows(csv_path) and len(started) >= 2):
            assert process.poll() is None, (tmp_path / "run.log").read_text()
            assert time.monotonic() < deadline, "the sweep wrote no chunk in time"
            started |= children(process.pid)
            time.sleep(0.01)
        started |= children(process.pid)
        os.kill(process.pid, signal_number)
        deadline = time.monotonic() + GONE_WITHIN_S
        while process.poll() is None and time.monotonic() < deadline:
            time.sleep(0.01)
        exit_code = process.poll()
        while any(alive(pid) for pid in started) and time.monotonic() < deadline:
            time.sleep(0.01)
        left = [pid for pid in started if alive(pid)]
    finally:
        for pid in [process.pid, *started]:  # whatever the outcome, leave nothing running
            if alive(pid):
                os.kill(pid, signal.SIGKILL)
        process.wait()
    assert exit_code is not None, f"the sweep did not stop within {GONE_WITHIN_S} s"
    assert left == []
    leftovers = sorted(tmp_path.rglob(f"{TEMPORARY_PREFIX}*"))
    if signal_number == signal.SIGKILL and not nameless_temporaries(tmp_path):
        # Where the system refuses nameless temporary files (sso._files.nameless_temporaries)
        # a kill can land between naming and renaming one: at most that one file, removed
        # by the resumed sweep below.
        assert len(leftovers) <= 1
    else:
        assert leftovers == []
    assert "Traceback" not in (tmp_path / "run.log").read_text()
    if signal_number != signal.SIGKILL:
        assert exit_code == 130  # the CLI's "interrupted"
    done_before = len(read_rows(csv_path))
    assert 1 <= done_before < POINTS, "the run was not interrupted mid-way"
    if signal_number == signal.SIGKILL:  # the hardest case: resume it to the end
        resumed = start_sweep(tmp_path, "resume.log", "--resume")
        assert resumed.wait(timeout=300) == 0, (tmp_path / "resume.log").read_text()
        rows = read_rows(csv_path)
        assert sorted(int(row["point"]) for row in rows) == list(range(POINTS))
        assert all(row["status"] == "ok" for row in rows)
        assert sorted(tmp_path.rglob(f"{TEMPORARY_PREFIX}*")) == []
