"""``sweep.csv`` and its manifest: columns, cell formats, appended chunks, resuming.

The CSV is appended to, never rewritten: each finished chunk adds its rows (in the
order the chunks finish) with one write and a flush to disk, so the cost of a
point does not grow with the sweep's size. A process killed in the middle of an
append leaves a last line without its end; a resumed run drops it (sso wrote it)
and computes that point again. The manifest ``sweep.json`` records what the sweep
is, with a hash of it that every row carries (``sweep_hash``); a resumed run checks
every row against the manifest (its point index, its axis values, its hash) and
refuses, naming the line and the reason, anything that does not belong.
"""

from __future__ import annotations

import csv
import hashlib
import io
import json
import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from sso._files import write_text_atomic
from sso._limits import SOLVERS
from sso._studies.element_columns import element_names, joint_count, list_shapes, value_shape
from sso._studies.row_checks import cell_problem, recheck_sample
from sso._validation import shown

SCHEMA_VERSION = 3
SCHEMA_CHANGE = ("each element of a list in a column of its own, design_beta_deg[0], ..., "
                 "where schema 2 held the whole list in one cell")
"""What the sweep files of :data:`SCHEMA_VERSION` hold that the version before did not."""
CSV_NAME = "sweep.csv"
MANIFEST_NAME = "sweep.json"
HASH_COLUMN = "sweep_hash"
SOLVER_FIELDS = ("residual_error", "status", "success", "kkt_per_rad", "time_s", "message")
RESULT_COLUMNS = (
    "status", "error", "residual_error", "residual_error_rpm2", "fluctuation",
    "max_output_accel_rad_s2", "design_beta_deg", "design_phase_deg", "success",
    "best_solver", "crosscheck_agree", "crosscheck_objective_gap",
    *(f"{solver}_{field}" for solver in SOLVERS for field in SOLVER_FIELDS),
    "time_s", "warnings",
)
COLUMN_RESULT_COLUMNS = (
    "status", "error", "residual_error", "minimum_residual_error", "can_cancel",
    "yoke_phase_deg", "design_beta_deg", "plane_angle_deg", "speed_fluctuation_percent",
    "torque_fluctuation_percent", "largest_transmission_error_deg",
    "transmission_error_peak_to_peak_deg", "on_centre_fluctuation_percent",
    "continuous_residual_error", "continuous_yoke_phase_deg", "tooth_offset", "success",
    "crosscheck_agree", "crosscheck_objective_gap", "joint_centres_residual_error",
    "joint_centres_points_mm", "joint_centres_margin_mm", "joint_centres_success",
    "tolerance_p95_residual_error", "robust_yoke_phase_deg", "robust_p95_residual_error",
    "time_s", "warnings",
)
"""The result columns of a sweep of a column case (:mod:`sso._studies.column_rows`)."""
TIME_COLUMNS = ("time_s", *(f"{solver}_time_s" for solver in SOLVERS))
TEXT_COLUMNS = ("status", "error", "best_solver", "warnings", HASH_COLUMN,
                *(f"{solver}_message" for solver in SOLVERS))
# Statuses of points that are done; a "lost" row (its worker died) is computed again.
DONE_STATUSES = ("ok", "failed")
STATUSES = (*DONE_STATUSES, "lost")
HASH_DIGITS = 16


def columns(axis_paths: Sequence[str], kind: str = "shaft_series") -> list[str]:
    """Header of ``sweep.csv``: point index, the axes, the results of a case of ``kind``
    (a shaft series', or a column's), the sweep's hash."""
    results = COLUMN_RESULT_COLUMNS if kind == "column" else RESULT_COLUMNS
    return ["point", *axis_paths, *results, HASH_COLUMN]


def sweep_columns(document: Mapping[str, Any], axes: Sequence[Any]) -> list[str]:
    """Header of a sweep's table over ``axes`` of the base case ``document``
    (:func:`columns`), every list spread over its elements
    (:mod:`sso._studies.element_columns`).

    Raises
    ------
    ValueError
        For an axis that mixes lists and single values
        (:func:`sso._studies.element_columns.value_shape`).
    """
    kind = document.get("kind", "shaft_series")
    shapes = {**list_shapes(kind, joint_count(document, axes)),
              **{axis.path: value_shape(axis.values, f"axis {shown(axis.path)}")
                 for axis in axes}}
    return [name for column in columns([axis.path for axis in axes], kind)
            for name in element_names(column, shapes.get(column, ()))]


def format_cell(value: Any) -> str:
    """One CSV cell: shortest round-trip floats, ``true``/``false``, text on one line (a
    list is never a cell: one column per element, :mod:`sso._studies.element_columns`)."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    # One line per row, so that a torn append is always a torn last line.
    return str(value).replace("\r", " ").replace("\n", " ")


def parse_cell(column: str, text: str) -> Any:
    """Inverse of :func:`format_cell` (text columns stay strings)."""
    if text == "":
        return None
    if column in TEXT_COLUMNS:
        return text
    if text in ("true", "false"):
        return text == "true"
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        return text


def format_row(row: Mapping[str, Any], header: Sequence[str]) -> dict[str, str]:
    """A result row as CSV cells, one per column of ``header``."""
    return {column: format_cell(row.get(column)) for column in header}


def render_rows(header: Sequence[str], rows: Iterable[Mapping[str, str]]) -> str:
    """Text of a whole ``sweep.csv``: the header and the rows, sorted by point index."""
    return _render(header, sorted(rows, key=lambda row: int(row["point"])), with_header=True)


def _render(header: Sequence[str], rows: Iterable[Mapping[str, str]],
            with_header: bool) -> str:
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(header), lineterminator="\n")
    if with_header:
        writer.writeheader()
    writer.writerows(rows)
    return buffer.getvalue()


def start_file(path: Path, header: Sequence[str]) -> None:
    """Create ``sweep.csv`` holding its header alone, unless it exists."""
    if not path.exists():
        write_text_atomic(path, _render(header, (), with_header=True))


def append_rows(path: Path, text: str | bytes) -> None:
    """Append rows (lines of ``sweep.csv``, or their UTF-8 bytes) in one write, flushed
    to disk."""
    data = text.encode("utf-8") if isinstance(text, str) else text
    descriptor = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_NOFOLLOW)
    try:
        view = memoryview(data)
        while view:
            view = view[os.write(descriptor, view):]
        os.fsync(descriptor)
    finally:
        os.close(descriptor)


def read_rows(path: Path) -> list[dict[str, str]]:
    """Rows of a ``sweep.csv`` as text cells, in file order."""
    with open(path, newline="", encoding="utf-8") as handle:
        return list(csv.DictReader(handle))


def typed_rows(rows: Iterable[Mapping[str, str]]) -> list[dict[str, Any]]:
    """Text rows with their cells parsed back to numbers, booleans and lists."""
    return [{column: parse_cell(column, text) for column, text in row.items()} for row in rows]


def manifest(document: Mapping[str, Any], axes: Sequence[Any], mode: str, action: str,
             point_count: int) -> dict[str, Any]:
    """What identifies a sweep (compared on ``resume``), with its hash."""
    identity = {
        "schema_version": SCHEMA_VERSION,
        "case": dict(document),
        "axes": [{"path": axis.path, "values": list(axis.values)} for axis in axes],
        "mode": mode,
        "action": action,
        "points": point_count,
    }
    text = json.dumps(identity, sort_keys=True, separators=(",", ":"))
    return {**identity, HASH_COLUMN: hashlib.sha256(text.encode("utf-8")).hexdigest()[:HASH_DIGITS]}


def done_rows(out_dir: Path, expected_manifest: Mapping[str, Any], header: Sequence[str],
              axis_cells: Callable[[int], list[str]],
              recheck: Callable[[int, Mapping[str, str]], str | None] | None = None,
              ) -> dict[int, dict[str, str]]:
    """Finished rows of an earlier run of the same sweep in ``out_dir``, by point.

    Every row is checked: its cells, its point index (in the sweep's range, done at
    most once), its axis values (those of its point), its ``sweep_hash`` (this
    sweep's) and the type and range of each figure
    (:func:`sso._studies.row_checks.cell_problem`); then a sample of the finished
    rows is computed again (``recheck``, :func:`sso._studies.row_checks.recheck_sample`).
    A last line without its end (an append cut short by a killed run) is removed
    from the file; its point is computed again. Nothing else in the file changes.

    Parameters
    ----------
    out_dir : pathlib.Path
    expected_manifest : mapping
        This sweep's manifest (:func:`manifest`).
    header : sequence of str
        This sweep's columns.
    axis_cells : callable
        Point index -> the formatted axis cells of that point.
    recheck : callable, optional
        ``recheck(point, row)``: what disagrees when the row's figures are computed
        again from its design, or None (None: no row is computed again).

    Raises
    ------
    ValueError
        If ``out_dir`` holds a different sweep, a CSV without its manifest, or a
        row that does not belong to this sweep or whose figures cannot be true (the
        message names the line and the field).
    """
    csv_path = out_dir / CSV_NAME
    manifest_path = out_dir / MANIFEST_NAME
    if not manifest_path.exists():
        if csv_path.exists():
            raise ValueError(f"resume: {csv_path} has no {MANIFEST_NAME} beside it, so it "
                             "cannot be checked against this sweep; use another out_dir")
        return {}
    try:
        found = json.loads(manifest_path.read_text(encoding="utf-8"))
    except (ValueError, OSError) as error:
        raise ValueError(f"resume: {manifest_path} is not a sweep manifest ({error}); use "
                         "another out_dir") from None
    expected = json.loads(json.dumps(expected_manifest))
    older = found.get("schema_version") if isinstance(found, dict) else None
    if isinstance(older, int) and not isinstance(older, bool) and older < SCHEMA_VERSION:
        raise ValueError(f"resume: {out_dir} holds a sweep written by an older sso (sweep "
                         f"schema {older}; this sso writes {SCHEMA_VERSION}, {SCHEMA_CHANGE}); "
                         "it cannot be resumed: run the sweep afresh in another out_dir")
    if not isinstance(found, dict) or found != expected:
        found = found if isinstance(found, dict) else {}
        differing = sorted(key for key in {*found, *expected}
                           if key != HASH_COLUMN and found.get(key) != expected.get(key))
        raise ValueError(f"resume: {out_dir} holds a different sweep (differs in "
                         f"{', '.join(differing) or HASH_COLUMN}); use another out_dir or "
                         "the same sweep")
    if not csv_path.exists():
        return {}
    rows, lines = _checked_rows(csv_path, header, expected[HASH_COLUMN], expected["points"],
                                axis_cells)
    if recheck is not None:
        disagreement = recheck_sample(rows, expected[HASH_COLUMN], recheck)
        if disagreement is not None:
            point, problem = disagreement
            raise ValueError(f"resume: {csv_path} line {lines[point]} (point {point}): "
                             f"{problem}; the file was changed after sso wrote it; use "
                             "another out_dir")
    return rows


class _GuardedReader:
    """A ``csv.reader`` whose errors (a cell beyond ``csv.field_size_limit()``, 131,072
    characters; a NUL) are a ValueError naming the file and the line."""

    def __init__(self, reader: Any, csv_path: Path) -> None:
        self._reader = reader
        self._path = csv_path

    @property
    def line_num(self) -> int:
        """Lines read so far (the csv reader's count)."""
        return int(self._reader.line_num)

    def __iter__(self) -> _GuardedReader:
        return self

    def __next__(self) -> list[str]:
        try:
            return list(next(self._reader))
        except csv.Error as error:
            if "field larger than field limit" in str(error):
                reason = (f"holds a cell longer than {csv.field_size_limit():,} characters, "
                          "which sso never writes")
            else:
                reason = f"cannot be read as CSV ({error})"
            raise ValueError(f"resume: {self._path} line {self._reader.line_num} {reason}: "
                             "the file is damaged or not this sweep's; use another out_dir, or "
                             "delete the folder to run the sweep afresh") from None


def _checked_rows(csv_path: Path, header: Sequence[str], sweep_hash: str, points: int,
                  axis_cells: Callable[[int], list[str]],
                  ) -> tuple[dict[int, dict[str, str]], dict[int, int]]:
    """The finished rows by point, and the line of each."""
    data = csv_path.read_bytes()
    if data and not data.endswith(b"\n"):
        kept = data.rfind(b"\n") + 1
        os.truncate(csv_path, kept)  # the torn end of our own last append
        data = data[:kept]
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as error:
        raise ValueError(f"resume: {csv_path} is not a sweep.csv written by sso ({error}); "
                         "use another out_dir") from None
    reader = _GuardedReader(csv.reader(io.StringIO(text, newline="")), csv_path)
    found_header = next(reader, None)
    if found_header != list(header):
        raise ValueError(f"resume: the columns of {csv_path} are not those of this sweep "
                         "(another sweep's file, or one written by an older sso); use "
                         "another out_dir")
    hash_at = len(header) - 1
    status_at = header.index("status")
    axes = slice(1, status_at)
    rows: dict[int, dict[str, str]] = {}
    lines: dict[int, int] = {}
    for cells in reader:
        line = reader.line_num
        where = f"resume: {csv_path} line {line}"
        if len(cells) != len(header):
            raise ValueError(f"{where} has {len(cells)} cells, not the {len(header)} of its "
                             "header: the file is damaged or not this sweep's; use another "
                             "out_dir")
        if cells[hash_at] != sweep_hash:
            raise ValueError(f"{where} belongs to another sweep ({HASH_COLUMN} "
                             f"{cells[hash_at]!r}, this sweep's is {sweep_hash!r}); use "
                             "another out_dir")
        point = cells[0]
        if not point.isdigit() or not 0 <= int(point) < points:
            raise ValueError(f"{where}: point {point!r} is outside this sweep's points "
                             f"[0, {points - 1}]")
        index = int(point)
        if cells[axes] != axis_cells(index):
            raise ValueError(f"{where}: point {index} has axis values {cells[axes]}, this "
                             f"sweep's point {index} has {axis_cells(index)}")
        status = cells[status_at]
        if status not in STATUSES:
            raise ValueError(f"{where}: status {status!r} is not one of {', '.join(STATUSES)}")
        earlier = rows.get(index)
        if earlier is not None and earlier["status"] in DONE_STATUSES:
            raise ValueError(f"{where}: point {index} is there twice; the file is damaged "
                             "or merged from two runs; use another out_dir")
        for column, text in zip(header[status_at + 1:hash_at], cells[status_at + 1:hash_at],
                                strict=True):
            problem = cell_problem(column, text, status)
            if problem is not None:
                raise ValueError(f"{where} (point {index}): {problem}; the file was changed "
                                 "after sso wrote it; use another out_dir")
        rows[index] = dict(zip(header, cells, strict=True))
        lines[index] = line
    done = {index: row for index, row in rows.items() if row["status"] in DONE_STATUSES}
    return done, lines
