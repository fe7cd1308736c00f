"""What a worker process runs: one chunk of sweep points, one row per point.

The functions here are top-level and take plain data, so a spawned process or a
Dask worker can import and run them. Each process builds the CasADi NLP of a
shape once (the per-thread cache of :mod:`sso._solvers.nlp`) and reuses it for
every point of that shape it is given.
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from functools import cached_property, partial
from typing import Any

import numpy as np

from sso._cases.schema import parse_case
from sso._shafts.optimise import optimise
from sso._studies.array_engine import ArrayPlan, run_array_points
from sso._studies.axes import Axis, point_document
from sso._studies.axis_checks import chunk_axes
from sso._studies.batched import BatchedPoints, batchable
from sso._studies.column_rows import column_row
from sso._studies.columns import RowTable, packed, unpacked
from sso._studies.element_columns import flat_row
from sso._studies.parquet_output import part_data
from sso._studies.point_row import PointRow, design_columns, solver_columns
from sso._studies.shared_rows import SharedLayout, write_rows
from sso._studies.table import HASH_COLUMN, sweep_columns

ACTIONS = ("optimise", "evaluate")


@dataclass(frozen=True)
class GridPositions:
    """Where the points of a sweep's chunk find their axis values, from their indices.

    Attributes
    ----------
    mode : {"product", "listed"}
        The sweep's mode.
    lengths : tuple of int
        Values of each axis of the sweep.
    lows : tuple of int
        Per axis, the position in the sweep's axis of the chunk's first value.
    """

    mode: str
    lengths: tuple[int, ...]
    lows: tuple[int, ...]

    def of(self, indices: np.ndarray) -> tuple[np.ndarray, ...]:
        """Per axis, the position of each point's value among the chunk's values."""
        if self.mode == "listed":
            return tuple(indices - low for low in self.lows)
        return tuple(position - low for position, low in
                     zip(np.unravel_index(indices, self.lengths), self.lows, strict=True))


@dataclass(frozen=True)
class SweepChunk:
    """A unit of work: some points of one sweep.

    A chunk travels to a worker as its point indices (consecutive ones as their
    first and count) and the rule that gives each point's axis values
    (:class:`GridPositions`), so its size does not grow with its points.

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
    values : tuple of tuple
        Per axis, the values this chunk's points take (a slice of the axis).
    plan : ArrayPlan or None
        The array engine's plan (:mod:`sso._studies.array_engine`); None where every
        point is read and solved on its own.
    sweep_hash : str
        The sweep's hash, written into every row.
    positions : GridPositions or tuple of numpy.ndarray
        Where each point finds its value in ``values``: the sweep's rule, or per
        axis the positions themselves.
    """

    document: dict[str, Any]
    action: str
    header: tuple[str, ...]
    paths: tuple[str, ...]
    indices: np.ndarray
    values: tuple[tuple[Any, ...], ...]
    plan: ArrayPlan | None
    sweep_hash: str
    positions: GridPositions | tuple[np.ndarray, ...]

    @classmethod
    def listed(cls, document: dict[str, Any], action: str,
               points: tuple[tuple[int, dict[str, Any]], ...], sweep_hash: str = "",
               plan: ArrayPlan | None = None) -> SweepChunk:
        """A chunk of the given ``(index, {path: value})`` points (the same paths each)."""
        paths = tuple(points[0][1]) if points else ()
        count = len(points)
        values = tuple(tuple(point[path] for _, point in points) for path in paths)
        header = sweep_columns(document, [Axis(path, axis_values)
                                          for path, axis_values in zip(paths, values,
                                                                       strict=True)])
        return cls(document, action, tuple(header), paths,
                   np.array([index for index, _ in points], dtype=np.int64),
                   values, plan, sweep_hash, tuple(np.arange(count) for _ in paths))

    @cached_property
    def value_indices(self) -> tuple[np.ndarray, ...]:
        """Per axis, the position of each point's value in ``values``."""
        if isinstance(self.positions, GridPositions):
            return self.positions.of(self.indices)
        return self.positions

    def __reduce__(self) -> tuple[Any, tuple[Any, ...]]:
        """Pickle the fields, the point indices packed (:func:`sso._studies.columns.packed`)."""
        return _unpack_chunk, (packed(self.indices), {
            field.name: getattr(self, field.name) for field in fields(self)
            if field.name != "indices"})

    def points(self, selected: np.ndarray) -> list[tuple[int, dict[str, Any]]]:
        """``(index, {path: value})`` of the selected points (a boolean mask)."""
        positions = [index_array[selected].tolist() for index_array in self.value_indices]
        return [(index, {path: self.values[axis][position[row]]
                         for axis, (path, position) in enumerate(zip(self.paths, positions,
                                                                     strict=True))})
                for row, index in enumerate(self.indices[selected].tolist())]


def _unpack_chunk(indices: Any, others: dict[str, Any]) -> SweepChunk:
    return SweepChunk(indices=unpacked(indices), **others)


def run_sweep_chunk(chunk: SweepChunk) -> RowTable:
    """Rows of the chunk's points; a point that fails gives an error row.

    With a plan, the chunk's axis values are read as cases
    (:func:`sso._studies.axis_checks.chunk_axes`), and the points every axis value of
    which the case accepts are computed as arrays (:mod:`sso._studies.array_engine`);
    every other point is read as a case.
    Optimising such a point, the points whose case the least-squares solver solves
    alone from several starts (:func:`sso._studies.batched.batchable`) are solved
    together, one :func:`sso.optimise_batch` call per shape; every other point is
    solved by :func:`sso.optimise` on its own.
    """
    accepted = np.zeros(len(chunk.indices), dtype=bool)
    tables = []
    if chunk.plan is not None:
        axes = chunk_axes(chunk.plan.run, chunk.document, chunk.action, chunk.paths,
                          chunk.plan.targets, chunk.values, chunk.value_indices,
                          chunk.positions.lows if isinstance(chunk.positions, GridPositions)
                          else None)
        accepted[:] = True
        for axis, positions in zip(axes, chunk.value_indices, strict=True):
            accepted &= axis.accepted[positions]
        if accepted.any():
            tables.append(run_array_points(
                chunk.plan, axes, chunk.header, chunk.paths, chunk.indices[accepted],
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
    shared : SharedLayout or None
        Write the rows' number columns into this shared memory
        (:mod:`sso._studies.shared_rows`), from row ``row_offset`` on.
    row_offset : int
        The place of the chunk's first row among the sweep's computed rows.
    """

    chunk: SweepChunk
    csv: bool = False
    parquet_schema: Any = None
    shared: SharedLayout | None = None
    row_offset: int = 0


@dataclass(frozen=True)
class ChunkOutput:
    """A chunk's rows, with their ``sweep.csv`` lines (UTF-8) and Parquet part when
    asked for: made in the worker, so the calling process only appends them.

    Attributes
    ----------
    table : RowTable
        The rows (without their number columns when ``in_shared``).
    csv : bytes
    parquet_part : bytes or None
    in_shared : bool
        The number columns were written into the task's shared memory.
    failed : int
        Rows whose status is not ``"ok"``.
    """

    table: RowTable
    csv: bytes = b""
    parquet_part: bytes | None = None
    in_shared: bool = False
    failed: int = 0


def run_chunk_task(task: ChunkTask) -> ChunkOutput:
    """The rows of the task's chunk (:func:`run_sweep_chunk`) and their output."""
    table = run_sweep_chunk(task.chunk)
    output = chunk_output(table, task.csv, task.parquet_schema)
    rest = None if task.shared is None else write_rows(task.shared, task.row_offset, table)
    return output if rest is None else replace(output, table=rest, in_shared=True)


def chunk_output(table: RowTable, csv: bool, parquet_schema: Any) -> ChunkOutput:
    """``table`` with its ``sweep.csv`` lines and Parquet part, as asked for."""
    status = table.columns.get("status")
    return ChunkOutput(table, table.csv_text().encode("utf-8") if csv else b"",
                       None if parquet_schema is None else part_data(table, parquet_schema),
                       failed=table.length if status is None
                       else int(np.count_nonzero(status != "ok")))


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
    """The result row of one point: inputs, best RE, solver statuses, times (a list
    one cell per element, as a sweep's table holds it).

    The point's case is checked like a case file (the same messages, naming the
    key and the allowed range). Never raises for a bad point: the error is
    recorded in the row's ``error`` column and its ``status`` is ``"failed"``.
    """
    row = PointRow({"point": index, **point})
    case = _parsed_case(row, index, document, point)
    if case is not None:
        row.fill(lambda: _solve_row(case, action))
    return flat_row(row.finish())


def _parsed_case(row: PointRow, index: int, document: dict[str, Any],
                 point: dict[str, Any]) -> Any:
    """The point's case, checked like a case file, or None (an error row) if it is bad."""
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
