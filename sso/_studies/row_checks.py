"""Whether a row of ``sweep.csv`` kept on ``resume`` can be true: its cells' types and
ranges, and a sample of rows whose figures are computed again from their design.

A resumed sweep builds its summary and report from the rows it keeps, so a row
whose point, axis values and hash match but whose figures were edited (an RE of -5,
``nan``, ``success = maybe``) would be reported as found. Every kept row's cells are
checked against the rules below; then :data:`RECHECKED_ROWS` of the finished rows,
drawn by a generator seeded with the sweep's hash (the same rows for the same file),
have their RE computed again from the design the row holds (the closed form or
quadrature of a shaft series; the chain matrix of a column) and compared by the
solvers' agreement rule (:func:`sso._solvers.crosscheck.allowed_objective_gap`:
``1e-14 + 1e-6 * |RE|``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from sso._solvers.crosscheck import allowed_objective_gap
from sso._studies.element_columns import base_name, gathered

RECHECKED_ROWS = 8
"""Finished rows of a resumed sweep whose RE is computed again (all of them, if fewer)."""

_BOOLEAN = ("success", "crosscheck_agree", "can_cancel", "joint_centres_success")
_INTEGER_SUFFIXES = ("_status",)
_NON_NEGATIVE_SUFFIXES = ("residual_error", "residual_error_rpm2", "fluctuation",
                          "max_output_accel_rad_s2", "kkt_per_rad", "time_s",
                          "objective_gap", "_percent", "transmission_error_deg",
                          "peak_to_peak_deg")
# Lists, one column per element (sso._studies.element_columns): each element a finite
# number, a tooth offset a whole number.
_LISTS = ("design_beta_deg", "design_phase_deg", "yoke_phase_deg", "plane_angle_deg",
          "continuous_yoke_phase_deg", "joint_centres_points_mm", "robust_yoke_phase_deg")
_WHOLE_LISTS = ("tooth_offset",)
_FINITE = ("joint_centres_margin_mm",)
# The cells every finished ("ok") row has, whatever the kind of its sweep.
_REQUIRED = ("residual_error", "design_beta_deg[0]")


def cell_problem(column: str, text: str, status: str) -> str | None:
    """What is wrong with the cell ``text`` of ``column`` in a row of ``status``, or None.

    Empty cells are allowed (a failed row, a solver not run), except the figures
    every finished row holds (:data:`_REQUIRED`).
    """
    if text == "":
        return (f"{column} is empty; a finished row holds it" if status == "ok"
                and column in _REQUIRED else None)
    if column in _BOOLEAN or column.endswith("_success"):
        return None if text in ("true", "false") else f"{column} = {text!r} is not true or false"
    if column.endswith(_INTEGER_SUFFIXES) or base_name(column) in _WHOLE_LISTS:
        return None if _is_integer(text) else f"{column} = {_short(text)} is not a whole number"
    if column in _FINITE or base_name(column) in _LISTS or column.endswith(_NON_NEGATIVE_SUFFIXES):
        value = _float(text)
        if value is None or not math.isfinite(value):
            return f"{column} = {_short(text)} is not a finite number"
        if column.endswith(_NON_NEGATIVE_SUFFIXES) and value < 0.0:
            return f"{column} = {_short(text)} is negative; it is >= 0"
    return None


Recheck = Callable[[int, Mapping[str, str]], str | None]


def recheck_sample(rows: Mapping[int, Mapping[str, str]], sweep_hash: str,
                   recheck: Recheck) -> tuple[int, str] | None:
    """The first disagreement among :data:`RECHECKED_ROWS` finished rows, or None.

    Parameters
    ----------
    rows : mapping of int to mapping
        Kept rows by point (text cells).
    sweep_hash : str
        The sweep's hash (hexadecimal): it seeds which rows are drawn.
    recheck : callable
        ``recheck(point, row)``: what disagrees in that row, or None.

    Returns
    -------
    (int, str) or None
        The point and what disagrees.
    """
    finished = np.array(sorted(point for point, row in rows.items() if row["status"] == "ok"),
                        dtype=np.int64)
    generator = np.random.default_rng(int(sweep_hash, 16))
    chosen = generator.choice(finished, size=min(RECHECKED_ROWS, len(finished)), replace=False)
    for point in sorted(int(value) for value in chosen):
        problem = recheck(point, rows[point])
        if problem is not None:
            return point, problem
    return None


def recheck_row(document: Mapping[str, Any], point: Mapping[str, Any],
                row: Mapping[str, str]) -> str | None:
    """Whether ``row``'s RE is that of the design it holds, computed again.

    Parameters
    ----------
    document : mapping
        The sweep's base case.
    point : mapping
        The point's axis values (case key -> value).
    row : mapping
        The row's text cells.

    Returns
    -------
    str or None
        The field that disagrees, the saved and computed values and the tolerance.
    """
    from sso._cases.schema import CaseError, parse_case
    from sso._studies.axes import point_document

    try:
        case = parse_case(point_document(document, point), "resumed point")
    except (CaseError, ValueError) as error:
        return f"its point is not a valid case ({error}), yet its status is ok"
    saved = float(row["residual_error"])
    computed = (_column_re(case, row) if case.kind == "column" else _series_re(case, row))
    if isinstance(computed, str):
        return computed
    allowed = allowed_objective_gap((saved, computed))
    if abs(saved - computed) <= allowed:
        return None
    return (f"residual_error = {saved!r} is not the RE of the row's design, computed "
            f"again: {computed!r} (allowed difference {allowed:.3g}: 1e-14 + 1e-6 * |RE|)")


def _series_re(case: Any, row: Mapping[str, str]) -> float | str:
    from sso._shafts.series import ShaftSeries

    beta_deg, phase_deg = _list_of(row, "design_beta_deg"), _list_of(row, "design_phase_deg")
    try:
        series = ShaftSeries(beta_deg, phase_deg, case.model)
    except (TypeError, ValueError) as error:
        return f"design_beta_deg, design_phase_deg: not a design of this case ({error})"
    evaluation = series.evaluate(case.input_speed_rpm, quadrature_rtol=case.quadrature_rtol,
                                 quadrature_atol=case.quadrature_atol)
    return float(evaluation.residual_error)


def _column_re(case: Any, row: Mapping[str, str]) -> float | str:
    from sso._column.chain_matrix import residual_error

    geometry = case.geometry()
    yoke_phase_deg = _list_of(row, "yoke_phase_deg")
    if len(yoke_phase_deg) != geometry.joint_count - 1 or None in yoke_phase_deg:
        return (f"yoke_phase_deg = {yoke_phase_deg}: not one phasing per intermediate "
                f"shaft ({geometry.joint_count - 1})")
    return float(residual_error(np.radians(geometry.beta_deg),
                                np.radians(geometry.phase_deg_from_yoke(yoke_phase_deg))))


def _is_integer(text: str) -> bool:
    body = text[1:] if text.startswith("-") else text
    return body.isdigit() and body.isascii()


def _float(text: str) -> float | None:
    try:
        return float(text)
    except ValueError:
        return None


def _list_of(row: Mapping[str, str], name: str) -> list[Any]:
    """The list ``name`` of a row of text cells, from its element columns (None where
    an element is empty or not a number)."""
    prefix = name + "["
    value = gathered({column: _float(text) for column, text in row.items()
                      if column.startswith(prefix)}, name)
    return value if isinstance(value, list) else []


def _short(text: str) -> str:
    return repr(text if len(text) <= 60 else text[:57] + "...")

