"""A sweep's rows as columns: one array per column, never one dict per point.

A chunk's rows travel from a worker as a :class:`RowTable`, the calling process
appends its CSV text to ``sweep.csv`` (and its Parquet part) and concatenates the
tables; a row becomes a dict only when a user asks for it. Every cell means what
the same cell of ``sweep.csv`` means (:func:`sso.batch.table.format_cell`): a
float column's NaN is an empty cell (no value), an object column holds the
values as they are (``None`` or ``""`` empty), and a 2-D float column holds a list per row
(``design_beta_deg``; a row of NaN is empty). A column missing from the table is
empty in every row.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from sso.batch.table import TEXT_COLUMNS, format_cell

_NEEDS_QUOTES = (",", '"', "\n", "\r")


@dataclass(frozen=True)
class RowTable:
    """Rows of a sweep as columns.

    Attributes
    ----------
    header : tuple of str
        Every column of ``sweep.csv``, in order.
    columns : dict of str to numpy.ndarray
        The columns that hold a value in some row, each of length ``length``
        (float64, int64, bool or object; 2-D float64 for a list per row).
    length : int
        Rows.
    """

    header: tuple[str, ...]
    columns: dict[str, np.ndarray]
    length: int

    @classmethod
    def from_rows(cls, header: Sequence[str], rows: Sequence[Mapping[str, Any]]) -> RowTable:
        """The table of some rows (dicts of cell values, as a point's row holds them)."""
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
        return "".join(",".join(row) + "\n" for row in zip(*cells, strict=False))


def _column(name: str, values: list[Any]) -> np.ndarray:
    """The best array for one column's values (object when the kinds mix)."""
    present = [value for value in values if value is not None]
    if name not in TEXT_COLUMNS:
        if all(isinstance(value, float) for value in present):
            return np.array([np.nan if value is None else value for value in values],
                            dtype=float)
        if len(present) == len(values) and all(
                isinstance(value, int) and not isinstance(value, bool) for value in values):
            return np.array(values, dtype=np.int64)
        lists = [value for value in present if isinstance(value, (list, tuple))]
        if (lists and len(lists) == len(present) and len({len(value) for value in lists}) == 1
                and len(lists[0]) > 0
                and all(isinstance(item, float) for value in lists for item in value)):
            width = len(lists[0])
            return np.array([[np.nan] * width if value is None else list(value)
                             for value in values], dtype=float).reshape(len(values), width)
    column = np.empty(len(values), dtype=object)
    column[:] = values
    return column


def _value(column: np.ndarray, index: int) -> Any:
    """Cell ``index`` of a column as a Python value (``None`` where empty)."""
    value = column[index]
    if column.dtype == object:
        return None if value == "" else value  # an empty cell, as sweep.csv reads back
    if column.ndim == 2:
        items: list[float] = value.tolist()
        return None if items and items[0] != items[0] else items
    if column.dtype.kind == "f":
        number = float(value)
        return None if number != number else number
    return value.item()


def _cells(column: np.ndarray) -> list[str]:
    """A column's CSV cells (quoted where :mod:`csv` quotes them)."""
    if column.dtype == object:
        return [_quoted(format_cell(value)) for value in column.tolist()]
    if column.ndim == 2:
        if not column.shape[1]:
            return ["[]"] * len(column)
        mark = '"' if column.shape[1] > 1 else ""  # a list of two or more holds a comma
        return [f"{mark}[{', '.join(map(repr, row))}]{mark}" if row[0] == row[0] else ""
                for row in column.tolist()]
    if column.dtype.kind == "f":
        return [repr(value) if value == value else "" for value in column.tolist()]
    if column.dtype.kind == "b":
        return ["true" if value else "false" for value in column.tolist()]
    return [str(value) for value in column.tolist()]


def _quoted(cell: str) -> str:
    if any(mark in cell for mark in _NEEDS_QUOTES):
        return '"' + cell.replace('"', '""') + '"'
    return cell
