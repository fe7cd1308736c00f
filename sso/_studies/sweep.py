"""``sso.sweep``: optimise or evaluate a base case at every point of a grid of key values."""

from __future__ import annotations

import json
import math
import time
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from sso._files import (
    claim_folder,
    remove_stale_temporaries,
    write_bytes_atomic,
    write_text_atomic,
)
from sso._folder_lock import folder_lock
from sso._progress import ProgressBar, interactive
from sso._resources import ResourceEstimate, check_memory
from sso._shafts.options import build_problem
from sso._shafts.quadrature import rule_for_bounds
from sso._studies.array_engine import ArrayPlan, array_plan, number_columns
from sso._studies.axes import (
    Axis,
    base_case,
    parse_axes,
    point_count,
    value_positions,
    value_ranges,
)
from sso._studies.column_rows import check_axis_values, check_sweepable
from sso._studies.columns import RowTable, TableAssembly
from sso._studies.element_columns import flat_row
from sso._studies.estimate import sweep_estimate
from sso._studies.execution import parallelism, run_tasks, runs_in_pool, validate_workers
from sso._studies.parquet_output import (
    PARQUET_NAME,
    arrow_schema,
    part_data,
    start_parts,
    write_part,
)
from sso._studies.report import SWEEP_FIGURES_PLOT, SWEEP_FOLDER, SWEEP_PLOT, render_sweep
from sso._studies.results import SweepResult, SweepRows
from sso._studies.row_checks import recheck_row
from sso._studies.shared_rows import shared_columns
from sso._studies.table import (
    CSV_NAME,
    HASH_COLUMN,
    MANIFEST_NAME,
    append_rows,
    done_rows,
    format_cell,
    manifest,
    start_file,
    sweep_columns,
    typed_rows,
)
from sso._studies.worker import (
    ACTIONS,
    ChunkTask,
    GridPositions,
    SweepChunk,
    chunk_output,
    failed_rows,
    run_chunk_task,
)
from sso._validation import shown

# Default chunking: about this many chunks per worker (load balance), each of at
# most DEFAULT_CHUNK_CAP points (a lost chunk costs little, progress stays live).
CHUNKS_PER_WORKER = 4
DEFAULT_CHUNK_CAP = 25
# An array sweep (sso._studies.array_engine) is cut into tasks of decreasing size
# (guided self-scheduling): each takes 1 / (ARRAY_SHARE x workers) of the points
# not yet cut, at most ARRAY_CHUNK_CAP points (hundredths of a second of evaluating
# to tenths of optimising at the rates docs/scaling.md records, which gives them,
# and ARRAY_CHUNK_CAP x estimate.ARRAY_CHUNK_BYTES_PER_POINT at the peak) and at
# least ARRAY_CHUNK_FLOOR (milliseconds of work, above a task's cost to the pool or
# to Dask), or in a small sweep an
# ARRAY_CHUNKS_PER_WORKER-th of a worker's share. The first tasks are long and
# the last ones short, so the workers end within a short task of each other.
ARRAY_SHARE = 2
ARRAY_CHUNKS_PER_WORKER = 8
ARRAY_CHUNK_FLOOR = 2_000
ARRAY_CHUNK_CAP = 50_000
# On Dask a task costs about 4 ms of CPU (benchmarks/sweep_throughput.py measures it
# on a 2-worker LocalCluster: about 2 ms in the calling process, its scheduler's and
# client's work, and 2 ms in the worker process), some three times what it costs the
# local pool, so Dask's tasks are longer: at least DASK_CHUNK_FLOOR points of their
# action (about 25 ms of work each), an evaluate task up to DASK_EVALUATE_CHUNK_CAP
# points (about 35 ms, and 35 MB at the peak: a Dask worker computes in a thread,
# whose allocator's heaps hold at most 64 MB each, and a chunk that needs two of them
# gives one back when it ends, to be faulted in again by the next: 10,000 page faults
# a worker on the evaluate sweep of 200,000-point tasks). And they go out in rounds of
# equal tasks, one a worker thread: Dask's scheduler gives a single-threaded worker its
# next task while the current one runs (worker-saturation 1.1 x 1 thread, rounded up),
# and its work stealing looks every second, so the first two rounds are shared out as
# they are cut, and a task handed to a busy worker waits there. A round takes half of
# the points left (each task half a worker's share, ARRAY_SHARE); the round that would
# leave fewer than a round of DASK_CHUNK_FLOOR-point tasks takes every point left.
DASK_CHUNK_FLOOR = {"optimise": 10_000, "evaluate": 50_000}
DASK_EVALUATE_CHUNK_CAP = 100_000
MAX_CHUNK_SIZE = ARRAY_CHUNK_CAP
DOCUMENT_FORMATS = ("md", "html", "png")
SWEEP_FILES = (CSV_NAME, MANIFEST_NAME, "report.md", "report.html", SWEEP_PLOT, SWEEP_FIGURES_PLOT,
               PARQUET_NAME)
"""The files a sweep writes into its folder (its ``sso-files.json`` lists them; the
Parquet parts are a folder); it refuses a folder holding anything else."""


def sweep(
    base: Any,
    axes: Mapping[str, Any],
    *,
    mode: str = "product",
    action: str = "optimise",
    out_dir: str | Path | None = None,
    resume: bool = False,
    client: Any = None,
    workers: int | None = None,
    chunk_size: int | None = None,
    progress: bool | None = None,
    plots: bool = True,
    memory_limit_mb: float | None = None,
    parquet: bool = False,
) -> SweepResult:
    """Optimise or evaluate a base case at every point of a sweep.

    Parameters
    ----------
    base : str, pathlib.Path, sso._cases.shaft_series.Case or mapping
        The base case: a case file, a case read from one, or a mapping laid out
        like a case file (``{"design": {"beta_deg": [...]}, "option": 3, ...}``).
    axes : mapping of str to list or range
        Case keys to vary, as written in a case file with optional indices
        (``"design.beta_deg[1]"``, ``"bounds.beta_deg[1]"``, ``"option"``,
        ``"model"``, ``"input_speed_rpm"``, ``"solver.starts"``), each mapped to a
        list of values or a range ``{"start", "stop", "num"}`` /
        ``{"start", "stop", "step"}``.
    mode : {"product", "listed"}
        Every combination of the axes' values (last axis fastest), or the
        ``i``-th values of all axes together (equal lengths).
    action : {"optimise", "evaluate"}
        Optimise each point's case, or evaluate its design as given.
    out_dir : str or pathlib.Path, optional
        Folder for ``sweep.csv`` (each chunk's rows appended as it finishes, in
        that order; every digit), ``sweep.json`` (what the sweep is),
        ``report.md``, ``report.html`` and ``sweep_re.png`` (written when the sweep
        ends). It must be new, empty or hold only the files sso wrote there for a
        sweep (its ``sso-files.json`` lists them); one sweep at a time
        writes into it (a lock file beside it, :mod:`sso._folder_lock`). Without it
        nothing is written.
    resume : bool
        Continue the sweep already in ``out_dir``: compute only its missing
        points. Every row found is checked against ``sweep.json`` (point index,
        axis values, the sweep's hash); a row that does not belong is refused.
    client : dask.distributed.Client, optional
        Run the chunks on this Dask cluster instead of local processes.
    workers : int, optional
        Local processes (default: every available core); 1 runs in this process.
    chunk_size : int, optional
        Points per task, ``1..50000`` (default: about four tasks per worker, at
        most 25 points each; a sweep run as arrays, tasks of decreasing size, each
        half a worker's share of the points left, 2,000 to 50,000 points; on
        Dask rounds of equal tasks, one a worker, each at least 10,000 optimised or
        50,000 evaluated points, an evaluate task up to 100,000).
    progress : bool, optional
        Draw a progress bar on stderr (default: only on an interactive terminal
        outside CI).
    plots : bool
        Draw the report's plots (needs ``out_dir``; imports matplotlib).
    memory_limit_mb : float, optional
        Refuse the sweep if its memory estimate exceeds this, MB (default
        ``SSO_MEMORY_LIMIT_MB`` or :data:`sso._limits.DEFAULT_MEMORY_LIMIT_MB`).
    parquet : bool
        Also write the rows as Parquet beside ``sweep.csv`` (``sweep.parquet/``, a
        part per chunk; needs ``out_dir`` and pyarrow, the ``parquet`` extra). A
        resumed sweep that has it keeps writing it.

    Returns
    -------
    SweepResult
        Failing points are recorded in their rows (``status = "failed"`` and the
        error), never raised.

    Raises
    ------
    ValueError
        For a bad base case, a case kind that cannot be swept, a bad axis, mode,
        action or count, or an ``out_dir`` that holds a different sweep (or any
        sweep, without ``resume``), rows that are not this sweep's, or files a
        sweep does not write; or, before any point is computed, if the memory
        estimate exceeds the limit.
    sso._folder_lock.FolderLockedError
        (a ValueError) If another process writes into ``out_dir``.
    """
    started = time.perf_counter()
    case = base_case(base)  # refuses the kinds a sweep cannot vary
    document = case.to_dict()
    parsed_axes = parse_axes(axes, document)
    if case.kind == "column":
        check_sweepable(case)
        check_axis_values(document, parsed_axes)
    if action not in ACTIONS:
        raise ValueError(f"action = {shown(action)} is not one of "
                         f"{', '.join(map(repr, ACTIONS))}")
    worker_count = validate_workers(workers)
    plan = array_plan(case, parsed_axes, action)
    check_memory(_estimate(case, parsed_axes, mode, action,
                           worker_count if client is None else 1, plan is not None,
                           client is not None),
                 memory_limit_mb)
    count = point_count(parsed_axes, mode)
    header = sweep_columns(document, parsed_axes)
    identity = manifest(document, parsed_axes, mode, action, count)
    job = _Job(document, action, parsed_axes, mode, count, header, identity, plan, client,
               worker_count, chunk_size, interactive() if progress is None else progress)
    if out_dir is None:
        if parquet:
            raise ValueError("parquet = True writes sweep.parquet into out_dir; give out_dir")
        rows = job.run({}, None)
        return _result(job, parsed_axes, mode, rows, 0, started, None)
    out_dir = Path(out_dir)
    parquet = bool(parquet) or (resume and (out_dir / PARQUET_NAME).is_dir())
    schema = arrow_schema(header, parsed_axes) if parquet else None  # pyarrow is there
    with folder_lock(out_dir, "run a sweep"):
        earlier = _open_folder(out_dir, resume, job)
        if schema is not None:
            start_parts(out_dir)
        resumed = len(earlier)
        rows = job.run(earlier, out_dir / CSV_NAME, schema)
        result = _result(job, parsed_axes, mode, rows, resumed, started, out_dir)
        formats = tuple(name for name in DOCUMENT_FORMATS if plots or name != "png")
        written = [write_bytes_atomic(out_dir / name, data)
                   for name, data in render_sweep(result, formats).items()]
    data = (out_dir / CSV_NAME, out_dir / MANIFEST_NAME,
            *((out_dir / PARQUET_NAME,) if schema is not None else ()))
    return replace(result, files=(*data, *written))


@dataclass(frozen=True)
class _Job:
    """What a sweep computes and how: its points, columns, identity and execution."""

    document: dict[str, Any]
    action: str
    axes: tuple[Axis, ...]
    mode: str
    count: int
    header: list[str]
    identity: dict[str, Any]
    plan: ArrayPlan | None
    client: Any
    workers: int
    chunk_size: int | None
    progress: bool

    def point(self, index: int) -> dict[str, Any]:
        """The axis values of point ``index`` (case key -> value)."""
        positions = value_positions(self.axes, self.mode, [index])
        return {axis.path: axis.values[int(position[0])]
                for axis, position in zip(self.axes, positions, strict=True)}

    def axis_cells(self, index: int) -> list[str]:
        """The formatted axis cells of point ``index``, as ``sweep.csv`` holds them (a
        list-valued axis one cell per element, empty beyond its value's length)."""
        cells = flat_row(self.point(index))
        return [format_cell(cells.get(name)) for name in self.header[1:self.header.index("status")]]

    def recheck(self, index: int, row: Mapping[str, str]) -> str | None:
        """What disagrees when the RE of point ``index``'s kept row is computed again."""
        return recheck_row(self.document, self.point(index), row)

    def chunks(self, pending: np.ndarray) -> list[SweepChunk]:
        """The tasks of the pending points (sorted), each with the slice of every axis
        its points take, found from its first and last point alone."""
        sizes = _chunk_sizes(self.chunk_size, len(pending),
                             parallelism(self.client, self.workers), self.plan is not None,
                             *array_chunk_rule(self.client is not None, self.action))
        lengths = tuple(len(axis.values) for axis in self.axes)
        chunks = []
        for start, size in zip(np.cumsum([0, *sizes]).tolist()[:-1], sizes, strict=True):
            indices = pending[start:start + size]
            bounds = value_ranges(lengths, self.mode, int(indices[0]), int(indices[-1]))
            chunks.append(SweepChunk(
                self.document, self.action, tuple(self.header),
                tuple(axis.path for axis in self.axes), indices,
                tuple(axis.values[low:high] for axis, (low, high) in zip(self.axes, bounds,
                                                                         strict=True)),
                self.plan,
                self.identity[HASH_COLUMN],
                GridPositions(self.mode, lengths, tuple(low for low, _ in bounds))))
        return chunks

    def run(self, earlier: dict[int, dict[str, str]], csv_path: Path | None,
            schema: Any = None) -> RowTable:
        """Compute the points not in ``earlier``, appending each chunk's rows to
        ``csv_path`` (and a Parquet part beside it, given the parts' ``schema``);
        every row, sorted by point."""
        waiting = np.ones(self.count, dtype=bool)
        waiting[np.fromiter(earlier, dtype=np.int64, count=len(earlier))] = False
        pending = np.flatnonzero(waiting)
        chunks = self.chunks(pending)
        resumed = RowTable.from_rows(self.header, typed_rows(earlier.values()))
        if schema is not None and csv_path is not None and resumed.length:
            write_part(csv_path.parent, int(resumed.columns["point"].min()), resumed.length,
                       part_data(resumed, schema), resumed=True)
        # Each chunk's rows go to their place as the chunk ends: the chunks cover the
        # pending points in order, so the rows come out sorted whichever order the
        # chunks finish in, and joining them overlaps the work still running.
        lengths = [len(chunk.indices) for chunk in chunks]
        # Workers of this machine write the number columns in place (shared_rows).
        elsewhere = self.client is not None or runs_in_pool(None, self.workers, len(chunks))
        shared = (shared_columns(number_columns(self.plan, self.axes), len(pending))
                  if self.plan is not None and elsewhere else None)
        assembly = TableAssembly(self.header, lengths, None if shared is None else shared.arrays)
        offsets = np.cumsum([0, *lengths]).tolist()
        bar = ProgressBar(len(pending), "points", self.progress)
        try:
            tasks = [ChunkTask(chunk, csv_path is not None, schema,
                               None if shared is None else shared.layout, offsets[index])
                     for index, chunk in enumerate(chunks)]
            for index, output, error in run_tasks(run_chunk_task, tasks, self.client,
                                                   self.workers):
                if error is not None:
                    output = chunk_output(failed_rows(chunks[index], error),
                                          csv_path is not None, schema)
                if csv_path is not None:
                    append_rows(csv_path, output.csv)
                    if schema is not None:
                        write_part(csv_path.parent, int(chunks[index].indices[0]),
                                   lengths[index], output.parquet_part or b"")
                assembly.place(index, output.table, output.in_shared)
                bar.advance(output.table.length, output.failed)
        finally:
            bar.close()
            if shared is not None:
                shared.close()
        rows = RowTable.concatenate(self.header, [resumed, assembly.table()])
        points = rows.columns.get("point", np.zeros(0, dtype=np.int64))
        if np.all(points[1:] > points[:-1]):
            return rows
        return rows.take(np.argsort(points, kind="stable"))


def _open_folder(out_dir: Path, resume: bool, job: _Job) -> dict[int, dict[str, str]]:
    """Make ``out_dir`` the sweep's folder (its lock held); the rows of an earlier run.

    Raises
    ------
    ValueError
        If ``out_dir`` is a file, holds anything sso did not write there for a
        sweep (a case's report, the user's files), holds a sweep without ``resume``, or holds
        another sweep or rows that do not belong to this one.
    """
    claim_folder(out_dir, SWEEP_FOLDER, SWEEP_FILES, folders=(PARQUET_NAME,))
    remove_stale_temporaries(out_dir)  # of a sweep killed mid-write (we hold the lock)
    csv_path = out_dir / CSV_NAME
    if resume:
        rows = done_rows(out_dir, job.identity, job.header, job.axis_cells, job.recheck)
    elif csv_path.exists() or (out_dir / MANIFEST_NAME).exists():
        raise ValueError(f"out_dir = {str(out_dir)!r} already holds a sweep; pass "
                         "resume=True (--resume) to complete it, or choose another folder")
    else:
        rows = {}
    write_text_atomic(out_dir / MANIFEST_NAME, json.dumps(job.identity, indent=2) + "\n")
    start_file(csv_path, job.header)
    return rows


def _result(job: _Job, axes: tuple[Axis, ...], mode: str, rows: RowTable, resumed: int,
            started: float, out_dir: Path | None) -> SweepResult:
    return SweepResult(axes=axes, mode=mode, action=job.action, rows=SweepRows(rows),
                       computed=rows.length - resumed, resumed=resumed,
                       elapsed_s=time.perf_counter() - started, out_dir=out_dir,
                       manifest=job.identity)


def _estimate(case: Any, axes: tuple[Axis, ...], mode: str, action: str,
              workers: int, arrays: bool, on_dask: bool) -> ResourceEstimate:
    """Memory and solves of the sweep, from the base case's shape."""
    count = (math.prod(len(axis.values) for axis in axes) if mode != "listed"
             else max(len(axis.values) for axis in axes))
    optimising = action == "optimise"
    per_point = case.starts * len(case.solvers) if optimising and hasattr(case, "starts") else 1
    joints = free = samples = 0
    if case.kind == "shaft_series":
        with warnings.catch_warnings():  # the points' runs report these warnings
            warnings.simplefilter("ignore")
            problem = build_problem(case.beta_deg, case.phase_deg, case.model, case.option,
                                    case.beta_bounds_deg, case.phase_bounds_deg)
            samples = rule_for_bounds(problem.beta_upper_rad, case.model).samples
        joints, free = problem.n_joints, problem.n_free
    return sweep_estimate(count, joints, free, samples, per_point, workers,
                          optimising and case.kind == "shaft_series", arrays,
                          min(count, array_chunk_rule(on_dask, action)[1]))


def array_chunk_rule(on_dask: bool, action: str) -> tuple[int, int, bool]:
    """The fewest and the most points of an array sweep's task, and whether its tasks
    go out in rounds of one a worker (see the chunking constants above)."""
    if not on_dask:
        return ARRAY_CHUNK_FLOOR, ARRAY_CHUNK_CAP, False
    return (DASK_CHUNK_FLOOR[action],
            DASK_EVALUATE_CHUNK_CAP if action == "evaluate" else ARRAY_CHUNK_CAP, True)


def _chunk_sizes(chunk_size: Any, points: int, at_once: int, arrays: bool = False,
                 fewest: int = ARRAY_CHUNK_FLOOR, most: int = ARRAY_CHUNK_CAP,
                 in_rounds: bool = False) -> list[int]:
    """Points of each task, in order (see the chunking constants above); an array
    sweep's tasks of ``fewest`` to ``most`` points, ``in_rounds`` of ``at_once`` equal
    tasks."""
    if chunk_size is None and arrays and in_rounds:
        return _rounds(points, at_once, fewest, most)
    if chunk_size is None and arrays:
        floor = min(fewest, math.ceil(points / (ARRAY_CHUNKS_PER_WORKER * at_once)))
        sizes = []
        while points > 0:
            size = min(points, most,
                       max(floor, math.ceil(points / (ARRAY_SHARE * at_once))))
            sizes.append(size)
            points -= size
        return sizes
    if chunk_size is None:
        size = max(1, min(DEFAULT_CHUNK_CAP, math.ceil(points / (CHUNKS_PER_WORKER * at_once))))
    elif (isinstance(chunk_size, bool) or not isinstance(chunk_size, int)
            or not 1 <= chunk_size <= MAX_CHUNK_SIZE):
        raise ValueError(f"chunk_size = {chunk_size!r} is outside the allowed range "
                         f"[1, {MAX_CHUNK_SIZE}] (a whole number of points per task)")
    else:
        size = chunk_size
    return [min(size, points - start) for start in range(0, points, size)]


def _rounds(points: int, at_once: int, fewest: int, most: int) -> list[int]:
    """Tasks in rounds of ``at_once`` equal tasks, each round half the points left, each
    task ``fewest`` to ``most`` points; the last round takes every point left, cut into
    a whole number of rounds of at most ``most`` points a task."""
    sizes: list[int] = []
    while points > 0:
        size = min(most, max(fewest, math.ceil(points / (ARRAY_SHARE * at_once))))
        if points - at_once * size < at_once * fewest:
            tasks = min(points, at_once * math.ceil(points / (at_once * most)))
            size, longer = divmod(points, tasks)
            return [*sizes, *[size + 1] * longer, *[size] * (tasks - longer)]
        sizes += [size] * at_once
        points -= at_once * size
    return sizes
