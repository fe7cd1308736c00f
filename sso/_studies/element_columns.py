"""A sweep's lists as one column per element, named as the sweep's keys index a list.

A spreadsheet cannot use a cell holding a list, so every list a sweep's row holds (a
design's angles, a list-valued axis such as ``hardpoints.points_mm[2]``) is spread
over one column per element: ``design_beta_deg[0]``, ``design_beta_deg[1]``, ...; a
list of lists over ``name[i][j]``. ``sweep.csv``, ``sweep.parquet`` and the rows of a
:class:`sso.SweepResult` hold the same columns. The columns are known before any
point runs: a result list has one element per joint (or per intermediate shaft) of
the sweep's largest case (the base case, or the longest value of an axis that sets
the whole list of joints), an axis as many as its longest value; a row whose list is
shorter leaves the rest of its columns empty.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np

from sso._validation import shown

_ELEMENT = re.compile(r"^(?P<name>.*?)(?P<indices>(\[\d+\])+)$")
# Per case kind: the key whose list sets the joint count, and its entries beyond the joints.
_JOINTS_KEY = {"shaft_series": ("design", "beta_deg", 0), "column": ("hardpoints", "points_mm", 2)}


def element_names(name: str, shape: Sequence[int]) -> list[str]:
    """The columns of a list ``name`` of ``shape``: ``name[i]``, or ``name[i][j]``...,
    in row-major order; ``[name]`` itself for a shape ``()`` (not a list)."""
    names = [name]
    for size in shape:
        names = [f"{prefix}[{index}]" for prefix in names for index in range(size)]
    return names


def base_name(column: str) -> str:
    """The list a column is an element of (``design_beta_deg`` for
    ``design_beta_deg[2]``), or the column itself."""
    match = _ELEMENT.match(column)
    return column if match is None else match["name"]


def value_shape(values: Iterable[Any], where: str) -> tuple[int, ...]:
    """The smallest shape holding every value: ``()`` when none is a list, else the
    longest list's length followed by the shape of their items.

    Raises
    ------
    ValueError
        If lists and single values mix at one depth (``where`` names the values).
    """
    values = list(values)
    lists = [isinstance(value, list) for value in values]
    if not any(lists):
        return ()
    if not all(lists):
        raise ValueError(f"{where} mixes lists and single values ({shown(values[:4])}); a "
                         "sweep's table gives each element of a list its own column, so "
                         "the values must be all lists of the same depth, or none")
    items = [item for value in values for item in value]
    return (max(len(value) for value in values), *value_shape(items, where))


def joint_count(document: Mapping[str, Any], axes: Sequence[Any]) -> int:
    """The most joints of a sweep's points: of the base case, or of the longest value
    of an axis that sets the whole key of the joints (``design.beta_deg``, or a
    column's ``hardpoints.points_mm``)."""
    table, key, beyond = _JOINTS_KEY.get(str(document.get("kind")), _JOINTS_KEY["shaft_series"])
    whole = f"{table}.{key}"
    keys = document.get(table)
    lists = [keys.get(key) if isinstance(keys, dict) else None,
             *(value for axis in axes if axis.path == whole for value in axis.values)]
    return max([len(value) - beyond for value in lists if isinstance(value, list)] or [0])


def list_shapes(kind: str, joints: int) -> dict[str, tuple[int, ...]]:
    """The shape of each list a row of a case of ``kind`` holds, for ``joints`` joints:
    one value per joint or per intermediate shaft; a column's moved joint centres one
    point (x, y, z, mm) per joint."""
    shafts = max(joints - 1, 0)
    if kind != "column":
        return {"design_beta_deg": (joints,), "design_phase_deg": (shafts,)}
    return {"design_beta_deg": (joints,), "plane_angle_deg": (shafts,),
            "yoke_phase_deg": (shafts,), "continuous_yoke_phase_deg": (shafts,),
            "tooth_offset": (shafts,), "joint_centres_points_mm": (joints, 3),
            "robust_yoke_phase_deg": (shafts,)}


def flat_row(row: Mapping[str, Any]) -> dict[str, Any]:
    """``row`` with each list spread over its elements (``{"a": [1, [2, 3]]}`` gives
    ``{"a[0]": 1, "a[1][0]": 2, "a[1][1]": 3}``); a row without lists as it is (the
    same dict)."""
    if not any(isinstance(value, (list, tuple)) for value in row.values()):
        return row if isinstance(row, dict) else dict(row)
    flat: dict[str, Any] = {}
    for name, value in row.items():
        _spread(flat, name, value)
    return flat


def _spread(flat: dict[str, Any], name: str, value: Any) -> None:
    if isinstance(value, (list, tuple)):
        for index, item in enumerate(value):
            _spread(flat, f"{name}[{index}]", item)
    else:
        flat[name] = value


def gathered(row: Mapping[str, Any], name: str) -> Any:
    """The value of ``name`` in a row of element columns: the cell itself, or the list
    its elements make (empty trailing elements left off, a list of lists for
    ``name[i][j]``); None when the row holds neither, or only empty elements."""
    if name in row:
        return row[name]
    prefix = name + "["
    items: dict[int, dict[str, Any]] = {}
    for column, value in row.items():
        if column.startswith(prefix):
            index, _, rest = column[len(prefix):].partition("]")
            if index.isdigit():
                items.setdefault(int(index), {})["item" + rest] = value
    if not items:
        return None
    values = [gathered(items[index], "item") if index in items else None
              for index in range(max(items) + 1)]
    while values and values[-1] is None:
        values.pop()
    return values or None


def split_columns(name: str, array: np.ndarray) -> dict[str, np.ndarray]:
    """A 2-D array of one list per row as its element columns (contiguous copies)."""
    return {element: np.ascontiguousarray(array[:, index])
            for index, element in enumerate(element_names(name, array.shape[1:2]))}
