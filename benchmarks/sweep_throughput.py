"""Throughput of a 1000-point option-3 sweep: one process, the local pool, and Dask.

Runs the same sweep (the paper's option-3 case in the exact model, the start of
all three operating angles on a 10 x 10 x 10 grid in [10, 40] deg, one start per
solver, IPOPT and SLSQP cross-checked) several ways in one run:

* one process (``workers=1``);
* the local process pool on every core (the default; its processes start, import
  CasADi and build the NLP inside the timed run, as they do in every sweep);
* a Dask ``LocalCluster`` on loopback, one single-threaded worker process per
  core: the first sweep on fresh workers ("cold") and a second one ("warm", a
  cluster that is already running and has built its NLP); cluster start-up is
  timed apart;
* the pool and warm Dask again with one point per task.

For each it reports points per second, the ratio to one process, and the
overhead per point: ``(wall time * workers - sum of the points' own times) /
points``, the time a worker spends on anything but computing a point (process
start, imports, NLP build, scheduling, transfer). Every run must give the same rows.

Usage::

    python -m benchmarks.sweep_throughput [--points-per-axis 10] [--starts 1] [--json]
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path
from typing import Any

from sso.batch.execution import WORKER_ENVIRONMENT

# The one-process run uses one BLAS thread like the pool's and Dask's workers (set
# before numpy loads its BLAS), so all runs compute the same bits at equal footing.
for _name, _value in WORKER_ENVIRONMENT.items():
    os.environ.setdefault(_name, _value)

CASE = Path(__file__).resolve().parent.parent / "cases" / "paper_option3_exact.toml"


def timed_sweep(base: dict[str, Any], axes: dict[str, Any], parallel: int,
                **options: Any) -> dict[str, Any]:
    """Wall time, throughput and overhead per point of one sweep, and its rows."""
    import sso

    started = time.perf_counter()
    result = sso.sweep(base, axes, progress=False, **options)
    wall_s = time.perf_counter() - started
    points = len(result.rows)
    busy_s = sum(row["time_s"] for row in result.rows)
    return {"wall_s": wall_s, "points_per_s": points / wall_s,
            "overhead_per_point_ms": 1e3 * (wall_s * parallel - busy_s) / points,
            "rows": comparable(result)}


def comparable(result: Any) -> list[dict[str, Any]]:
    """Rows without their wall-time columns."""
    from sso.batch.table import TIME_COLUMNS

    return [{key: value for key, value in row.items() if key not in TIME_COLUMNS}
            for row in result.rows]


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """Run the benchmark, print a table, return the figures."""
    from distributed import Client, LocalCluster

    from sso.batch.axes import base_case
    from sso.batch.execution import available_cores

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--points-per-axis", type=int, default=10,
                        help="grid values per operating angle (default 10: 1000 points)")
    parser.add_argument("--starts", type=int, default=1, help="starts per solver (default 1)")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON too")
    args = parser.parse_args(argv)

    base = base_case(CASE).to_dict()
    base["solver"]["starts"] = args.starts
    grid = {"start": 10.0, "stop": 40.0, "num": args.points_per_axis}
    axes = {f"design.beta_deg[{joint}]": grid for joint in range(3)}
    points = args.points_per_axis ** 3
    cores = available_cores()

    runs = {"one process": timed_sweep(base, axes, 1, workers=1),
            "local pool": timed_sweep(base, axes, cores)}
    cluster_started = time.perf_counter()
    with LocalCluster(n_workers=cores, threads_per_worker=1, processes=True,
                      host="127.0.0.1", dashboard_address=":0") as cluster, \
            Client(cluster) as client:
        client.wait_for_workers(cores)
        cluster_s = time.perf_counter() - cluster_started
        runs["Dask, cold workers"] = timed_sweep(base, axes, cores, client=client)
        runs["Dask, warm workers"] = timed_sweep(base, axes, cores, client=client)
        runs["Dask warm, 1 point per task"] = timed_sweep(base, axes, cores, client=client,
                                                          chunk_size=1)
    runs["local pool, 1 point per task"] = timed_sweep(base, axes, cores, chunk_size=1)
    reference = runs["one process"]["rows"]
    identical = all(run.pop("rows") == reference for run in runs.values())
    one_s = runs["one process"]["wall_s"]
    for run in runs.values():
        run["ratio_to_one_process"] = one_s / run["wall_s"]
    pool = runs["local pool"]
    figures = {
        "points": points, "cores": cores, "starts_per_solver": args.starts, "runs": runs,
        "dask_cluster_start_s": cluster_s,
        "dask_minus_pool_overhead_per_point_ms": {
            "cold": (runs["Dask, cold workers"]["overhead_per_point_ms"]
                     - pool["overhead_per_point_ms"]),
            "warm": (runs["Dask, warm workers"]["overhead_per_point_ms"]
                     - pool["overhead_per_point_ms"]),
            "1 point per task": (runs["Dask warm, 1 point per task"]["overhead_per_point_ms"]
                                 - runs["local pool, 1 point per task"]["overhead_per_point_ms"]),
        },
        "identical_rows": identical,
    }
    print(f"{points}-point option-3 sweep, {cores} cores, {args.starts} start(s) per solver")
    print(f"{'run':<32}{'wall s':>8}{'points/s':>10}{'x one process':>15}{'overhead ms/pt':>16}")
    for label, run in runs.items():
        print(f"{label:<32}{run['wall_s']:>8.2f}{run['points_per_s']:>10.1f}"
              f"{run['ratio_to_one_process']:>15.2f}{run['overhead_per_point_ms']:>16.2f}")
    extra = figures["dask_minus_pool_overhead_per_point_ms"]
    print("Dask overhead per point minus the local pool's: "
          + ", ".join(f"{label} {value:+.2f} ms" for label, value in extra.items())
          + f"; cluster start {cluster_s:.1f} s (not counted)")
    print(f"rows identical in every run: {identical}")
    if args.json:
        print(json.dumps(figures, indent=2))
    if not identical:
        raise SystemExit("the runs gave different rows")
    return figures


if __name__ == "__main__":
    main()
