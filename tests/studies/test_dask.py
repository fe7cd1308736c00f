"""The same work on a real Dask cluster (loopback, two worker processes) as locally."""

import sys
from pathlib import Path

import numpy as np
import pytest

import sso
from sso._studies.table import TIME_COLUMNS, read_rows

distributed = pytest.importorskip("distributed")

# Option 3 from starts on a grid: some points end where SLSQP's last bits depend on
# the BLAS threading, so equal bits need equally configured workers.
BASE = {"design": {"beta_deg": [30.0, 40.0, 50.0], "phase_deg": [90.0, 90.0]},
        "bounds": {"beta_deg": [10.0, 40.0]}, "solver": {"starts": 1}}
AXES = {"design.beta_deg[0]": [10.0, 25.0, 40.0, 95.0], "design.beta_deg[1]": [10.0, 25.0, 40.0],
        "design.beta_deg[2]": [10.0, 25.0, 40.0]}


@pytest.fixture(scope="module")
def client():
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=":0") as cluster:
        with distributed.Client(cluster) as dask_client:
            yield dask_client


def _without_times(rows):
    return [{key: value for key, value in row.items() if key not in TIME_COLUMNS}
            for row in rows]


def test_a_sweep_on_dask_gives_the_local_pool_results_exactly(client, tmp_path):
    local = sso.sweep(BASE, AXES, out_dir=tmp_path / "local", workers=2, chunk_size=4,
                      plots=False)
    on_dask = sso.sweep(BASE, AXES, out_dir=tmp_path / "dask", client=client, chunk_size=4,
                        plots=False)
    assert len(on_dask.rows) == 36
    assert _without_times(on_dask.rows) == _without_times(local.rows)
    # The failing points (beta 95 deg) are recorded on the cluster as well.
    assert [row["status"] for row in on_dask.rows].count("failed") == 9
    assert all(row["residual_error"] < 1e-15 for row in on_dask.rows if row["status"] == "ok")



def test_a_batched_lm_sweep_on_dask_gives_the_local_pool_results_exactly(client):
    # "lm" alone: each chunk's points are solved together (sso.optimise_batch).
    base = {**BASE, "solver": {"starts": 2, "solvers": ["lm"]}}
    local = sso.sweep(base, AXES, workers=2, chunk_size=5, progress=False)
    on_dask = sso.sweep(base, AXES, client=client, chunk_size=5, progress=False)
    assert _without_times(on_dask.rows) == _without_times(local.rows)
    assert [row["status"] for row in on_dask.rows].count("failed") == 9
    assert all(row["best_solver"] == "lm" and row["residual_error"] < 1e-15
               for row in on_dask.rows if row["status"] == "ok")

def test_a_tolerance_study_on_dask_gives_the_local_numbers_exactly(client):
    series = sso.ShaftSeries([15.8362, 10.0, 15.8387], [90.0053, 89.9695])
    local = sso.tolerance_study(series, samples=600, seed=3, chunk_size=150, workers=2)
    on_dask = sso.tolerance_study(series, samples=600, seed=3, chunk_size=150, client=client)
    for metric in ("residual_error", "fluctuation", "max_output_accel_rad_s2"):
        np.testing.assert_array_equal(getattr(on_dask, metric), getattr(local, metric))


def test_sso_sweep_with_scheduler_runs_on_the_cluster(client, tmp_path):
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "cli"))
    from test_studies import SWEEP, sso_command

    (tmp_path / "map.toml").write_text(SWEEP)
    on_dask = sso_command("sweep", "map.toml", "--scheduler", client.scheduler.address,
                          "--no-plots", "--out", "dask", cwd=tmp_path)
    local = sso_command("sweep", "map.toml", "--workers", "1", "--no-plots", "--out", "local",
                        cwd=tmp_path)
    assert on_dask.returncode == 0 and local.returncode == 0, on_dask.stderr
    # sweep.csv holds the rows in the order their chunks finished.
    rows = [sorted(read_rows(tmp_path / folder / "map" / "sweep.csv"),
                   key=lambda row: int(row["point"])) for folder in ("dask", "local")]
    assert _without_times(rows[0]) == _without_times(rows[1])


def test_an_array_sweep_on_dask_gives_the_rows_of_one_process(client):
    # The array engine's chunks (sso._studies.array_engine) on two Dask workers: the same
    # rows as one process, every column but the wall times.
    # Each worker reads the axis values its chunks take (sso._studies.axis_checks), with
    # tasks of 17 points (each worker runs several) and in the automatic rounds.
    base = {**BASE, "option": 3, "solver": {"solvers": ["lm"], "starts": 2}}
    axes = {"design.beta_deg[0]": {"start": 10.0, "stop": 40.0, "num": 20},
            "design.beta_deg[1]": [10.0, 25.0, 40.0, 95.0, 45.0],
            "design.phase_deg[0]": [30.0, 90.0]}
    one = sso.sweep(base, axes, workers=1, progress=False)
    for chunk_size in (17, None):
        on_dask = sso.sweep(base, axes, client=client, chunk_size=chunk_size, progress=False)
        assert _without_times(on_dask.rows) == _without_times(one.rows)
    assert sum(row["status"] == "failed" for row in one.rows) == 40  # beta 95 deg refused
    moved = [row for row in one.rows if row["design.beta_deg[1]"] == 45.0]
    assert len(moved) == 40 and all("start beta_deg[1] = 45 deg lies outside its bounds"
                                    in row["warnings"] for row in moved)


def test_dask_workers_on_this_machine_write_the_numbers_in_place(client, tmp_path):
    # The cluster's workers run here: they write into the calling process's memory file
    # (sso._studies.shared_rows), and the rows and sweep.csv are those of one process.
    base = {**BASE, "option": 3, "solver": {"solvers": ["lm"], "starts": 1}}
    axes = {"design.beta_deg[0]": {"start": 10.0, "stop": 40.0, "num": 30},
            "design.beta_deg[2]": {"start": 10.0, "stop": 40.0, "num": 7}}
    one = sso.sweep(base, axes, workers=1, progress=False, out_dir=tmp_path / "one",
                    plots=False)
    on_dask = sso.sweep(base, axes, client=client, chunk_size=40, progress=False,
                        out_dir=tmp_path / "dask", plots=False)
    assert _without_times(on_dask.rows) == _without_times(one.rows)
    def written(folder):  # chunks are appended as they end: in point order here
        return sorted(_without_times(read_rows(tmp_path / folder / "sweep.csv")),
                      key=lambda row: int(row["point"]))

    assert written("dask") == written("one")
    if sys.platform.startswith("linux"):
        column = on_dask.rows.table.columns["residual_error"]
        while isinstance(column, (np.ndarray, memoryview)):
            column = column.base if isinstance(column, np.ndarray) else column.obj
        assert type(column).__name__ == "mmap"


def test_a_dask_worker_keeps_what_sweep_tasks_free(client):
    # Dask's nanny starts its workers with MALLOC_TRIM_THRESHOLD_=65536 (give memory
    # back early); a sweep's tasks set the allocator to keep it (sso._studies.worker_memory).
    from test_worker_memory import PAGES, faults_of_a_chunk_again

    from sso._studies.execution import run_tasks
    from sso._studies.worker_memory import glibc_allocator

    if not glibc_allocator():
        pytest.skip("the allocator set is glibc's")
    faults = [value for _, value, _ in run_tasks(faults_of_a_chunk_again, [0, 1, 2, 3],
                                                  client=client)]
    assert len(faults) == 4 and max(faults) < PAGES // 100
