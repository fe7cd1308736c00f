"""``sweep.parquet``: a sweep's rows as Parquet, one part file appended per chunk.

A Parquet file cannot grow once written (its footer comes last), so the rows go
into a folder of parts, ``sweep.parquet/part-<first point>-<count>.parquet``, each
written atomically as its chunk finishes: a killed sweep leaves only whole parts,
and pandas, polars and pyarrow read the folder as one table. ``sweep.csv`` stays
the sweep's record (a resumed sweep checks its rows there); a resumed sweep writes
the rows it takes over as one part, after removing the parts it wrote before.
Every part has the same schema (:func:`arrow_schema`), whichever rows it holds.

pyarrow is imported only here, and only when Parquet output is asked for (the
``parquet`` extra installs it).
"""

from __future__ import annotations

import io
import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from sso._files import write_bytes_atomic
from sso._limits import SOLVERS
from sso._studies.columns import RowTable
from sso._studies.element_columns import base_name, flat_row, list_shapes
from sso._studies.table import TEXT_COLUMNS, format_cell

PARQUET_NAME = "sweep.parquet"
_PART = re.compile(r"^part-\d{12}-\d{12}(-resumed)?\.parquet$")
# Besides a shaft series' columns, those a column case's rows add
# (sso._studies.table.COLUMN_RESULT_COLUMNS).
_FLOAT_COLUMNS = ("residual_error", "residual_error_rpm2", "fluctuation",
                  "max_output_accel_rad_s2", "crosscheck_objective_gap", "time_s",
                  *(f"{solver}_{field}" for solver in SOLVERS
                    for field in ("residual_error", "kkt_per_rad", "time_s")),
                  "minimum_residual_error", "speed_fluctuation_percent",
                  "torque_fluctuation_percent", "largest_transmission_error_deg",
                  "transmission_error_peak_to_peak_deg", "on_centre_fluctuation_percent",
                  "continuous_residual_error", "joint_centres_residual_error",
                  "joint_centres_margin_mm", "tolerance_p95_residual_error",
                  "robust_p95_residual_error")
_FLAG_COLUMNS = ("success", "crosscheck_agree", *(f"{solver}_success" for solver in SOLVERS),
                 "can_cancel", "joint_centres_success")
_INTEGER_COLUMNS = ("point", *(f"{solver}_status" for solver in SOLVERS))
# Lists, one column per element: every list a row holds (sso._studies.element_columns).
_INTEGER_LISTS = ("tooth_offset",)
_FLOAT_LISTS = tuple(sorted({name for kind in ("shaft_series", "column")
                             for name in list_shapes(kind, 0)} - set(_INTEGER_LISTS)))


def pyarrow_module() -> Any:
    """pyarrow, or a ValueError saying how to install it."""
    try:
        import pyarrow
        import pyarrow.parquet  # noqa: F401  (the writer)
    except ImportError:
        raise ValueError("Parquet output needs pyarrow; install the 'parquet' extra "
                         "(pip install 'sso[parquet]')") from None
    return pyarrow


def arrow_schema(header: Sequence[str], axes: Sequence[Any]) -> Any:
    """The schema of every part: numbers, flags and text by column (a list one column
    per element, as in ``sweep.csv``).

    An axis column whose values are all numbers is a float column; any other holds
    each value as its ``sweep.csv`` cell (text).
    """
    pa = pyarrow_module()
    axis_values: dict[str, list[Any]] = {}
    for axis in axes:
        for value in axis.values:
            for name, element in flat_row({axis.path: value}).items():
                axis_values.setdefault(name, []).append(element)
    numeric_axes = {name for name, values in axis_values.items()
                    if all(isinstance(value, (int, float)) and not isinstance(value, bool)
                           for value in values)}
    fields = []
    for name in header:
        if name in _INTEGER_COLUMNS or base_name(name) in _INTEGER_LISTS:
            kind = pa.int64()
        elif (name in _FLOAT_COLUMNS or name in numeric_axes
              or base_name(name) in _FLOAT_LISTS):
            kind = pa.float64()
        elif name in _FLAG_COLUMNS:
            kind = pa.bool_()
        else:
            kind = pa.string()
        fields.append(pa.field(name, kind))
    return pa.schema(fields)


def arrow_table(table: RowTable, schema: Any) -> Any:
    """A :class:`RowTable` as a ``pyarrow.Table`` of ``schema`` (an empty cell null)."""
    pa = pyarrow_module()
    arrays = []
    for field in schema:
        column = table.columns.get(field.name)
        if column is None:
            arrays.append(pa.nulls(table.length, type=field.type))
        elif column.dtype.kind == "f":
            arrays.append(pa.array(column, type=field.type, mask=np.isnan(column)))
        elif column.dtype != object:
            arrays.append(pa.array(column, type=field.type))
        elif pa.types.is_string(field.type) and field.name not in TEXT_COLUMNS:
            arrays.append(pa.array([None if value is None else format_cell(value)
                                    for value in column.tolist()], type=field.type))
        else:  # an empty text is an empty cell, as sweep.csv reads back
            arrays.append(pa.array([None if value == "" else value for value in column.tolist()],
                                   type=field.type))
    return pa.Table.from_arrays(arrays, schema=schema)


def part_data(table: RowTable, schema: Any) -> bytes:
    """The bytes of a part file holding ``table``'s rows (in a worker, or here)."""
    import pyarrow.parquet as pq

    buffer = io.BytesIO()
    pq.write_table(arrow_table(table, schema), buffer)
    return buffer.getvalue()


def write_part(folder: Path, first_point: int, rows: int, data: bytes,
               resumed: bool = False) -> Path:
    """Write a new part of ``sweep.parquet`` atomically: ``data``
    (:func:`part_data`), the ``rows`` rows from point ``first_point`` on."""
    name = f"part-{first_point:012d}-{rows:012d}{'-resumed' if resumed else ''}.parquet"
    return write_bytes_atomic(folder / PARQUET_NAME / name, data)


def start_parts(folder: Path) -> None:
    """Make ``sweep.parquet`` an empty folder, removing only the parts sso wrote.

    Raises
    ------
    ValueError
        If it holds anything that is not a part sso writes.
    """
    parts = folder / PARQUET_NAME
    parts.mkdir(exist_ok=True)
    foreign = sorted(entry.name for entry in parts.iterdir()
                     if not (entry.is_file() and _PART.match(entry.name)))
    if foreign:
        raise ValueError(f"{parts} holds {', '.join(foreign[:5])}, which sso does not write; "
                         "choose another folder")
    for entry in parts.iterdir():
        entry.unlink()


def read_frame(folder: Path) -> Any:
    """Every part of ``folder/sweep.parquet`` as one ``pandas.DataFrame``, sorted by point."""
    import pyarrow.parquet as pq

    frame = pq.read_table(folder / PARQUET_NAME).to_pandas()
    return frame.sort_values("point", kind="stable").reset_index(drop=True)
