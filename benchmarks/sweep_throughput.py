"""Throughput of a 1000-point option-3 sweep: one process, the local pool, Dask, and "lm".

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

Then the same sweep with the least-squares solver alone (``solvers = ["lm"]``), in
one process, three ways on the same chunks (the sweep's own chunking for one
worker), interleaved and repeated (median):

* batched: each chunk's points solved together (``run_sweep_chunk``: one
  ``sso.optimise_batch`` call per chunk, then each point's row);
* point by point: the same points, each solved by ``sso.optimise(...,
  solvers=("lm",))`` and given its row (``run_point``, the path every other solver
  list takes): the strongest per-point baseline;
* the ``sso.optimise`` calls alone, on cases read beforehand, with no row (the
  solver's share of the point-by-point path).

It prints points per second and the ratio batched / point by point, checks that the
two give the same RE (1e-12) and success flag at every point, and times the parts
of a batched point (reading its case, the batch call, evaluating the optimum).

Usage::

    python -m benchmarks.sweep_throughput [--points-per-axis 10] [--starts 1] [--json]
    python -m benchmarks.sweep_throughput --lm-only      # the "lm" part alone
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time
import warnings
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


LM_REPEATS = 3


def lm_sweep(base: dict[str, Any], axes: dict[str, Any], repeats: int = LM_REPEATS
             ) -> dict[str, Any]:
    """Points per second of an "lm" sweep, batched against point by point (one process)."""
    import sso
    from sso.batch.axes import expand_points, parse_axes, point_document
    from sso.batch.sweep import _chunk_size
    from sso.batch.worker import SweepChunk, run_point, run_sweep_chunk
    from sso.cases.schema import parse_case

    document = dict(base, solver={**base["solver"], "solvers": ["lm"]})
    points = list(enumerate(expand_points(parse_axes(axes, document), "product")))
    size = _chunk_size(None, len(points), 1)
    chunks = [SweepChunk(document, "optimise", tuple(points[start:start + size]))
              for start in range(0, len(points), size)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cases = [parse_case(point_document(document, point), "point") for _, point in points]

    def batched() -> list[dict[str, Any]]:
        return [row for chunk in chunks for row in run_sweep_chunk(chunk)]

    def point_by_point() -> list[dict[str, Any]]:
        return [run_point(index, chunk.document, point, chunk.action)
                for chunk in chunks for index, point in chunk.points]

    def optimise_alone() -> list[Any]:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return [sso.optimise(case.series(), case.option, **case.optimise_options())
                    for case in cases]

    methods = {"batched": batched, "point by point": point_by_point,
               "sso.optimise calls alone": optimise_alone}
    for method in methods.values():  # warm-up: imports, the NLP build of the shape
        method() if method is not batched else run_sweep_chunk(chunks[0])
    times: dict[str, list[float]] = {label: [] for label in methods}
    outputs: dict[str, Any] = {}
    for _ in range(repeats):
        for label, method in methods.items():
            started = time.perf_counter()
            outputs[label] = method()
            times[label].append(time.perf_counter() - started)
    fast, slow = outputs["batched"], outputs["point by point"]
    agree = all(a["status"] == b["status"] == "ok" and a["success"] is b["success"]
                and abs(a["residual_error"] - b["residual_error"]) <= 1e-12
                for a, b in zip(fast, slow, strict=True))
    runs = {label: {"wall_s": statistics.median(seconds),
                    "points_per_s": len(points) / statistics.median(seconds)}
            for label, seconds in times.items()}
    return {"points": len(points), "chunk_size": size, "repeats": repeats, "runs": runs,
            "ratio_batched_to_point_by_point": (runs["batched"]["points_per_s"]
                                                / runs["point by point"]["points_per_s"]),
            "parts_of_a_batched_point_ms": batched_parts(chunks, cases),
            "rows_agree": agree}


def batched_parts(chunks: list[Any], cases: list[Any]) -> dict[str, float]:
    """Milliseconds per point of each part of the batched path, timed apart."""
    from sso.batch.axes import point_document
    from sso.batch.batched import BatchedPoints
    from sso.batch.point_row import PointRow
    from sso.cases.schema import parse_case

    points = [(chunk.document, point) for chunk in chunks for _, point in chunk.points]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        started = time.perf_counter()
        for document, point in points:
            parse_case(point_document(document, point), "point")
        reading_s = time.perf_counter() - started
        laying_out_s = solving_s = evaluating_s = 0.0
        position = 0
        for chunk in chunks:
            group = BatchedPoints(lambda case: {})
            rows = [PointRow({}) for _ in chunk.points]
            started = time.perf_counter()
            for row, case in zip(rows, cases[position:position + len(rows)], strict=True):
                group.add(row, case)
            laying_out_s += time.perf_counter() - started
            position += len(rows)
            started = time.perf_counter()
            group.solve()
            total_s = time.perf_counter() - started
            solved_s = sum(row.cells["lm_time_s"] for row in rows)
            solving_s += solved_s
            evaluating_s += total_s - solved_s
    count = len(points)
    return {"read the case": 1e3 * reading_s / count,
            "lay out its starts": 1e3 * laying_out_s / count,
            "optimise_batch (its share)": 1e3 * solving_s / count,
            "evaluate the optimum, fill the row": 1e3 * evaluating_s / count}


def print_lm(figures: dict[str, Any], starts: int) -> None:
    print(f"\n{figures['points']}-point option-3 sweep with \"lm\" alone, one process, "
          f"{starts} start(s), chunks of {figures['chunk_size']} points, median of "
          f"{figures['repeats']}")
    print(f"{'run':<32}{'wall s':>8}{'points/s':>10}")
    for label, run in figures["runs"].items():
        print(f"{label:<32}{run['wall_s']:>8.2f}{run['points_per_s']:>10.1f}")
    print(f"batched / point by point: {figures['ratio_batched_to_point_by_point']:.2f}x; "
          f"same RE (1e-12) and success at every point: {figures['rows_agree']}")
    print("a batched point, ms: " + ", ".join(
        f"{label} {value:.3f}" for label, value in figures["parts_of_a_batched_point_ms"].items()))


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
    parser.add_argument("--lm-only", action="store_true",
                        help='measure only the "lm" sweep, batched against point by point')
    args = parser.parse_args(argv)

    base = base_case(CASE).to_dict()
    base["solver"]["starts"] = args.starts
    grid = {"start": 10.0, "stop": 40.0, "num": args.points_per_axis}
    axes = {f"design.beta_deg[{joint}]": grid for joint in range(3)}
    points = args.points_per_axis ** 3
    cores = available_cores()
    lm_figures = lm_sweep(base, axes)
    print_lm(lm_figures, args.starts)
    if args.lm_only:
        if args.json:
            print(json.dumps(lm_figures, indent=2))
        if not lm_figures["rows_agree"]:
            raise SystemExit("the batched and the point-by-point rows differ")
        return {"lm": lm_figures}

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
        "lm": lm_figures,
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
    if not identical or not lm_figures["rows_agree"]:
        raise SystemExit("the runs gave different rows")
    return figures


if __name__ == "__main__":
    main()
