"""``sso.sweep``: optimise or evaluate a base case at every point of a grid of key values."""

from __future__ import annotations

import json
import math
import time
import warnings
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any

from sso.batch.axes import Axis, base_case, expand_points, parse_axes
from sso.batch.estimate import sweep_estimate
from sso.batch.execution import run_tasks, validate_workers
from sso.batch.report import SWEEP_FOLDER
from sso.batch.results import SweepResult
from sso.batch.table import (
    CSV_NAME,
    MANIFEST_NAME,
    columns,
    done_rows,
    format_row,
    manifest,
    typed_rows,
    write_rows,
)
from sso.batch.worker import ACTIONS, SweepChunk, failed_rows, run_sweep_chunk
from sso.files import claim_folder, remove_stale_temporaries, write_text_atomic
from sso.limits import OUTPUT_FORMATS
from sso.reports.kinds import write_report
from sso.shafts.options import build_problem
from sso.shafts.quadrature import rule_for_bounds
from sso.solvers.progress import ProgressBar, interactive
from sso.solvers.resources import ResourceEstimate, check_memory
from sso.validation import shown

MAX_CHUNK_SIZE = 10_000
# Default chunking: about this many chunks per worker (load balance), each of at
# most DEFAULT_CHUNK_CAP points (a lost chunk costs little, progress stays live).
CHUNKS_PER_WORKER = 4
DEFAULT_CHUNK_CAP = 25


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
) -> SweepResult:
    """Optimise or evaluate a base case at every point of a sweep.

    Parameters
    ----------
    base : str, pathlib.Path, sso.cases.shaft_series.Case or mapping
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
        Folder for ``sweep.csv`` (rewritten atomically as chunks finish; every
        digit), ``sweep.json`` (what the sweep is), ``report.md``, ``report.html``
        and ``sweep_re.png``. When the sweep ends the whole folder is written
        afresh (:func:`sso.write_report`). It must be new, empty or hold only
        files sso wrote there for a sweep (listed in its ``sso-files.json``).
        Without it nothing is written.
    resume : bool
        Continue the sweep already in ``out_dir``: compute only its missing
        points. The final ``sweep.csv`` equals that of an uninterrupted run
        (apart from the wall-time columns).
    client : dask.distributed.Client, optional
        Run the chunks on this Dask cluster instead of local processes.
    workers : int, optional
        Local processes (default: every available core); 1 runs in this process.
    chunk_size : int, optional
        Points per task, ``1..10000`` (default: about four tasks per worker, at
        most 25 points each).
    progress : bool, optional
        Draw a progress bar on stderr (default: only on an interactive terminal
        outside CI).
    plots : bool
        Draw the report's plots (needs ``out_dir``; imports matplotlib).
    memory_limit_mb : float, optional
        Refuse the sweep if its memory estimate exceeds this, MB (default
        ``SSO_MEMORY_LIMIT_MB`` or :data:`sso.limits.DEFAULT_MEMORY_LIMIT_MB`).

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
        sweep, without ``resume``), files sso did not write or another kind of
        result; or, before
        any point is computed, if the memory estimate exceeds the limit.
    """
    started = time.perf_counter()
    case = base_case(base)  # refuses the kinds a sweep cannot vary
    document = case.to_dict()
    parsed_axes = parse_axes(axes, document)
    if action not in ACTIONS:
        raise ValueError(f"action = {shown(action)} is not one of "
                         f"{', '.join(map(repr, ACTIONS))}")
    worker_count = validate_workers(workers)
    check_memory(_estimate(case, parsed_axes, mode, action,
                           worker_count if client is None else 1), memory_limit_mb)
    points = expand_points(parsed_axes, mode)
    header = columns([axis.path for axis in parsed_axes])
    identity = manifest(document, parsed_axes, mode, action, len(points))

    rows: dict[int, dict[str, str]] = {}
    csv_path = None
    if out_dir is not None:
        out_dir = claim_folder(out_dir, SWEEP_FOLDER, (CSV_NAME, MANIFEST_NAME))
        remove_stale_temporaries(out_dir)  # of a sweep killed mid-write
        csv_path = out_dir / CSV_NAME
        if resume:
            rows = done_rows(out_dir, identity, header)
        elif csv_path.exists() or (out_dir / MANIFEST_NAME).exists():
            raise ValueError(f"out_dir = {str(out_dir)!r} already holds a sweep; pass "
                             "resume=True (--resume) to complete it, or choose another folder")
        write_text_atomic(out_dir / MANIFEST_NAME, json.dumps(identity, indent=2) + "\n")
    resumed = len(rows)

    pending = [(index, point) for index, point in enumerate(points) if index not in rows]
    parallelism = _parallelism(client, worker_count)
    size = _chunk_size(chunk_size, len(pending), parallelism)
    chunks = [SweepChunk(document, action, tuple(pending[start:start + size]))
              for start in range(0, len(pending), size)]
    bar = ProgressBar(len(pending), "points", interactive() if progress is None else progress)
    try:
        for index, chunk_rows, error in run_tasks(run_sweep_chunk, chunks, client,
                                                   worker_count):
            if error is not None:
                chunk_rows = failed_rows(chunks[index], error)
            for row in chunk_rows:
                rows[row["point"]] = format_row(row, header)
            if csv_path is not None:
                write_rows(csv_path, header, rows.values())
            bar.advance(len(chunk_rows), sum(row["status"] != "ok" for row in chunk_rows))
    finally:
        bar.close()
    if csv_path is not None:  # also when a resumed sweep had nothing left to compute
        write_rows(csv_path, header, rows.values())

    ordered = tuple(typed_rows(row for _, row in sorted(rows.items())))
    result = SweepResult(axes=parsed_axes, mode=mode, action=action, rows=ordered,
                         computed=len(pending), resumed=resumed,
                         elapsed_s=time.perf_counter() - started, out_dir=out_dir,
                         manifest=identity)
    if out_dir is None:
        return result
    formats = tuple(name for name in OUTPUT_FORMATS if plots or name != "png")
    return replace(result, files=tuple(write_report(result, out_dir, formats)))


def _estimate(case: Any, axes: tuple[Axis, ...], mode: str, action: str,
              workers: int) -> ResourceEstimate:
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
                          optimising and case.kind == "shaft_series")


def _parallelism(client: Any, workers: int) -> int:
    """Tasks that can run at once: the Dask cluster's threads, or the local workers."""
    if client is None:
        return workers
    threads: int = sum(client.nthreads().values())
    return max(1, threads)


def _chunk_size(chunk_size: Any, points: int, parallelism: int) -> int:
    if chunk_size is None:
        return max(1, min(DEFAULT_CHUNK_CAP, math.ceil(points / (CHUNKS_PER_WORKER * parallelism))))
    if (isinstance(chunk_size, bool) or not isinstance(chunk_size, int)
            or not 1 <= chunk_size <= MAX_CHUNK_SIZE):
        raise ValueError(f"chunk_size = {chunk_size!r} is outside the allowed range "
                         f"[1, {MAX_CHUNK_SIZE}] (a whole number of points per task)")
    return chunk_size
