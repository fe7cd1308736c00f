"""``sweep.csv`` and its manifest: columns, cell formats, atomic writes, resuming.

The CSV holds one row per finished point, sorted by point index, and is rewritten
atomically (temporary file, then ``os.replace``) each time a chunk finishes, so an
interrupted sweep leaves a complete file of the points done so far. The manifest
``sweep.json`` records what the sweep is, so that a resumed run can check it
continues the same sweep.
"""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from sso.files import write_text_atomic
from sso.limits import SOLVERS

SCHEMA_VERSION = 1
CSV_NAME = "sweep.csv"
MANIFEST_NAME = "sweep.json"
SOLVER_FIELDS = ("residual_error", "status", "success", "kkt_per_rad", "time_s", "message")
RESULT_COLUMNS = (
    "status", "error", "residual_error", "residual_error_rpm2", "fluctuation",
    "max_output_accel_rad_s2", "design_beta_deg", "design_phase_deg", "success",
    "best_solver", "crosscheck_agree", "crosscheck_objective_gap",
    *(f"{solver}_{field}" for solver in SOLVERS for field in SOLVER_FIELDS),
    "time_s", "warnings",
)
TIME_COLUMNS = ("time_s", *(f"{solver}_time_s" for solver in SOLVERS))
TEXT_COLUMNS = ("status", "error", "best_solver", "warnings",
                *(f"{solver}_message" for solver in SOLVERS))
# Solvers whose columns a sweep.csv written before they could be swept lacks; such a
# file still resumes (their cells stay empty in its earlier rows).
ADDED_SOLVERS = ("lm",)
# Statuses of points that are done; any other row (a lost worker) is computed again.
DONE_STATUSES = ("ok", "failed")


def columns(axis_paths: Sequence[str]) -> list[str]:
    """Header of ``sweep.csv``: point index, the axes, then the results."""
    return ["point", *axis_paths, *RESULT_COLUMNS]


def format_cell(value: Any) -> str:
    """One CSV cell: shortest round-trip floats, JSON lists, ``true``/``false``."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, (list, tuple)):
        return json.dumps(list(value))
    return str(value)


def parse_cell(column: str, text: str) -> Any:
    """Inverse of :func:`format_cell` (text columns stay strings)."""
    if text == "":
        return None
    if column in TEXT_COLUMNS:
        return text
    if text in ("true", "false"):
        return text == "true"
    try:
        return json.loads(text) if text.startswith("[") else int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        return text


def format_row(row: Mapping[str, Any], header: Sequence[str]) -> dict[str, str]:
    """A result row as CSV cells, one per column of ``header``."""
    return {column: format_cell(row.get(column)) for column in header}


def write_rows(path: Path, header: Sequence[str], rows: Iterable[Mapping[str, str]]) -> None:
    """Write formatted rows, sorted by point index, atomically."""
    write_text_atomic(path, render_rows(header, rows))


def render_rows(header: Sequence[str], rows: Iterable[Mapping[str, str]]) -> str:
    """Text of ``sweep.csv``: the header and the formatted rows, sorted by point index."""
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(header), lineterminator="\n")
    writer.writeheader()
    writer.writerows(sorted(rows, key=lambda row: int(row["point"])))
    return buffer.getvalue()


def read_rows(path: Path) -> list[dict[str, str]]:
    """Rows of a ``sweep.csv`` as text cells."""
    with open(path, newline="", encoding="utf-8") as handle:
        return list(csv.DictReader(handle))


def typed_rows(rows: Iterable[Mapping[str, str]]) -> list[dict[str, Any]]:
    """Text rows with their cells parsed back to numbers, booleans and lists."""
    return [{column: parse_cell(column, text) for column, text in row.items()} for row in rows]


def manifest(document: Mapping[str, Any], axes: Sequence[Any], mode: str, action: str,
             point_count: int) -> dict[str, Any]:
    """What identifies a sweep (compared on ``resume``)."""
    return {
        "schema_version": SCHEMA_VERSION,
        "case": dict(document),
        "axes": [{"path": axis.path, "values": list(axis.values)} for axis in axes],
        "mode": mode,
        "action": action,
        "points": point_count,
    }


def done_rows(out_dir: Path, expected_manifest: Mapping[str, Any],
              header: Sequence[str]) -> dict[int, dict[str, str]]:
    """Finished rows of an earlier run of the same sweep in ``out_dir``, by point.

    Raises
    ------
    ValueError
        If ``out_dir`` holds a different sweep, or a CSV without its manifest.
    """
    csv_path = out_dir / CSV_NAME
    manifest_path = out_dir / MANIFEST_NAME
    if not manifest_path.exists():
        if csv_path.exists():
            raise ValueError(f"resume: {csv_path} has no {MANIFEST_NAME} beside it, so it "
                             "cannot be checked against this sweep; use another out_dir")
        return {}
    found = json.loads(manifest_path.read_text(encoding="utf-8"))
    if found != json.loads(json.dumps(expected_manifest)):
        differing = sorted(key for key in {*found, *expected_manifest}
                           if found.get(key) != json.loads(json.dumps(expected_manifest.get(key))))
        raise ValueError(f"resume: {out_dir} holds a different sweep (differs in "
                         f"{', '.join(differing)}); use another out_dir or the same sweep")
    if not csv_path.exists():
        return {}
    rows = read_rows(csv_path)
    earlier = [column for column in header
               if not column.startswith(tuple(f"{solver}_" for solver in ADDED_SOLVERS))]
    if rows and list(rows[0]) not in (list(header), earlier):
        raise ValueError(f"resume: the columns of {csv_path} are not those of this sweep")
    return {int(row["point"]): row for row in rows if row["status"] in DONE_STATUSES}
