"""The "Sweeps at scale" page's measured section, rendered from one recorded benchmark run.

``python -m doctools.scaling record FIGURES_JSON`` copies the figures that
``python -m benchmarks.sweep_throughput --json FIGURES_JSON`` wrote into
``docs/data/sweep_scaling_run.json``, adding the commit and the machine
(:func:`benchmarks.machine.machine_description`, the one description). At each
build the hook replaces the marker line ``<!-- sweep scaling run -->`` of
``scaling.md`` with :func:`section`: the measured rates and ratios of the three
ways a sweep runs, the sweep on disk, and the projection to 10^9 designs
(:func:`projection`), all from that one run. Nothing on the page is typed in by hand.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import subprocess
import sys
from pathlib import Path
from typing import Any

from benchmarks.machine import machine_description
from doctools import performance

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "docs" / "data" / "sweep_scaling_run.json"
MARKER = "<!-- sweep scaling run -->"
DESIGNS = 10**9
MACHINES = (1, 10, 100)
CORES_PER_MACHINE = 32
POINTS_PER_SWEEP = 10**6
TASK_OVERHEAD_S = 1e-3
"""Scheduler time a Dask task costs, s: the upper figure of Dask's array best practices."""
ONE = "one process"
POOL = "2 local processes"
DASK = "Dask LocalCluster, 2 workers"
WRITTEN = "evaluate, to sweep.csv"


def record(figures_path: Path, target: Path = RECORD) -> dict[str, Any]:
    """Write the run record from the benchmark's figures; returns it."""
    document = json.loads(figures_path.read_text(encoding="utf-8"))
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    document["run"] = {"command": "python -m benchmarks.sweep_throughput",
                       "commit": commit or "unknown", "machine": machine_description()}
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_text(json.dumps(document, indent=1) + "\n", encoding="utf-8")
    return document


def load(target: Path = RECORD) -> dict[str, Any]:
    """The recorded run."""
    return performance.load(target)


def written_rate(document: dict[str, Any]) -> float:
    """Points a second of the evaluate sweep written to ``sweep.csv`` in one process,
    from its header to its last row (computing and the CSV text)."""
    disk = document["on_disk"]
    rate: float = disk["points"] / (disk["wall_s"] - disk["before_header_s"]
                                    - disk["after_last_row_s"])
    return rate


def duration(hours: float) -> str:
    """A duration in hours, minutes or seconds, three significant digits."""
    if hours >= 1:
        return f"{hours:.3g} h"
    if hours * 60 >= 1:
        return f"{hours * 60:.3g} min"
    return f"{hours * 3600:.3g} s"


def projection(document: dict[str, Any], action: str, machines: int) -> dict[str, float]:
    """Wall time of 10^9 designs of ``action`` on ``machines`` machines, from the run.

    ``action`` is ``"optimise"``, ``"evaluate"`` (rows in memory) or
    :data:`WRITTEN` (evaluated and written to ``sweep.csv``: the worker rate of the
    sweep on disk, the efficiency of the evaluate sweep).

    Assumptions (each stated on the page): a cluster core computes at the measured
    one-process rate; the workers keep the measured efficiency of the 2-worker Dask
    cluster (its ratio to one process over 2, at most 1); the designs are cut into
    sweeps of :data:`POINTS_PER_SWEEP` points (a sweep's rows are held in its calling
    process), each cut into tasks of the largest chunk (``chunk_size`` given: the
    automatic chunking, about 8 tasks a worker, would cut them far smaller on many
    workers); the scheduler spends :data:`TASK_OVERHEAD_S` on a task; each calling
    process places and appends rows at the rate its measured CPU time per point
    allows; so many sweeps run at once that the callers keep up and every worker
    has a task.

    Returns
    -------
    dict
        ``workers``, ``worker_rate`` (points/s a worker), ``efficiency``,
        ``compute_hours``, ``tasks``, ``scheduler_hours``, ``caller_rate`` (points/s
        a calling process can take) and ``callers`` (sweeps at once to keep up).
    """
    runs = document["evaluate" if action == WRITTEN else action]["runs"]
    worker_rate = (written_rate(document) if action == WRITTEN
                   else runs[ONE]["median_points_per_s"])
    efficiency = min(1.0, runs[DASK]["ratio_to_one_process"] / 2)
    workers = machines * CORES_PER_MACHINE
    rate = workers * worker_rate * efficiency
    chunk = document["chunks"]["most_points"]
    tasks = math.ceil(DESIGNS / chunk)
    caller_cpu_per_point = statistics.median(
        run["calling_process_cpu_s"] / run["points"] for run in runs[DASK]["passes"])
    caller_rate = 1.0 / caller_cpu_per_point
    tasks_per_sweep = math.ceil(POINTS_PER_SWEEP / chunk)
    return {"workers": workers, "worker_rate": worker_rate, "efficiency": efficiency,
            "compute_hours": DESIGNS / rate / 3600, "tasks": tasks,
            "scheduler_hours": tasks * TASK_OVERHEAD_S / 3600, "caller_rate": caller_rate,
            "callers": max(math.ceil(rate / caller_rate),
                           math.ceil(workers / tasks_per_sweep))}


def section(document: dict[str, Any]) -> str:
    """The measured part of the page, Markdown."""
    run = document["run"]
    box = run["machine"]
    before = document["load_before"]
    after = document["load_after_timed_runs"]
    settings = document["settings"]
    lines = [
        f"Measured from {document['started_utc']} to {document['finished_utc']} UTC by "
        f"`{run['command']}` at commit `{run['commit']}`, on {box['cpu_count']} cores of an "
        f"{box['processor']} (Python {box['python']}, NumPy {box['numpy']}). The machine is "
        "shared: "
        f"its load average over 1, 5 and 15 min was {before['load_average_1_5_15_min']} "
        f"before the timed runs and {after['load_average_1_5_15_min']} after them, for "
        f"{before['cpu_count']} cores; every ratio is taken within this one run, the median "
        f"of {settings['passes']} interleaved passes.{_autogroup_note(before)}",
        "",
        "| sweep | run | points/s (median) | ratio to one process | load average (1 min) "
        "at each pass |",
        "| --- | --- | --- | --- | --- |",
    ]
    for action in ("optimise", "evaluate"):
        runs = document[action]["runs"]
        points = runs[ONE]["points"]
        for label, figures in runs.items():
            loads = ", ".join(f"{one['load_average_1min']:.1f}" for one in figures["passes"])
            lines.append(f"| {action}, {points:,} points | {label} | "
                         f"{figures['median_points_per_s']:,.0f} | "
                         f"{figures['ratio_to_one_process']:.2f} | {loads} |")
    identical = all(document[action]["identical_rows"] for action in ("optimise", "evaluate"))
    lines += [
        "",
        f"Every run gave the rows of the first one-process run: {'yes' if identical else 'NO'}. "
        f"Start-ups, not counted above: the Dask cluster {document['dask_cluster_start_s']:.1f} s, "
        f"the local pool's fork server and workers (the first pool of a process) "
        f"{document['pool_start_s']:.2f} s.",
        "",
        task_times(document),
    ]
    lines += _robust_lines(document)
    disk = document.get("on_disk")
    if disk:
        lines += [
            "",
            f"On disk, the {disk['points']:,}-point evaluate sweep in one process: the first "
            f"10% of its points took {disk['first_10_percent_s']:.2f} s and the last 10% "
            f"{disk['last_10_percent_s']:.2f} s (last / first {disk['last_over_first']:.2f}; "
            f"the rate stays constant within 20%: "
            f"{'yes' if disk['constant_rate'] else 'NO'}); the report after the last row "
            f"took {disk['after_last_row_s']:.2f} s, of a wall time of {disk['wall_s']:.1f} s. "
            f"Written to `sweep.csv`, it ran at {written_rate(document):,.0f} points/s, "
            f"against {document['evaluate']['runs'][ONE]['median_points_per_s']:,.0f} in "
            f"memory. A point takes {disk['csv_bytes_per_point']:.0f} bytes of `sweep.csv` and "
            f"{disk['parquet_bytes_per_point']:.0f} bytes of `sweep.parquet`.",
        ]
    lines += ["", "### 10^9 designs on a cluster", ""]
    actions = ("evaluate", *((WRITTEN,) if disk else ()), "optimise")
    for action in actions:
        first = projection(document, action, MACHINES[0])
        lines += [
            f"**{action.capitalize()}** (a worker: {first['worker_rate']:,.0f} points/s, "
            f"efficiency {first['efficiency']:.2f}; {first['tasks']:,} tasks, "
            f"{duration(first['scheduler_hours'])} of scheduler time; a calling process "
            f"takes {first['caller_rate']:,.0f} points/s):",
            "",
            f"| machines ({CORES_PER_MACHINE} cores each) | workers | time of computing "
            "| wall time (at least the scheduler's) | sweeps at once to keep the workers busy |",
            "| --- | --- | --- | --- | --- |",
        ]
        for machines in MACHINES:
            figures = projection(document, action, machines)
            wall = max(figures["compute_hours"], figures["scheduler_hours"])
            lines.append(f"| {machines} | {figures['workers']:,} | "
                         f"{duration(figures['compute_hours'])} | {duration(wall)} | "
                         f"{figures['callers']:,} |")
        lines.append("")
    if disk:
        lines.append(
            f"Output of 10^9 points: {DESIGNS * disk['csv_bytes_per_point'] / 1e9:,.0f} GB of "
            f"`sweep.csv` or {DESIGNS * disk['parquet_bytes_per_point'] / 1e9:,.0f} GB of "
            f"`sweep.parquet`, in {DESIGNS // POINTS_PER_SWEEP:,} sweeps of "
            f"{POINTS_PER_SWEEP:,} points.")
    return "\n".join(lines) + "\n"


def _robust_lines(document: dict[str, Any]) -> list[str]:
    """The figures other work on the machine moves least, where the run has them: each
    run's CPU time per point against one process's, and the ceiling (the chunks'
    compute in two independent processes against one, in the same passes)."""
    ceiling = document.get("ceiling", {})
    if not ceiling:
        return []
    lines = ["", "| sweep | run | calling process CPU / one process's | workers' CPU / one "
             "process's | ratio the CPU times allow | ratio over the ceiling |",
             "| --- | --- | --- | --- | --- | --- |"]
    for action in ("optimise", "evaluate"):
        for label in (POOL, DASK):
            run = document[action]["runs"][label]
            lines.append(f"| {action} | {label} | "
                         f"{run['calling_process_cpu_over_one_process']:.2f} | "
                         f"{run['workers_cpu_over_one_process']:.2f} | "
                         f"{run['cpu_bound_ratio']:.2f} | "
                         f"{run['ratio_to_one_process'] / ceiling[action]['ratio']:.2f} |")
    lines += ["", "The ceiling: the same chunks computed with no engine around them by one "
              "process alone and by two independent processes at once, in each pass just "
              "before the sweeps; " + "; ".join(
                  f"{action}: two processes {ceiling[action]['ratio']:.2f}x one, their CPU "
                  f"time per point {ceiling[action]['cpu_together_over_alone']:.2f}x"
                  for action in ("optimise", "evaluate")) + ". On a machine shared with "
              "other sessions two processes of one session get little more than one (the "
              "cores are shared between sessions first); the engine's ratios are read "
              "against this ceiling."]
    return lines


def _autogroup_note(load: dict[str, Any]) -> str:
    if load.get("sched_autogroup") != "1":
        return ""
    return (" The kernel shares the cores between sessions first (autogroup scheduling), so "
            "while other sessions keep both cores busy a sweep's second process adds little "
            "to its session's share: a parallel ratio measured under such load is a lower "
            "bound of what an idle machine gives.")


def task_times(document: dict[str, Any]) -> str:
    """What a task of the most and of the fewest points takes at one process's rates."""
    per_point_s = {action: 1.0 / document[action]["runs"][ONE]["median_points_per_s"]
                   for action in ("evaluate", "optimise")}
    chunks = document["chunks"]
    most, fewest = chunks["most_points"], chunks["fewest_points"]
    return (f"At one process's rates in this run ({per_point_s['evaluate'] * 1e6:.2f} us a "
            f"point evaluating, {per_point_s['optimise'] * 1e6:.2f} us optimising), a task of "
            f"the most points ({most:,}) takes {most * per_point_s['evaluate']:.2f} s of "
            f"evaluating or {most * per_point_s['optimise']:.2f} s of optimising, and one of "
            f"the fewest ({fewest:,}) {fewest * per_point_s['evaluate'] * 1e3:.1f} ms or "
            f"{fewest * per_point_s['optimise'] * 1e3:.1f} ms; Dask puts its scheduler's cost "
            f"at up to {TASK_OVERHEAD_S * 1e3:g} ms a task.")


def page_with_section(markdown: str, document: dict[str, Any]) -> str:
    """``markdown`` with its marker line replaced by the measured section."""
    if MARKER not in markdown:
        raise ValueError(f"the Sweeps at scale page has no {MARKER} line")
    return markdown.replace(MARKER, section(document))


def main(arguments: list[str] | None = None) -> int:
    """``python -m doctools.scaling record FIGURES_JSON``: record a benchmark run."""
    parser = argparse.ArgumentParser(description=main.__doc__)
    parser.add_argument("action", choices=["record"])
    parser.add_argument("figures", type=Path)
    options = parser.parse_args(arguments)
    document = record(options.figures)
    print(f"recorded the run of {document['finished_utc']} UTC in {RECORD}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
