"""A sweep's rows as columns: one array per column, never one dict per point.

A chunk's rows travel from a worker as a :class:`RowTable` (pickled compactly:
an object column as codes into its distinct objects, see :meth:`RowTable.__reduce__`),
the calling process appends its CSV text to ``sweep.csv`` (and its Parquet part)
and places the table into the sweep's columns as it arrives
(:class:`TableAssembly`); a row becomes a dict only when a user asks for it. Every cell means what
the same cell of ``sweep.csv`` means (:func:`sso._studies.table.format_cell`): a
float column's NaN is an empty cell (no value), an object column holds the
values as they are (``None`` or ``""`` empty). A list is one column per element
(:mod:`sso._studies.element_columns`). A column missing from the table is empty in
every row.
"""

from __future__ import annotations

import ctypes
import itertools
import math
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from sso._studies.element_columns import flat_row
from sso._studies.table import TEXT_COLUMNS, format_cell

_NEEDS_QUOTES = (",", '"', "\n", "\r")
DISTINCT_SAMPLE = 1024
"""Values of a number column looked at to decide whether to write each distinct value
once (when they hold at most a quarter as many distinct values)."""


@dataclass(frozen=True)
class RowTable:
    """Rows of a sweep as columns.

    Attributes
    ----------
    header : tuple of str
        Every column of ``sweep.csv``, in order.
    columns : dict of str to numpy.ndarray
        The columns that hold a value in some row, each of length ``length``
        (float64, int64, bool or object).
    length : int
        Rows.
    """

    header: tuple[str, ...]
    columns: dict[str, np.ndarray]
    length: int

    @classmethod
    def from_rows(cls, header: Sequence[str], rows: Sequence[Mapping[str, Any]]) -> RowTable:
        """The table of some rows (dicts of cell values, as a point's row holds them;
        a list spread over its element columns, :func:`flat_row`).

        Raises
        ------
        ValueError
            If a row holds a list element that is not a column of ``header`` (a list
            longer than the sweep's columns allow).
        """
        known = set(header)
        flat_rows = []
        for row in rows:
            flat = flat_row(row)
            beyond = [] if flat is row else [name for name in flat
                                             if name not in known and name.endswith("]")]
            if beyond:
                raise ValueError(f"row of point {row.get('point')} holds "
                                 f"{', '.join(beyond[:3])}, beyond the sweep's columns")
            flat_rows.append(flat)
        rows = flat_rows
        columns: dict[str, np.ndarray] = {}
        for name in header:
            values = [row.get(name) for row in rows]
            if any(value is not None for value in values):
                columns[name] = _column(name, values)
        return cls(tuple(header), columns, len(rows))

    @classmethod
    def empty(cls, header: Sequence[str]) -> RowTable:
        """A table without rows."""
        return cls(tuple(header), {}, 0)

    @classmethod
    def concatenate(cls, header: Sequence[str], tables: Sequence[RowTable]) -> RowTable:
        """The rows of every table, in order (tables of other column types are joined as
        object columns)."""
        tables = [table for table in tables if table.length]
        if len(tables) == 1:
            return tables[0]
        if not tables:
            return cls.empty(header)
        length = sum(table.length for table in tables)
        columns = {}
        for name in header:
            parts = [table.columns.get(name) for table in tables]
            if all(part is None for part in parts):
                continue
            kinds = {(part.dtype, part.shape[1:]) for part in parts if part is not None}
            if len(kinds) == 1 and all(part is not None for part in parts):
                columns[name] = np.concatenate([part for part in parts if part is not None])
            else:
                columns[name] = np.concatenate([
                    table.object_column(name) for table in tables])
        return cls(tuple(header), columns, length)

    def __reduce__(self) -> tuple[Any, tuple[Any, ...]]:
        """Pickle compactly: a column of one value as that value, a chunk's point
        indices as their first, an object column as int32 codes into its distinct
        objects. A chunk's status, flags, messages and hash then unpickle
        in the calling process as one ``take`` (or one fill) instead of one object at
        a time, and its constant numbers (a time per point, a fixed phase) travel once."""
        return _unpack, (self.header, {name: packed(column)
                                       for name, column in self.columns.items()},
                         self.length)

    def sliced(self, start: int, stop: int) -> RowTable:
        """Rows ``start`` to ``stop - 1`` (views of the columns)."""
        return RowTable(self.header, {name: column[start:stop]
                                      for name, column in self.columns.items()},
                        stop - start)

    def take(self, indices: np.ndarray) -> RowTable:
        """The rows at ``indices``, in that order."""
        return RowTable(self.header, {name: column[indices]
                                      for name, column in self.columns.items()},
                        len(indices))

    def object_column(self, name: str) -> np.ndarray:
        """Column ``name`` as Python values (``None`` where empty), an object array."""
        column = self.columns.get(name)
        result = np.empty(self.length, dtype=object)
        if column is None:
            return result
        result[:] = [_value(column, index) for index in range(self.length)]
        return result

    def row(self, index: int) -> dict[str, Any]:
        """Row ``index`` as a dict of every column (the typed cells of ``sweep.csv``)."""
        return {name: (_value(self.columns[name], index) if name in self.columns else None)
                for name in self.header}

    def rows(self) -> Iterator[dict[str, Any]]:
        """Every row as a dict, in order."""
        return (self.row(index) for index in range(self.length))

    def csv_text(self) -> str:
        """The rows as lines of ``sweep.csv`` (no header), as :mod:`csv` writes them."""
        if not self.length:
            return ""
        cells = [_cells(self.columns[name]) if name in self.columns
                 else itertools.repeat("", self.length) for name in self.header]
        return "\n".join(map(",".join, zip(*cells, strict=False))) + "\n"


class TableAssembly:
    """The rows of a sweep's chunks, placed as each chunk arrives.

    Each chunk's rows have a known place (the chunks cover the points in order);
    the columns are allocated when the first chunk arrives and every chunk of the
    same columns (names, types and widths) is copied into its place, so the work of
    joining the chunks is spread over the run instead of following it. A chunk of
    other columns (an error row's text, say) is kept as it is and joined at the end.
    Columns a worker writes in place (``shared``, :mod:`sso._studies.shared_rows`)
    are the sweep's columns themselves: a chunk written there brings only its other
    columns, and nothing is copied.

    Parameters
    ----------
    header : sequence of str
        Every column, in order.
    lengths : sequence of int
        Rows of each chunk, in order.
    shared : mapping of str to numpy.ndarray, optional
        Columns of every row that workers write into.
    """

    def __init__(self, header: Sequence[str], lengths: Sequence[int],
                 shared: Mapping[str, np.ndarray] | None = None) -> None:
        self.header = tuple(header)
        self.offsets = np.concatenate([[0], np.cumsum(lengths, dtype=np.int64)]).tolist()
        self.shared = dict(shared or {})
        self.columns: dict[str, np.ndarray] | None = None
        self.placed = [False] * len(lengths)
        self.apart: dict[int, RowTable] = {}

    def place(self, index: int, table: RowTable, in_shared: bool = False) -> None:
        """Put chunk ``index``'s rows (``table``) in their place (``in_shared``: its
        shared columns are already there, ``table`` holds the others)."""
        start, stop = self.offsets[index], self.offsets[index + 1]
        if table.length != stop - start:
            raise ValueError(f"chunk {index} has {table.length} rows, not {stop - start}")
        written = self.shared if in_shared else {}
        if written:
            table = RowTable(table.header, {**table.columns, **{
                name: column[start:stop] for name, column in written.items()}}, table.length)
        if self.columns is None:
            self.columns = {name: written[name] if name in written else
                            np.empty((self.offsets[-1], *column.shape[1:]), dtype=column.dtype)
                            for name, column in table.columns.items()}
        if table.columns.keys() == self.columns.keys() and all(
                column.dtype == self.columns[name].dtype
                and column.shape[1:] == self.columns[name].shape[1:]
                for name, column in table.columns.items()):
            for name, column in table.columns.items():
                if written.get(name) is not self.columns[name]:
                    self.columns[name][start:stop] = column
            self.placed[index] = True
        else:
            self.apart[index] = table

    def table(self) -> RowTable:
        """Every placed chunk's rows, in order.

        Raises
        ------
        ValueError
            If a chunk was never placed.
        """
        missing = [index for index, placed in enumerate(self.placed)
                   if not placed and index not in self.apart]
        if missing:
            raise ValueError(f"chunks {missing[:5]} were never placed")
        whole = RowTable(self.header, self.columns or {}, self.offsets[-1])
        if not self.apart:
            return whole
        return RowTable.concatenate(self.header, [
            self.apart[index] if index in self.apart
            else whole.sliced(self.offsets[index], self.offsets[index + 1])
            for index in range(len(self.placed))])


def packed(column: np.ndarray) -> Any:
    """A column as it travels: ``("same", first row, rows)`` where every row holds the
    same bits (or, in an object column, the same object), ``("range", first, rows)``
    for consecutive whole numbers (a chunk's points), ``("codes", codes, distinct
    objects)`` for any other object column; any other column as it is."""
    if not len(column):
        return column
    if column.dtype != object:
        if (column.dtype == np.int64 and column.ndim == 1 and len(column) > 1
                and np.all(np.diff(column) == 1)):
            return "range", int(column[0]), len(column)
        raw = np.ascontiguousarray(column).view(np.uint8).reshape(len(column), -1)
        if np.array_equal(raw, np.broadcast_to(raw[0], raw.shape)):
            return "same", column[:1].copy(), len(column)
        return column
    if column.ndim != 1:
        return column
    column = np.ascontiguousarray(column)
    # An object array holds pointers to its objects: rows of one pointer hold one
    # object, found without touching an object (a text column of a million rows in a
    # millisecond; by value, True == 1 would also merge a flag and a number).
    pointers = np.frombuffer(memoryview(
        (ctypes.c_char * column.nbytes).from_address(column.ctypes.data)), dtype=np.uintp)
    if np.all(pointers == pointers[0]):
        return "same", column[:1].copy(), len(column)
    _, first, codes = np.unique(pointers, return_index=True, return_inverse=True)
    return "codes", codes.astype(np.int32).ravel(), column[first]


def _unpack(header: tuple[str, ...], columns: dict[str, Any], length: int) -> RowTable:
    return RowTable(header, {name: unpacked(column) for name, column in columns.items()},
                    length)


def unpacked(column: Any) -> np.ndarray:
    """The column :func:`packed` made ``column`` of (a column of one value as a
    read-only view of it)."""
    if not isinstance(column, tuple):
        kept: np.ndarray = column
        return kept
    kind, first, rest = column
    if kind == "same":  # read-only, one row seen ``rest`` times: nothing copied
        return np.broadcast_to(first, (rest, *first.shape[1:]))
    if kind == "range":
        return np.arange(first, first + rest, dtype=np.int64)
    taken: np.ndarray = rest[first]
    return taken


INT64_RANGE = (-(2**63), 2**63 - 1)
"""Whole numbers an int64 column holds; a column with any other keeps Python ints."""


def _column(name: str, values: list[Any]) -> np.ndarray:
    """The best array for one column's values (object when the kinds mix)."""
    present = [value for value in values if value is not None]
    if name not in TEXT_COLUMNS:
        if all(isinstance(value, float) for value in present):
            return np.array([np.nan if value is None else value for value in values],
                            dtype=float)
        if len(present) == len(values) and all(
                isinstance(value, int) and not isinstance(value, bool)
                and INT64_RANGE[0] <= value <= INT64_RANGE[1] for value in values):
            return np.array(values, dtype=np.int64)
    column = np.empty(len(values), dtype=object)
    column[:] = values
    return column


def _value(column: np.ndarray, index: int) -> Any:
    """Cell ``index`` of a column as a Python value (``None`` where empty)."""
    value = column[index]
    if column.dtype == object:
        return None if value == "" else value  # an empty cell, as sweep.csv reads back
    if column.dtype.kind == "f":
        number = float(value)
        return None if number != number else number
    return value.item()


def _cells(column: np.ndarray) -> list[str]:
    """A column's CSV cells (quoted where :mod:`csv` quotes them).

    Numbers are written by the ``repr`` of a whole list at once (each element's
    ``repr``, the shortest text that reads back to the same float, in C) and cut
    at its separators; a column of few distinct numbers (an axis, a design that
    was evaluated, a chunk's time per point) and text are formatted once per
    distinct value.
    """
    if column.dtype == object:
        return _object_cells(column.tolist())
    if not len(column):
        return []
    if column.dtype.kind == "b":
        flags: list[str] = np.where(column, "true", "false").tolist()
        return flags
    return _number_cells(column)


def _number_cells(column: np.ndarray) -> list[str]:
    """Cells of a 1-D number column; NaN: empty."""
    sample = column[:DISTINCT_SAMPLE]
    if len(column) > DISTINCT_SAMPLE and len(np.unique(_bits(sample))) * 4 <= len(sample):
        # Distinct by their bits: 0.0 and -0.0 are written apart, as repr writes them.
        _, first, where = np.unique(_bits(column), return_index=True, return_inverse=True)
        texts = np.empty(len(first), dtype=object)
        texts[:] = _number_cells(column[first])
        repeated: list[str] = texts[where.ravel()].tolist()
        return repeated
    cells = repr(column.tolist())[1:-1].split(", ")
    return _emptied(cells, np.isnan(column)) if column.dtype.kind == "f" else cells


def _bits(column: np.ndarray) -> np.ndarray:
    return column.view(np.int64) if column.dtype == np.float64 else column


def _emptied(cells: list[str], empty: np.ndarray) -> list[str]:
    """``cells`` with the cells where ``empty`` holds made empty (NaN: no value)."""
    for index in np.flatnonzero(empty).tolist():
        cells[index] = ""
    return cells


def _object_cells(values: list[Any]) -> list[str]:
    try:
        distinct = {_distinct(value): value for value in values}
    except TypeError:  # a value that cannot be a key (a dict an axis gave): one by one
        return [_quoted(format_cell(value)) for value in values]
    text = {key: _quoted(format_cell(value)) for key, value in distinct.items()}
    return [text[_distinct(value)] for value in values]


def _distinct(value: Any) -> tuple[Any, ...]:
    """A key that tells apart the values a cell writes apart: by type, and -0.0 from 0.0
    (equal, but written "-0.0" and "0.0")."""
    if type(value) is float and value == 0.0:
        return (float, value, math.copysign(1.0, value))
    return (type(value), value)


def _quoted(cell: str) -> str:
    if any(mark in cell for mark in _NEEDS_QUOTES):
        return '"' + cell.replace('"', '""') + '"'
    return cell
