"""A Dask sweep whose last worker dies stops, says what to do, and resumes to the end.

Real parts: a Dask scheduler on loopback, a worker in its own process (``dask worker``
with no nanny, so nothing restarts it) killed with SIGKILL while the sweep runs, and
``sso sweep --scheduler`` in a subprocess. The wait without workers is shortened
through ``SSO_NO_WORKER_TIMEOUT_S`` (its default is ``sso._limits.NO_WORKER_TIMEOUT_S``).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from sso._studies.table import read_rows

distributed = pytest.importorskip("distributed")

CASE = Path("cases/paper_option1_exact.toml").resolve()
# Cross-checked points, one per task: tens of ms each, so the sweep is mid-way when the
# worker is killed.
SWEEP = f"""
name = "gone"
case = "{CASE}"
chunk_size = 1
[axes]
"design.beta_deg[0]" = {{ start = 10, stop = 30, num = 60 }}
"""
TIMEOUT_S = 3.0


def start_worker(address):
    return subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address,
                             "--nthreads", "1", "--no-nanny", "--no-dashboard"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def test_a_sweep_without_workers_stops_with_exit_1_and_resumes(tmp_path):
    (tmp_path / "gone.toml").write_text(SWEEP)
    environment = {**os.environ, "SSO_NO_WORKER_TIMEOUT_S": str(TIMEOUT_S),
                   "PYTHONPATH": str(Path(__file__).resolve().parents[2])}
    command = [sys.executable, "-m", "sso._cli", "sweep", "gone.toml", "--no-plots", "--quiet"]
    with distributed.LocalCluster(n_workers=0, processes=True, host="127.0.0.1",
                                  dashboard_address=":0") as cluster:
        address = cluster.scheduler.address
        worker = start_worker(address)
        with distributed.Client(cluster) as client:
            client.wait_for_workers(1, timeout=60)
        sweep = subprocess.Popen([*command, "--scheduler", address], cwd=tmp_path,
                                 env=environment, stdout=subprocess.PIPE,
                                 stderr=subprocess.PIPE, text=True)
        csv_path = tmp_path / "results" / "gone" / "sweep.csv"
        deadline = time.monotonic() + 120
        try:
            while not (csv_path.exists() and len(read_rows(csv_path)) >= 3):
                assert sweep.poll() is None and time.monotonic() < deadline
                time.sleep(0.01)
            os.kill(worker.pid, signal.SIGKILL)
            worker.wait()
            killed = time.monotonic()
            output, errors = sweep.communicate(timeout=60)
            stopped_after_s = time.monotonic() - killed
        finally:
            for process in (worker, sweep):
                if process.poll() is None:
                    process.kill()
                    process.wait()
        assert sweep.returncode == 1, errors
        assert TIMEOUT_S <= stopped_after_s <= TIMEOUT_S + 10
        assert f"has had no worker for {TIMEOUT_S:g} s" in errors
        assert "start workers for it (dask worker ADDRESS) and run the same command with " \
               "--resume" in errors
        assert "Traceback" not in errors
        done_before = len(read_rows(csv_path))
        assert 3 <= done_before < 60

        worker = start_worker(address)
        try:
            resumed = subprocess.run([*command, "--scheduler", address, "--resume"],
                                     cwd=tmp_path, env=environment, capture_output=True,
                                     text=True, timeout=300)
        finally:
            worker.kill()
            worker.wait()
    rows = read_rows(csv_path)
    ok = sorted(int(row["point"]) for row in rows if row["status"] == "ok")
    assert ok == list(range(60))
    # Every point computed; the exit code is then the sweep's verdict on its points: 1 when
    # a point's solvers disagree or did not converge (one of these 60 does: its IPOPT stops
    # at an acceptable level that SLSQP improves on), as in a sweep never interrupted.
    disagreeing = [row for row in rows if row["success"] != "true"]
    assert resumed.returncode == (1 if disagreeing else 0), resumed.stderr
    assert "Traceback" not in resumed.stderr
