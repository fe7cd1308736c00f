"""A saved sweep's rows checked as ``--resume`` checks the rows it keeps.

``sso report`` of a :class:`sso.SweepResult` saved by :func:`sso.write_report` renders
its rows; none is rendered whose figures cannot be true, or whose RE is not that of
its design (:mod:`sso._studies.row_checks`).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from sso._record import RecordError
from sso._studies.element_columns import gathered
from sso._studies.row_checks import cell_problem, recheck_row, recheck_sample
from sso._studies.table import HASH_COLUMN, format_row, sweep_columns


def check_saved_rows(result: Any) -> None:
    """Refuse a saved sweep (:class:`sso.SweepResult` read back from ``result.json``)
    whose rows' figures cannot be true: every row's cells checked as ``--resume``
    checks them (:func:`cell_problem`), and ``RECHECKED_ROWS`` finished rows, drawn
    by the sweep's hash, computed again from their design (:func:`recheck_row`; needs
    the sweep's manifest, which names its base case).

    Raises
    ------
    sso._record.RecordError
        Naming the row (its position and point) and the field.
    """
    header = saved_columns(result)
    known = set(header)
    status_at = header.index("status")
    texts: dict[int, dict[str, str]] = {}
    positions: dict[int, int] = {}
    for position, row in enumerate(result.rows):
        unknown = [name for name in row if name not in known]
        if unknown:
            name = unknown[0]
            reason = (f"holds a list; a sweep's rows hold each element in a column of its own "
                      f"({name}[0], {name}[1], ...), so this sweep was saved by an older sso: "
                      "run it again" if isinstance(row[name], list)
                      else "is not a column of this sweep")
            raise RecordError(f"rows[{position}].{name} {reason}")
        cells = format_row(row, header)
        status = cells["status"]
        for column in header[status_at + 1:-1]:
            problem = cell_problem(column, cells[column], status)
            if problem is not None:
                raise RecordError(f"rows[{position}] (point {cells['point']}): {problem}")
        if cells["point"].isdigit():
            texts[int(cells["point"])] = cells
            positions[int(cells["point"])] = position
    document, sweep_hash = result.manifest.get("case"), result.manifest.get(HASH_COLUMN)
    if not isinstance(document, dict) or not isinstance(sweep_hash, str) \
            or not all(character in "0123456789abcdef" for character in sweep_hash):
        return

    def recheck(point: int, cells: Mapping[str, str]) -> str | None:
        row = result.rows[positions[point]]
        return recheck_row(document, {axis.path: gathered(row, axis.path)
                                      for axis in result.axes}, cells)

    disagreement = recheck_sample(texts, sweep_hash, recheck)
    if disagreement is not None:
        point, problem = disagreement
        raise RecordError(f"rows[{positions[point]}] (point {point}): {problem}")


def saved_columns(result: Any) -> list[str]:
    """The columns of a sweep's rows (:func:`sso._studies.table.sweep_columns` of its
    manifest's base case and its axes)."""
    document = result.manifest.get("case")
    return sweep_columns(document if isinstance(document, dict) else {}, result.axes)
