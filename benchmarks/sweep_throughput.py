"""Throughput of sweeps: one process, two local processes, a 2-worker Dask LocalCluster.

Two sweeps of the paper's option-3 case in the exact model (a shipped case), each
run three ways, in interleaved passes within one run of this script (``sso.sweep``
end to end, its rows in memory):

* **optimise**: the start of all three operating angles on a grid in [10, 40] deg
  (47^3 = 103,823 points by default), ``"lm"`` alone, one start per point;
* **evaluate**: the same angles on a 100^3 grid (1,000,000 points), evaluated.

Each runs in one process (``workers=1``), on the local pool of 2 processes, and on
a Dask ``LocalCluster`` of 2 single-threaded worker processes. The cluster is
started before the timed runs, and the local pool's fork server by a first small
pool sweep; both start-ups are reported apart. Every pass runs the six sweeps in
turn; the table gives each run's median rate over the passes and the ratio of
medians to one process, and the script checks that every run gives the rows of
the first one-process run (every column but the wall times). The machine's load
average and core count are recorded before and after: on a shared machine the
ratios of parallel runs fall while other work takes the cores.

Beside the wall times, each run records CPU times, which other work on the machine
inflates far less: the calling process's (``time.process_time``) and that of every
process below it (the fork server and pool workers, or Dask's nannies and workers;
Linux ``/proc``). The summary gives both per point, the calling process's against
one process's (for 1.6x on 2 cores the calling process must take a small fraction
of the work) and the ratio the CPU times allow on 2 idle cores
(:func:`cpu_bound_ratio`).

What a task costs (:func:`task_cost`): the optimise sweep on the local pool and on
Dask, cut into tasks of 50,000 points and then of 5,000, in interleaved passes; the
CPU time of the calling process and of the workers beyond the points' work, per
task (the difference of the two cuts' CPU times over the difference of their tasks).

The ceiling (skip with ``--no-ceiling``): the same per-chunk compute with no sso
engine around it (no pool, no Dask, no shared rows, no assembly): each sweep's
points cut into chunks of ``ARRAY_CHUNK_CAP`` points and computed
(``run_sweep_chunk``, what a worker runs) by one process alone, then by two
independent processes at once, each computing every chunk, in each pass just
before the action's sweeps (:class:`Ceiling`). Its ratio (two processes' points a
second over one's) is what this machine gives two processes of this work at that
moment, whatever the engine does (on a machine shared with other work, the cores
are shared between sessions first: two processes of one session get little more
than one); its CPU per point, two at once over one alone, is what running beside
each other costs them (caches, memory bandwidth). The summary gives the engine's
ratios over it.

Then, against the strongest per-point baseline: the first ``--sample`` points of
the optimise sweep solved one by one by ``sso.optimise(..., solvers=("lm",))``
(``run_point``: read the point as a case, solve, evaluate, fill its row), with the
ratio of rates and the check that both give the same RE (within 1e-12) and success
flag at every sampled point.

Last, the sweep on disk (skip with ``--no-disk``): the 1,000,000-point evaluate
sweep in one process with ``out_dir`` (``sweep.csv`` watched while it grows, from
the moment the sweep writes its header): the time of the first 10% of the points
against the last 10% (target: last / first at most 1.2), the time of the
end-of-sweep report after the last row, and the bytes a point takes in
``sweep.csv`` and, from a 100,000-point evaluate sweep with ``parquet=True``, in
``sweep.parquet``.

Usage::

    python -m benchmarks.sweep_throughput [--optimise-per-axis 47]
        [--evaluate-per-axis 100] [--passes 7] [--sample 500] [--no-disk]
        [--no-ceiling] [--json PATH]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import tempfile
import threading
import time
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from sso._studies.execution import WORKER_ENVIRONMENT

# The one-process run uses one BLAS thread like the pool's and Dask's workers (set
# before numpy loads its BLAS), so all runs compute the same bits at equal footing.
for _name, _value in WORKER_ENVIRONMENT.items():
    os.environ.setdefault(_name, _value)

CASE = Path(__file__).resolve().parent.parent / "cases" / "paper_option3_exact.toml"
WORKERS = 2
CONSTANT_RATE_TOLERANCE = 1.2
"""The last 10% of an evaluate sweep's points may take at most this times the first 10%."""
PARQUET_PER_AXIS = 47
OPTIMISE_PER_AXIS = 47
"""Grid values per angle of the optimise sweep: 47^3 = 103,823 points."""
EVALUATE_PER_AXIS = 100
"""Grid values per angle of the evaluate sweep: 100^3 = 1,000,000 points."""
IDLE_WINDOW_S = 3.0
"""How long the CPU the processes use idle is measured, s."""


def base_document() -> dict[str, Any]:
    """The paper's option 3, exact model, "lm" alone from one start."""
    from sso._studies.axes import base_case

    document = base_case(CASE).to_dict()
    document["solver"].update({"solvers": ["lm"], "starts": 1})
    return document


def grid(per_axis: int) -> dict[str, Any]:
    """All three operating angles on ``per_axis`` values in [10, 40] deg."""
    return {f"design.beta_deg[{joint}]": {"start": 10.0, "stop": 40.0, "num": per_axis}
            for joint in range(3)}


def comparable(result: Any) -> dict[str, Any]:
    """The rows' columns without the wall times."""
    from sso._studies.table import TIME_COLUMNS

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
    """One sweep in memory: its wall time and rate, the calling process's CPU time and
    that of the processes it started (the pool's or the cluster's workers)."""
    import sso

    started = time.perf_counter()
    cpu_started = time.process_time()
    others_started = descendants_cpu_s()
    result = sso.sweep(base_document(), axes, action=action, progress=False, **options)
    wall_s = time.perf_counter() - started
    return {"points": len(result.rows), "wall_s": wall_s,
            "points_per_s": len(result.rows) / wall_s,
            "calling_process_cpu_s": time.process_time() - cpu_started,
            "workers_cpu_s": descendants_cpu_s() - others_started}, result


def descendants_cpu_s() -> float:
    """CPU time (user and system) of every live process below this one, s (Linux /proc;
    NaN elsewhere): the fork server and the pool's workers, Dask's nannies and workers."""
    ticks = os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 100
    parents: dict[int, int] = {}
    cpu: dict[int, float] = {}
    try:
        entries = [entry for entry in Path("/proc").iterdir() if entry.name.isdigit()]
    except OSError:
        return math.nan
    for entry in entries:
        try:
            fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        parents[int(entry.name)] = int(fields[1])
        cpu[int(entry.name)] = (int(fields[11]) + int(fields[12])) / ticks
    below, frontier = set(), {os.getpid()}
    while frontier:
        frontier = {pid for pid, parent in parents.items() if parent in frontier} - below
        below |= frontier
    return sum(cpu[pid] for pid in below) if entries else math.nan


def load_now() -> dict[str, Any]:
    """The machine's load average (1, 5, 15 min) and its cores, now."""
    load = os.getloadavg() if hasattr(os, "getloadavg") else (math.nan,) * 3
    autogroup = Path("/proc/sys/kernel/sched_autogroup_enabled")
    return {"load_average_1_5_15_min": [round(value, 2) for value in load],
            "cpu_count": os.cpu_count(),
            # 1: the kernel shares the cores between sessions first, so while other
            # sessions keep them busy, a session's second process gains it little.
            "sched_autogroup": (autogroup.read_text().strip() if autogroup.exists()
                                else "n/a")}


def modes(client: Any) -> dict[str, dict[str, Any]]:
    """The three ways a sweep runs, by label."""
    return {"one process": {"workers": 1},
            f"{WORKERS} local processes": {"workers": WORKERS},
            f"Dask LocalCluster, {WORKERS} workers": {"client": client}}


def idle_cpu_per_s(seconds: float = IDLE_WINDOW_S) -> dict[str, float]:
    """CPU seconds per second that the calling process and the processes below it
    use while no sweep runs (the Dask client's and cluster's heartbeats and event
    loops): subtracted from each run's CPU times in proportion to its wall time."""
    wall_started, cpu_started = time.perf_counter(), time.process_time()
    others_started = descendants_cpu_s()
    time.sleep(seconds)
    wall_s = time.perf_counter() - wall_started
    return {"calling_process": (time.process_time() - cpu_started) / wall_s,
            "workers": (descendants_cpu_s() - others_started) / wall_s}


def busy_cpu_s(run: dict[str, Any], idle: dict[str, float]) -> tuple[float, float]:
    """A run's CPU times of the calling process and of the workers, per point, less
    what they use idle over the run's wall time."""
    return ((run["calling_process_cpu_s"] - idle["calling_process"] * run["wall_s"])
            / run["points"],
            (run["workers_cpu_s"] - idle["workers"] * run["wall_s"]) / run["points"])


def interleaved(actions: dict[str, dict[str, Any]], client: Any,
                passes: int, ceiling: Ceiling | None = None) -> dict[str, Any]:
    """Every action run every way in each pass (and, given a :class:`Ceiling`, its
    chunks computed alone and by two processes, in the same pass); medians, ratios,
    same rows."""
    samples: dict[str, dict[str, list[dict[str, Any]]]] = {
        action: {label: [] for label in modes(client)} for action in actions}
    reference: dict[str, Any] = {}
    identical = {action: True for action in actions}
    for _ in range(passes):
        for action, axes in actions.items():
            if ceiling is not None:
                ceiling.measure(action)
            for label, options in modes(client).items():
                run, result = timed(action, axes, **options)
                run["load_average_1min"] = round(os.getloadavg()[0], 2)
                samples[action][label].append(run)
                rows = comparable(result)
                del result
                if action not in reference:
                    reference[action] = rows
                else:
                    identical[action] &= same_rows(rows, reference[action])
                del rows
    idle = idle_cpu_per_s()
    figures: dict[str, Any] = {"idle_cpu_per_s": idle}
    for action, runs in samples.items():
        one = statistics.median(run["points_per_s"] for run in runs["one process"])
        one_cpu = statistics.median(busy_cpu_s(run, idle)[0] for run in runs["one process"])
        table = {}
        for label, passes_of in runs.items():
            rate = statistics.median(run["points_per_s"] for run in passes_of)
            calling = statistics.median(busy_cpu_s(run, idle)[0] for run in passes_of)
            workers = statistics.median(busy_cpu_s(run, idle)[1] for run in passes_of)
            table[label] = {"points": passes_of[0]["points"],
                            "median_points_per_s": rate,
                            "ratio_to_one_process": rate / one,
                            "calling_process_cpu_us_per_point": 1e6 * calling,
                            "workers_cpu_us_per_point": 1e6 * workers,
                            "calling_process_cpu_over_one_process": calling / one_cpu,
                            "workers_cpu_over_one_process": workers / one_cpu,
                            "cpu_bound_ratio": cpu_bound_ratio(one_cpu, calling, workers),
                            "passes": passes_of}
        figures[action] = {"runs": table, "identical_rows": identical[action]}
    return figures


def cpu_bound_ratio(one_process_s: float, calling_s: float, workers_s: float) -> float:
    """The ratio to one process that the CPU times allow on WORKERS idle cores: the
    one-process CPU time per point over the larger of the calling process's and an
    even share of all the run's CPU time. Other work on the machine inflates CPU times
    far less than wall times, so this bound holds up under load; it ignores waiting
    (a worker idle while another finishes, the start of a run)."""
    if one_process_s <= 0 or not math.isfinite(workers_s):
        return math.nan
    busiest = max(calling_s, (calling_s + workers_s) / WORKERS)
    return one_process_s / busiest if busiest > 0 else math.nan


class Ceiling:
    """The same per-chunk compute in one process alone and in two independent
    processes at once (see the module), measured pass by pass (:meth:`measure`);
    :meth:`figures` gives per action the medians of the points a second (two
    processes: both runs' points over the longer wall time) and of the CPU time per
    point."""

    def __init__(self, per_axis: dict[str, int]) -> None:
        import multiprocessing

        context = multiprocessing.get_context("spawn")
        self.links = []
        for _ in range(WORKERS):
            mine, theirs = context.Pipe()
            process = context.Process(target=_chunk_computer, args=(theirs, per_axis),
                                      daemon=True)
            process.start()
            self.links.append((process, mine))
        for _, link in self.links:
            link.recv()  # ready: chunks built and one computed
        self.samples: dict[str, dict[str, list[dict[str, float]]]] = {
            action: {"alone": [], "together": []} for action in per_axis}

    def measure(self, action: str) -> None:
        """One pass of ``action``: its chunks computed alone, then by two at once."""
        for label, running in (("alone", self.links[:1]), ("together", self.links)):
            for _, link in running:
                link.send(action)
            runs = [link.recv() for _, link in running]
            self.samples[action][label].append({
                "points_per_s": sum(run["points"] for run in runs)
                / max(run["wall_s"] for run in runs),
                "cpu_us_per_point": 1e6 * sum(run["cpu_s"] for run in runs)
                / sum(run["points"] for run in runs),
                "load_average_1min": round(os.getloadavg()[0], 2)})

    def close(self) -> None:
        """End the processes."""
        for process, link in self.links:
            link.send(None)
            process.join(timeout=30)

    def figures(self) -> dict[str, Any]:
        """Per action: medians, the ratio, the CPU per point together over alone."""
        figures: dict[str, Any] = {}
        for action, runs in self.samples.items():
            if not runs["alone"]:
                continue
            alone = statistics.median(run["points_per_s"] for run in runs["alone"])
            together = statistics.median(run["points_per_s"] for run in runs["together"])
            alone_cpu = statistics.median(run["cpu_us_per_point"] for run in runs["alone"])
            together_cpu = statistics.median(run["cpu_us_per_point"]
                                             for run in runs["together"])
            figures[action] = {"alone_points_per_s": alone,
                               "together_points_per_s": together,
                               "ratio": together / alone, "alone_cpu_us_per_point": alone_cpu,
                               "together_cpu_us_per_point": together_cpu,
                               "cpu_together_over_alone": together_cpu / alone_cpu,
                               "passes": runs}
        return figures


def _chunk_computer(link: Any, per_axis: dict[str, int]) -> None:
    """A process of :func:`ceiling`: builds each sweep's chunks, then computes all of
    them each time it is sent the sweep's action (as a new sweep run: its chunks read
    their axis values, as the engine's do), and sends back its points, wall time and
    CPU time; ends when sent None. It keeps the memory it frees, as the engine's
    workers do."""
    import secrets
    from dataclasses import replace

    import numpy as np

    from sso._studies.array_engine import array_plan
    from sso._studies.axes import base_case, parse_axes, point_count
    from sso._studies.sweep import ARRAY_CHUNK_CAP, _Job
    from sso._studies.table import columns, manifest
    from sso._studies.worker import run_sweep_chunk
    from sso._studies.worker_memory import keep_freed_memory

    keep_freed_memory()
    chunks = {}
    for action, count in per_axis.items():
        case = base_case(base_document())
        document = case.to_dict()
        axes = parse_axes(grid(count), document)
        points = point_count(axes, "product")
        job = _Job(document, action, axes, "product", points,
                   columns([axis.path for axis in axes], case.kind),
                   manifest(document, axes, "product", action, points),
                   array_plan(case, axes, action), None, 1, ARRAY_CHUNK_CAP, False)
        chunks[action] = job.chunks(np.arange(points))
        run_sweep_chunk(chunks[action][0])
    link.send("ready")
    while (action := link.recv()) is not None:
        started, cpu_started = time.perf_counter(), time.process_time()
        plan = replace(chunks[action][0].plan, run=secrets.token_hex(8))
        points = sum(run_sweep_chunk(replace(chunk, plan=plan)).length
                     for chunk in chunks[action])
        link.send({"points": points, "wall_s": time.perf_counter() - started,
                   "cpu_s": time.process_time() - cpu_started})


TASK_COST_CHUNKS = (50_000, 5_000)
"""Points a task of the optimise sweep runs for :func:`task_cost`: few tasks, then many."""


def task_cost(client: Any, per_axis: int, passes: int,
              idle: dict[str, float]) -> dict[str, Any]:
    """CPU time a task costs the pool and Dask beyond its points' work: the optimise
    sweep cut into tasks of each of :data:`TASK_COST_CHUNKS` points, interleaved,
    the difference of the medians of the calling process's and the workers' CPU
    times (less what they use idle) over the difference of the tasks."""
    samples: dict[str, dict[int, list[tuple[float, float]]]] = {}
    tasks = {size: math.ceil(per_axis**3 / size) for size in TASK_COST_CHUNKS}
    for _ in range(passes):
        for label, options in list(modes(client).items())[1:]:
            for size in TASK_COST_CHUNKS:
                run, _ = timed("optimise", grid(per_axis), chunk_size=size, **options)
                samples.setdefault(label, {}).setdefault(size, []).append(
                    tuple(cpu * run["points"] for cpu in busy_cpu_s(run, idle)))
    few, many = TASK_COST_CHUNKS
    figures: dict[str, Any] = {"tasks": tasks}
    for label, runs in samples.items():
        cost = [(statistics.median(run[part] for run in runs[many])
                 - statistics.median(run[part] for run in runs[few]))
                / (tasks[many] - tasks[few]) for part in (0, 1)]
        figures[label] = {"calling_process_cpu_ms_per_task": 1e3 * cost[0],
                          "workers_cpu_ms_per_task": 1e3 * cost[1]}
    return figures


def against_point_by_point(sample: int, per_axis: int) -> dict[str, Any]:
    """The engine's rows against each point solved alone by sso.optimise (run_point)."""
    import warnings

    import sso
    from sso._studies.worker import run_point

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


def on_disk(per_axis: int, parquet_per_axis: int) -> dict[str, Any]:
    """The evaluate sweep written to disk in one process: first and last 10% of the
    points, the report after the last row, bytes a point in sweep.csv and Parquet."""
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
                time.sleep(0.005)

        watcher = threading.Thread(target=watch)
        watcher.start()
        started = time.perf_counter()
        try:
            result = sso.sweep(base_document(), grid(per_axis), action="evaluate", workers=1,
                               progress=False, out_dir=Path(folder) / "constant")
        finally:
            done.set()
            watcher.join()
        wall_s = time.perf_counter() - started
        csv_bytes = path.stat().st_size
        points = len(result.rows)
        del result
        parquet_result = sso.sweep(base_document(), grid(parquet_per_axis), action="evaluate",
                                   workers=1, progress=False, plots=False, parquet=True,
                                   out_dir=Path(folder) / "parquet")
        parquet_points = len(parquet_result.rows)
        parquet_bytes = sum(part.stat().st_size for part in
                            (Path(folder) / "parquet" / "sweep.parquet").iterdir())

    def instant(count: float) -> float:
        return next(moment for moment, rows in samples if rows >= count)

    header_written = samples[0][0]
    first_s = instant(0.1 * points) - header_written
    last_s = instant(points) - instant(0.9 * points)
    return {"points": points, "wall_s": wall_s, "before_header_s": header_written - started,
            "first_10_percent_s": first_s, "last_10_percent_s": last_s,
            "last_over_first": last_s / first_s,
            "constant_rate": last_s <= CONSTANT_RATE_TOLERANCE * first_s,
            "after_last_row_s": started + wall_s - instant(points),
            "csv_bytes_per_point": csv_bytes / points,
            "parquet_points": parquet_points,
            "parquet_bytes_per_point": parquet_bytes / parquet_points}


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """Run the benchmark, print a table, return the figures."""
    from distributed import Client, LocalCluster

    import sso
    from sso._studies.sweep import (
        ARRAY_CHUNK_CAP,
        ARRAY_CHUNK_FLOOR,
        ARRAY_CHUNKS_PER_WORKER,
        ARRAY_SHARE,
        DASK_CHUNK_FLOOR,
        DASK_EVALUATE_CHUNK_CAP,
    )

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--optimise-per-axis", type=int, default=OPTIMISE_PER_AXIS,
                        help="grid values per angle of the optimise sweep (47: 103,823 points)")
    parser.add_argument("--evaluate-per-axis", type=int, default=EVALUATE_PER_AXIS,
                        help="grid values per angle of the evaluate sweep (100: 1,000,000)")
    parser.add_argument("--passes", type=int, default=7,
                        help="interleaved passes of the six timed sweeps (default 7: "
                             "on a shared machine a median of 3 moves by 0.1x from run "
                             "to run)")
    parser.add_argument("--sample", type=int, default=500,
                        help="points solved one by one for the baseline (default 500)")
    parser.add_argument("--no-disk", action="store_true",
                        help="skip the sweep on disk (constant rate, report, output size)")
    parser.add_argument("--no-ceiling", action="store_true",
                        help="skip the ceiling (the chunks' compute in 1 and 2 independent "
                             "processes)")
    parser.add_argument("--json", type=Path, help="also write the figures to this file")
    args = parser.parse_args(argv)

    figures: dict[str, Any] = {
        "started_utc": datetime.now(UTC).strftime("%Y-%m-%d %H:%M"),
        "settings": {"optimise_per_axis": args.optimise_per_axis,
                     "evaluate_per_axis": args.evaluate_per_axis, "passes": args.passes,
                     "workers": WORKERS, "case": CASE.name},
        "load_before": load_now(),
        "chunks": {"most_points": ARRAY_CHUNK_CAP, "fewest_points": ARRAY_CHUNK_FLOOR,
                   "share_of_a_worker": 1 / ARRAY_SHARE,
                   "small_sweep_per_worker": ARRAY_CHUNKS_PER_WORKER,
                   "dask_fewest_points": DASK_CHUNK_FLOOR,
                   "dask_most_evaluate_points": DASK_EVALUATE_CHUNK_CAP},
    }
    cluster_started = time.perf_counter()
    with LocalCluster(n_workers=WORKERS, threads_per_worker=1, processes=True,
                      host="127.0.0.1", dashboard_address=":0") as cluster, \
            Client(cluster) as client:
        client.wait_for_workers(WORKERS)
        figures["dask_cluster_start_s"] = time.perf_counter() - cluster_started
        pool_started = time.perf_counter()
        sso.sweep(base_document(), grid(3), action="evaluate", workers=WORKERS, progress=False)
        figures["pool_start_s"] = time.perf_counter() - pool_started
        sso.sweep(base_document(), grid(3), action="evaluate", client=client, progress=False)
        ceiling = None if args.no_ceiling else Ceiling({"optimise": args.optimise_per_axis,
                                                        "evaluate": args.evaluate_per_axis})
        try:
            figures.update(interleaved({"optimise": grid(args.optimise_per_axis),
                                        "evaluate": grid(args.evaluate_per_axis)},
                                       client, args.passes, ceiling))
        finally:
            if ceiling is not None:
                ceiling.close()
        if ceiling is not None:
            figures["ceiling"] = ceiling.figures()
        figures["task_cost"] = task_cost(client, args.optimise_per_axis, args.passes,
                                         figures["idle_cpu_per_s"])
    figures["load_after_timed_runs"] = load_now()
    figures["point_by_point"] = against_point_by_point(args.sample, args.optimise_per_axis)
    if not args.no_disk:
        figures["on_disk"] = on_disk(args.evaluate_per_axis, PARQUET_PER_AXIS)
    figures["finished_utc"] = datetime.now(UTC).strftime("%Y-%m-%d %H:%M")
    figures["load_after"] = load_now()
    report(figures)
    if args.json:
        args.json.write_text(json.dumps(figures, indent=1) + "\n", encoding="utf-8")
    if not (figures["optimise"]["identical_rows"] and figures["evaluate"]["identical_rows"]
            and figures["point_by_point"]["same_re_and_success"]):
        raise SystemExit("the runs gave different rows")
    return figures


def report(figures: dict[str, Any]) -> None:
    """Print the figures as tables."""
    before, after = figures["load_before"], figures["load_after_timed_runs"]
    print(f"{before['cpu_count']} cores; load average (1, 5, 15 min) "
          f"{before['load_average_1_5_15_min']} before the timed runs, "
          f"{after['load_average_1_5_15_min']} after them")
    for action in ("optimise", "evaluate"):
        runs = figures[action]["runs"]
        points = next(iter(runs.values()))["points"]
        print(f"\n{action} sweep, option 3 exact, {points:,} points"
              + (' ("lm", one start)' if action == "optimise" else "")
              + f"; median of {figures['settings']['passes']} interleaved passes")
        print(f"{'run':<34}{'points/s':>12}{'x one process':>15}{'  per pass (points/s, load)'}")
        for label, run in runs.items():
            each = ", ".join(f"{one['points_per_s']:,.0f} ({one['load_average_1min']:.1f})"
                             for one in run["passes"])
            print(f"{label:<34}{run['median_points_per_s']:>12,.0f}"
                  f"{run['ratio_to_one_process']:>15.2f}  {each}")
        print("CPU per point (us; medians, less the CPU used idle), against one process's:")
        print(f"{'run':<34}{'calling':>9}{'workers':>9}{'calling / one':>15}"
              f"{'workers / one':>15}{'CPU-bound ratio':>17}")
        for label, run in runs.items():
            print(f"{label:<34}{run['calling_process_cpu_us_per_point']:>9.3f}"
                  f"{run['workers_cpu_us_per_point']:>9.3f}"
                  f"{run['calling_process_cpu_over_one_process']:>15.2f}"
                  f"{run['workers_cpu_over_one_process']:>15.2f}"
                  f"{run['cpu_bound_ratio']:>17.2f}")
        print(f"identical rows in every run: {figures[action]['identical_rows']}")
        limit = figures.get("ceiling", {}).get(action)
        if limit:
            print(f"ceiling (the chunks' compute, no engine): 2 independent processes "
                  f"{limit['ratio']:.2f}x one alone (loads "
                  + ", ".join(f"{one['load_average_1min']:.1f}"
                              for one in limit["passes"]["together"])
                  + f"); CPU per point together / alone {limit['cpu_together_over_alone']:.2f} "
                  f"({limit['together_cpu_us_per_point']:.3f} / "
                  f"{limit['alone_cpu_us_per_point']:.3f} us); the engine's ratios over it: "
                  + ", ".join(f"{label} {run['ratio_to_one_process'] / limit['ratio']:.2f}"
                              for label, run in runs.items() if label != "one process"))
    idle = figures["idle_cpu_per_s"]
    print(f"CPU used idle (cluster and pool up, no sweep): calling process "
          f"{idle['calling_process']:.3f} s/s, the processes below it {idle['workers']:.3f} s/s")
    cost = figures["task_cost"]
    print("CPU a task costs beyond its points (the optimise sweep in "
          + " and ".join(f"{count} tasks" for count in cost["tasks"].values()) + "): "
          + "; ".join(f"{label} {run['calling_process_cpu_ms_per_task']:.2f} ms in the calling "
                      f"process, {run['workers_cpu_ms_per_task']:.2f} ms in the workers"
                      for label, run in cost.items() if label != "tasks"))
    print(f"Dask cluster start: {figures['dask_cluster_start_s']:.1f} s; local pool start "
          f"(fork server and workers, first pool of the process): "
          f"{figures['pool_start_s']:.2f} s (neither counted)")
    baseline = figures["point_by_point"]
    print(f"\nengine {baseline['engine_points_per_s']:,.0f} points/s against point by point "
          f"{baseline['point_by_point_points_per_s']:,.0f} points/s ({baseline['sample']} "
          f"points): {baseline['ratio']:.1f}x; same RE (1e-12) and success: "
          f"{baseline['same_re_and_success']}")
    disk = figures.get("on_disk")
    if disk:
        print(f"\non disk, {disk['points']:,}-point evaluate sweep, one process: first 10% "
              f"{disk['first_10_percent_s']:.2f} s, last 10% {disk['last_10_percent_s']:.2f} s "
              f"(last / first {disk['last_over_first']:.2f}, target <= "
              f"{CONSTANT_RATE_TOLERANCE}: {'met' if disk['constant_rate'] else 'MISSED'}); "
              f"before the header {disk['before_header_s']:.2f} s, report after the last row "
              f"{disk['after_last_row_s']:.2f} s, wall {disk['wall_s']:.1f} s")
        print(f"output: sweep.csv {disk['csv_bytes_per_point']:.0f} bytes a point; "
              f"sweep.parquet {disk['parquet_bytes_per_point']:.0f} bytes a point "
              f"({disk['parquet_points']:,} points)")


if __name__ == "__main__":
    main()
