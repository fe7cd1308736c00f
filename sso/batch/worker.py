"""What a worker process runs: one chunk of sweep points, one row per point.

The functions here are top-level and take plain data, so a spawned process or a
Dask worker can import and run them. Each process builds the CasADi NLP of a
shape once (the per-thread cache of :mod:`sso.solvers.nlp`) and reuses it for
every point of that shape it is given.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np

from sso.batch.array_engine import ArrayPlan, run_array_points
from sso.batch.axes import point_document
from sso.batch.batched import BatchedPoints, batchable
from sso.batch.column_rows import column_row
from sso.batch.columns import RowTable
from sso.batch.point_row import PointRow, design_columns, solver_columns
from sso.batch.table import HASH_COLUMN

ACTIONS = ("optimise", "evaluate")


@dataclass(frozen=True)
class SweepChunk:
    """A unit of work: some points of one sweep.

    Attributes
    ----------
    document : dict
        The base case as a complete case-file document.
    action : {"optimise", "evaluate"}
        What to do at each point.
    header : tuple of str
        The columns of ``sweep.csv``.
    paths : tuple of str
        The axes' paths.
    indices : numpy.ndarray
        The points' indices.
    value_indices : tuple of numpy.ndarray
        Per axis, the position of each point's value in ``values``.
    values : tuple of tuple
        Per axis, the values this chunk's points take (a slice of the axis).
    plan : ArrayPlan or None
        The array engine's plan (:mod:`sso.batch.array_engine`), cut to ``values``;
        None where every point is read and solved on its own.
    sweep_hash : str
        The sweep's hash, written into every row.
    """

    document: dict[str, Any]
    action: str
    header: tuple[str, ...]
    paths: tuple[str, ...]
    indices: np.ndarray
    value_indices: tuple[np.ndarray, ...]
    values: tuple[tuple[Any, ...], ...]
    plan: ArrayPlan | None
    sweep_hash: str

    @classmethod
    def listed(cls, document: dict[str, Any], action: str,
               points: tuple[tuple[int, dict[str, Any]], ...], sweep_hash: str = "",
               plan: ArrayPlan | None = None) -> SweepChunk:
        """A chunk of the given ``(index, {path: value})`` points (the same paths each)."""
        from sso.batch.table import columns

        paths = tuple(points[0][1]) if points else ()
        count = len(points)
        return cls(document, action, tuple(columns(paths)), paths,
                   np.array([index for index, _ in points], dtype=np.int64),
                   tuple(np.arange(count) for _ in paths),
                   tuple(tuple(point[path] for _, point in points) for path in paths),
                   plan, sweep_hash)

    def points(self, selected: np.ndarray) -> list[tuple[int, dict[str, Any]]]:
        """``(index, {path: value})`` of the selected points (a boolean mask)."""
        positions = [index_array[selected].tolist() for index_array in self.value_indices]
        return [(index, {path: self.values[axis][position[row]]
                         for axis, (path, position) in enumerate(zip(self.paths, positions,
                                                                     strict=True))})
                for row, index in enumerate(self.indices[selected].tolist())]


def run_sweep_chunk(chunk: SweepChunk) -> RowTable:
    """Rows of the chunk's points; a point that fails gives an error row.

    With a plan, the points every axis value of which the case accepts are computed
    as arrays (:mod:`sso.batch.array_engine`); every other point is read as a case.
    Optimising such a point, the points whose case the least-squares solver solves
    alone from several starts (:func:`sso.batch.batched.batchable`) are solved
    together, one :func:`sso.optimise_batch` call per shape; every other point is
    solved by :func:`sso.optimise` on its own.
    """
    accepted = np.zeros(len(chunk.indices), dtype=bool)
    tables = []
    if chunk.plan is not None:
        accepted[:] = True
        for axis, positions in zip(chunk.plan.axes, chunk.value_indices, strict=True):
            accepted &= axis.accepted[positions]
        if accepted.any():
            tables.append(run_array_points(
                chunk.plan, chunk.header, chunk.paths, chunk.indices[accepted],
                [positions[accepted] for positions in chunk.value_indices], chunk.values))
    if not accepted.all():
        tables.append(RowTable.from_rows(chunk.header, _point_rows(chunk, ~accepted)))
    table = RowTable.concatenate(chunk.header, tables)
    sweep_hash = np.empty(table.length, dtype=object)
    sweep_hash[:] = chunk.sweep_hash
    table.columns[HASH_COLUMN] = sweep_hash
    return table


@dataclass(frozen=True)
class ChunkTask:
    """A chunk and what to make of its rows where it runs.

    Attributes
    ----------
    chunk : SweepChunk
    csv : bool
        Also make the rows' lines of ``sweep.csv``.
    parquet_schema : pyarrow.Schema or None
        Also make the rows' Parquet part, of this schema.
    """

    chunk: SweepChunk
    csv: bool = False
    parquet_schema: Any = None


@dataclass(frozen=True)
class ChunkOutput:
    """A chunk's rows, with their ``sweep.csv`` lines (UTF-8) and Parquet part when
    asked for: made in the worker, so the calling process only appends them."""

    table: RowTable
    csv: bytes = b""
    parquet_part: bytes | None = None


def run_chunk_task(task: ChunkTask) -> ChunkOutput:
    """The rows of the task's chunk (:func:`run_sweep_chunk`) and their output."""
    table = run_sweep_chunk(task.chunk)
    return chunk_output(table, task.csv, task.parquet_schema)


def chunk_output(table: RowTable, csv: bool, parquet_schema: Any) -> ChunkOutput:
    """``table`` with its ``sweep.csv`` lines and Parquet part, as asked for."""
    from sso.batch.parquet_output import part_data

    return ChunkOutput(table, table.csv_text().encode("utf-8") if csv else b"",
                       None if parquet_schema is None else part_data(table, parquet_schema))


def _point_rows(chunk: SweepChunk, selected: np.ndarray) -> list[dict[str, Any]]:
    """Rows of the selected points, each read as a case (see :func:`run_sweep_chunk`)."""
    batched = BatchedPoints(_optimise_row)
    rows = []
    for index, point in chunk.points(selected):
        row = PointRow({"point": index, **point})
        case = _parsed_case(row, index, chunk.document, point)
        if case is not None and chunk.action == "optimise" and batchable(case):
            batched.add(row, case)
        elif case is not None:
            row.fill(partial(_solve_row, case, chunk.action))
        rows.append(row)
    batched.solve()
    return [row.finish() for row in rows]


def run_point(index: int, document: dict[str, Any], point: dict[str, Any],
              action: str) -> dict[str, Any]:
    """The result row of one point: inputs, best RE, solver statuses, times.

    The point's case is checked like a case file (the same messages, naming the
    key and the allowed range). Never raises for a bad point: the error is
    recorded in the row's ``error`` column and its ``status`` is ``"failed"``.
    """
    row = PointRow({"point": index, **point})
    case = _parsed_case(row, index, document, point)
    if case is not None:
        row.fill(lambda: _solve_row(case, action))
    return row.finish()


def _parsed_case(row: PointRow, index: int, document: dict[str, Any],
                 point: dict[str, Any]) -> Any:
    """The point's case, checked like a case file, or None (an error row) if it is bad."""
    from sso.cases.schema import parse_case

    case = row.attempt(lambda: parse_case(point_document(document, point), f"point {index}"))
    if case is not None:
        row.notes[:0] = case.warnings
    return case


def _solve_row(case: Any, action: str) -> dict[str, Any]:
    if case.kind == "column":
        return column_row(case, action)
    return _optimise_row(case) if action == "optimise" else _evaluate_row(case)


def failed_rows(chunk: SweepChunk, error: BaseException) -> RowTable:
    """Rows for every point of a chunk whose task itself failed (a lost worker).

    Their status is ``"lost"``: a resumed sweep computes them again.
    """
    message = f"{type(error).__name__}: {error}"
    everything = np.ones(len(chunk.indices), dtype=bool)
    return RowTable.from_rows(chunk.header, [
        {"point": index, **point, "status": "lost", "error": message,
         HASH_COLUMN: chunk.sweep_hash} for index, point in chunk.points(everything)])


def _evaluate_row(case: Any) -> dict[str, Any]:
    series = case.series()
    evaluation = series.evaluate(case.input_speed_rpm, quadrature_rtol=case.quadrature_rtol,
                                 quadrature_atol=case.quadrature_atol)
    return design_columns(evaluation, series.beta_deg, series.phase_deg)


def _optimise_row(case: Any) -> dict[str, Any]:
    from sso.shafts.optimise import optimise

    result = optimise(case.series(), case.option, **case.optimise_options())
    row = {
        **design_columns(result.optimum, result.best_series.beta_deg,
                         result.best_series.phase_deg),
        "success": result.success,
        "best_solver": result.best.solver,
    }
    if result.crosscheck is not None:
        row["crosscheck_agree"] = result.crosscheck.agree
        row["crosscheck_objective_gap"] = result.crosscheck.objective_gap
    for name, solution in result.solutions.items():
        row.update(solver_columns(
            name, solution.fun, solution.status, solution.success, solution.message,
            solution.kkt, sum(run.time_s for run in result.runs if run.solver == name)))
    return row
