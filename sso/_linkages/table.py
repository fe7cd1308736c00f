"""The result table of a mechanism analysis: named columns with units."""

import csv
import io
import os
import re
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import numpy as np

from sso._display import Part, Readable, TextTable, format_number
from sso._limits import CSV_DIGITS
from sso._record import Record

# How a unit reads at the end of a column name (``"length"``: the links' unit).
UNIT_SUFFIXES = {"deg": "deg", "rad/s": "rad_s", "rad/s^2": "rad_s2", "length": "{length}",
                 "length/s": "{length}_s", "length/s^2": "{length}_s2"}


@dataclass(frozen=True, eq=False, repr=False)
class MechanismTable(Record, Readable):
    """Columns of equal length, one row per crank angle (or per case).

    Columns are read-only numpy arrays, reachable as ``table["name"]`` or
    ``table.name``. Tables compare by identity (arrays have no single truth
    value); compare columns with numpy.

    Attributes
    ----------
    name : str
        What was analysed, e.g. ``"four-bar"``.
    columns : dict of str to ndarray
        Column name to values, in display order.
    units : dict of str to str
        Column name to unit. ``"length"`` means the unit the link lengths were
        given in; ``""`` marks a dimensionless or boolean column.

    Raises
    ------
    ValueError
        If the columns differ in length, are not one-dimensional, or ``units``
        does not name exactly the columns.
    """

    name: str
    columns: dict[str, np.ndarray]
    units: dict[str, str]

    report_kind: ClassVar[str] = "mechanism_table"

    def __post_init__(self) -> None:
        columns = {key: np.array(values) for key, values in self.columns.items()}
        if list(self.units) != list(columns):
            raise ValueError(
                f"MechanismTable.units must name the columns {list(columns)} in order, "
                f"got {list(self.units)}"
            )
        lengths = {key: values.shape for key, values in columns.items()}
        if len(set(lengths.values())) > 1 or any(len(shape) != 1 for shape in lengths.values()):
            raise ValueError(
                f"MechanismTable.columns must be one-dimensional and of equal length, "
                f"got shapes {lengths}"
            )
        for values in columns.values():
            values.flags.writeable = False
        object.__setattr__(self, "columns", columns)
        object.__setattr__(self, "units", dict(self.units))

    def __getitem__(self, column: str) -> np.ndarray:
        try:
            return self.columns[column]
        except KeyError:
            raise KeyError(f"no column {column!r}; columns are {list(self.columns)}") from None

    def __getattr__(self, column: str) -> np.ndarray:
        # Only called when normal lookup fails; "columns" may be missing while unpickling.
        columns: dict[str, np.ndarray] = self.__dict__.get("columns", {})
        if column in columns:
            return columns[column]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {column!r}")

    def __len__(self) -> int:
        return len(next(iter(self.columns.values()), ()))

    def _repr_text(self) -> str:
        return (f"{self.name!r}, {len(self)} rows x {len(self.columns)} columns: "
                + ", ".join(self.columns))

    def _summary_parts(self) -> list[Part]:
        rows = []
        for column, values in self.columns.items():
            finite = values[np.isfinite(values)] if values.dtype.kind == "f" else values
            low, high = ((format_number(float(finite.min())), format_number(float(finite.max())))
                         if values.dtype.kind == "f" and len(finite) else ("", ""))
            rows.append((column, self.units[column] or "-", low, high))
        return [f"{self.name}: {len(self)} rows",
                TextTable(("column", "unit", "min", "max"), tuple(rows))]

    def unit_names(self, length_unit: str = "length") -> list[str]:
        """Column names that each end in their unit (``joint_a_x`` -> ``joint_a_x_mm``).

        Parameters
        ----------
        length_unit : str
            The unit the link lengths were given in (``"length"`` when unknown);
            anything but letters and digits becomes ``_`` (``"length units"`` ->
            ``joint_a_x_length_units``).
        """
        length = re.sub(r"[^A-Za-z0-9]+", "_", length_unit).strip("_") or "length"
        names = []
        for column, unit in self.units.items():
            suffix = UNIT_SUFFIXES.get(unit, "").format(length=length)
            names.append(column if not suffix or column.endswith(f"_{suffix}")
                         else f"{column}_{suffix}")
        return names

    def to_csv(self, path: str | os.PathLike[str]) -> Path:
        """Write the table as CSV, atomically, with a header of column names.

        Floats are written with 17 significant digits (round-trip exact); NaN
        is written as ``nan``, booleans as ``True``/``False``. The file is
        written to a temporary file in the same folder and renamed over
        ``path``, so an interrupted write never leaves a partial file.

        Parameters
        ----------
        path : str or path-like
            Destination file; its folder must exist.

        Returns
        -------
        pathlib.Path
            The path written.

        Raises
        ------
        OSError
            If the folder does not exist or is not writable.
        """
        path = Path(path)
        _write_text_atomically(path, self.csv_text())
        return path

    def csv_text(self, length_unit: str | None = None, digits: int = CSV_DIGITS) -> str:
        """The table as CSV text; by default exactly as :meth:`to_csv` writes it.

        Parameters
        ----------
        length_unit : str, optional
            Give it to end every column name in its unit (:meth:`unit_names`), as
            the reports do; by default the names are the table's own.
        digits : int
            Significant digits of the floats (17 round-trips exactly; reports use 6).
        """
        buffer = io.StringIO()
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(list(self.columns) if length_unit is None
                        else self.unit_names(length_unit))
        for row in zip(*self.columns.values(), strict=True):
            writer.writerow(_csv_cell(value, digits) for value in row)
        return buffer.getvalue()


def _csv_cell(value: np.generic, digits: int = CSV_DIGITS) -> str:
    if isinstance(value, np.bool_):
        return str(bool(value))
    return format(float(value), f".{digits}g")


def _write_text_atomically(path: Path, text: str) -> None:
    descriptor, temporary = tempfile.mkstemp(
        dir=path.parent, prefix=f".{path.name}.", suffix=".tmp"
    )
    try:
        with os.fdopen(descriptor, "w", encoding="utf-8", newline="") as handle:
            handle.write(text)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
