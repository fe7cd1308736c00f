"""Throughput of sweeps: one process, two local processes, a 2-worker Dask LocalCluster.

Two sweeps of the paper's option-3 case in the exact model, each run three ways in
one run of this script (``sso.sweep`` end to end, its rows in memory):

* **optimise**: the start of all three operating angles on a grid in [10, 40] deg
  (47^3 = 103,823 points by default), ``"lm"`` alone, one start per point;
* **evaluate**: the same angles on a 100^3 grid (1,000,000 points), evaluated.

Each runs in one process (``workers=1``), on the local pool of 2 processes, and on
a Dask ``LocalCluster`` of 2 single-threaded worker processes (started before the
timed run; its start-up is reported apart). The script prints points per second
and the ratio to one process, and checks that the three runs give the same rows
(every column but the wall times).

Then, against the strongest per-point baseline: the first ``--sample`` points of
the optimise sweep solved one by one by ``sso.optimise(..., solvers=("lm",))``
(``run_point``: read the point as a case, solve, evaluate, fill its row), with the
ratio of rates and the check that both give the same RE (within 1e-12) and success
flag at every sampled point.

Last, the constant rate of appending (``--constant-rate``): the evaluate sweep in
one process with ``out_dir``, ``sweep.csv`` watched while it grows; the rate of the
first 10% of the points against the last 10%.

Usage::

    python -m benchmarks.sweep_throughput [--optimise-per-axis 47]
        [--evaluate-per-axis 100] [--sample 2000] [--json] [--constant-rate]
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

from sso.batch.execution import WORKER_ENVIRONMENT

# The one-process run uses one BLAS thread like the pool's and Dask's workers (set
# before numpy loads its BLAS), so all runs compute the same bits at equal footing.
for _name, _value in WORKER_ENVIRONMENT.items():
    os.environ.setdefault(_name, _value)

CASE = Path(__file__).resolve().parent.parent / "cases" / "paper_option3_exact.toml"
WORKERS = 2


def base_document() -> dict[str, Any]:
    """The paper's option 3, exact model, "lm" alone from one start."""
    from sso.batch.axes import base_case

    document = base_case(CASE).to_dict()
    document["solver"].update({"solvers": ["lm"], "starts": 1})
    return document


def grid(per_axis: int) -> dict[str, Any]:
    """All three operating angles on ``per_axis`` values in [10, 40] deg."""
    return {f"design.beta_deg[{joint}]": {"start": 10.0, "stop": 40.0, "num": per_axis}
            for joint in range(3)}


def comparable(result: Any) -> dict[str, Any]:
    """The rows' columns without the wall times."""
    from sso.batch.table import TIME_COLUMNS

    table = result.rows.table
    return {name: column for name, column in table.columns.items()
            if name not in TIME_COLUMNS}


def same_rows(left: dict[str, Any], right: dict[str, Any]) -> bool:
    """Whether two runs' columns hold the same cells (NaN: an empty cell in both)."""
    import numpy as np

    if left.keys() != right.keys():
        return False
    return all(np.array_equal(left[name], right[name], equal_nan=left[name].dtype.kind == "f")
               if left[name].dtype != object else bool(np.all(left[name] == right[name]))
               for name in left)


def timed(action: str, axes: dict[str, Any], **options: Any) -> tuple[dict[str, Any], Any]:
    import sso

    started = time.perf_counter()
    result = sso.sweep(base_document(), axes, action=action, progress=False, **options)
    wall_s = time.perf_counter() - started
    return {"points": len(result.rows), "wall_s": wall_s,
            "points_per_s": len(result.rows) / wall_s}, result


def three_ways(action: str, axes: dict[str, Any], client: Any) -> dict[str, Any]:
    """One process, the pool of 2, Dask with 2 workers: rates, ratios, same rows."""
    runs: dict[str, dict[str, Any]] = {}
    rows: dict[str, Any] = {}
    for label, options in (("one process", {"workers": 1}),
                           (f"{WORKERS} local processes", {"workers": WORKERS}),
                           (f"Dask LocalCluster, {WORKERS} workers", {"client": client})):
        runs[label], result = timed(action, axes, **options)
        rows[label] = comparable(result)
        del result
    one = runs["one process"]["points_per_s"]
    for run in runs.values():
        run["ratio_to_one_process"] = run["points_per_s"] / one
    reference = rows["one process"]
    return {"runs": runs,
            "identical_rows": all(same_rows(value, reference) for value in rows.values())}


def against_point_by_point(sample: int, per_axis: int) -> dict[str, Any]:
    """The engine's rows against each point solved alone by sso.optimise (run_point)."""
    import warnings

    import sso
    from sso.batch.worker import run_point

    axes = grid(per_axis)
    document = base_document()
    started = time.perf_counter()
    result = sso.sweep(document, axes, workers=1, progress=False)
    engine_rate = len(result.rows) / (time.perf_counter() - started)
    rows = result.rows[:sample]
    started = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        slow = [run_point(row["point"], document, {path: row[path] for path in axes},
                          "optimise") for row in rows]
    baseline_rate = len(slow) / (time.perf_counter() - started)
    agree = all(abs(fast["residual_error"] - alone["residual_error"]) <= 1e-12
                and fast["success"] is alone["success"] for fast, alone in zip(rows, slow,
                                                                                strict=True))
    return {"sample": len(rows), "engine_points_per_s": engine_rate,
            "point_by_point_points_per_s": baseline_rate,
            "ratio": engine_rate / baseline_rate, "same_re_and_success": agree}


def constant_rate(per_axis: int) -> dict[str, Any]:
    """Rate of the first and the last 10% of an evaluate sweep appended to sweep.csv."""
    import sso

    samples: list[tuple[float, int]] = []
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "constant" / "sweep.csv"
        done = threading.Event()

        def watch() -> None:
            lines, offset = 0, 0
            while not done.is_set():
                if path.exists():
                    with open(path, "rb") as handle:
                        handle.seek(offset)
                        data = handle.read()
                    offset += len(data)
                    lines += data.count(b"\n")
                    samples.append((time.perf_counter(), max(lines - 1, 0)))
                time.sleep(0.02)

        watcher = threading.Thread(target=watch)
        watcher.start()
        started = time.perf_counter()
        try:
            result = sso.sweep(base_document(), grid(per_axis), action="evaluate", workers=1,
                               progress=False, plots=False, out_dir=Path(folder) / "constant")
        finally:
            done.set()
            watcher.join()
        wall_s = time.perf_counter() - started
    points = len(result.rows)

    def instant(count: float) -> float:
        return next(moment for moment, rows in samples if rows >= count)

    first_s = instant(0.1 * points) - started
    last_s = instant(points) - instant(0.9 * points)
    return {"points": points, "wall_s": wall_s, "first_10_percent_s": first_s,
            "last_10_percent_s": last_s, "last_over_first": last_s / first_s}


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """Run the benchmark, print a table, return the figures."""
    from distributed import Client, LocalCluster

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--optimise-per-axis", type=int, default=47,
                        help="grid values per angle of the optimise sweep (47: 103,823 points)")
    parser.add_argument("--evaluate-per-axis", type=int, default=100,
                        help="grid values per angle of the evaluate sweep (100: 1,000,000)")
    parser.add_argument("--sample", type=int, default=2000,
                        help="points solved one by one for the baseline (default 2000)")
    parser.add_argument("--constant-rate", action="store_true",
                        help="also time the first and last 10%% of an evaluate sweep on disk")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON too")
    args = parser.parse_args(argv)

    figures: dict[str, Any] = {}
    cluster_started = time.perf_counter()
    with LocalCluster(n_workers=WORKERS, threads_per_worker=1, processes=True,
                      host="127.0.0.1", dashboard_address=":0") as cluster, \
            Client(cluster) as client:
        client.wait_for_workers(WORKERS)
        figures["dask_cluster_start_s"] = time.perf_counter() - cluster_started
        figures["optimise"] = three_ways("optimise", grid(args.optimise_per_axis), client)
        figures["evaluate"] = three_ways("evaluate", grid(args.evaluate_per_axis), client)
    figures["point_by_point"] = against_point_by_point(args.sample, args.optimise_per_axis)
    if args.constant_rate:
        figures["constant_rate"] = constant_rate(args.evaluate_per_axis)

    for action in ("optimise", "evaluate"):
        runs = figures[action]["runs"]
        points = next(iter(runs.values()))["points"]
        print(f"\n{action} sweep, option 3 exact, {points:,} points"
              + (' ("lm", one start)' if action == "optimise" else ""))
        print(f"{'run':<34}{'wall s':>9}{'points/s':>12}{'x one process':>15}")
        for label, run in runs.items():
            print(f"{label:<34}{run['wall_s']:>9.2f}{run['points_per_s']:>12,.0f}"
                  f"{run['ratio_to_one_process']:>15.2f}")
        print(f"identical rows in the three runs: {figures[action]['identical_rows']}")
    print(f"Dask cluster start: {figures['dask_cluster_start_s']:.1f} s (not counted)")
    baseline = figures["point_by_point"]
    print(f"\nengine {baseline['engine_points_per_s']:,.0f} points/s against point by point "
          f"{baseline['point_by_point_points_per_s']:,.0f} points/s ({baseline['sample']} "
          f"points): {baseline['ratio']:.1f}x; same RE (1e-12) and success: "
          f"{baseline['same_re_and_success']}")
    if args.constant_rate:
        rate = figures["constant_rate"]
        print(f"\nconstant rate, {rate['points']:,}-point evaluate sweep to sweep.csv: first "
              f"10% {rate['first_10_percent_s']:.2f} s, last 10% "
              f"{rate['last_10_percent_s']:.2f} s (last / first "
              f"{rate['last_over_first']:.2f}), wall {rate['wall_s']:.1f} s")
    if args.json:
        print(json.dumps(figures, indent=2))
    if not (figures["optimise"]["identical_rows"] and figures["evaluate"]["identical_rows"]
            and baseline["same_re_and_success"]):
        raise SystemExit("the runs gave different rows")
    return figures


if __name__ == "__main__":
    main()
