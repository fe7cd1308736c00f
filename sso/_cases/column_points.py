"""Parser of a list of 3D points in a column case (mm), shared by its tables."""

from __future__ import annotations

from typing import Any

from sso._validation import finite_float

MAX_POINTS = 66
POINT_LIST = "a list of [x, y, z] points in mm, each coordinate finite"


def point_list(label: str, value: Any) -> tuple[tuple[float, float, float], ...]:
    """Parser of a list of ``[x, y, z]`` points (mm, finite)."""
    if not isinstance(value, list) or not 1 <= len(value) <= MAX_POINTS:
        raise ValueError(f"{label} = {value!r} must be {POINT_LIST} (1 to {MAX_POINTS} points)")
    points = []
    for index, point in enumerate(value):
        if not isinstance(point, list) or len(point) != 3:
            raise ValueError(f"{label}[{index}] = {point!r} must be [x, y, z] in mm")
        coordinates = []
        for axis, item in enumerate(point):
            if isinstance(item, bool) or not isinstance(item, (int, float)):
                # The schema's parsers raise ValueError for every bad value (CaseError).
                raise ValueError(  # noqa: TRY004
                    f"{label}[{index}][{axis}] = {item!r} must be a number (mm)")
            coordinates.append(finite_float(f"{label}[{index}][{axis}]", item))
        points.append((coordinates[0], coordinates[1], coordinates[2]))
    return tuple(points)
