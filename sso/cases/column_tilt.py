"""Case keys of a column's tilt position (the optional table ``[tilt]``).

``[tilt] angle_deg`` turns the input shaft's point ``P0`` of ``hardpoints.points_mm``
about a pivot axis (:mod:`sso.column.tilt`), so a sweep over ``tilt.angle_deg``
studies a tilting column through its tilt range. The axis defaults to the vehicle's
lateral axis ``[0, 1, 0]`` (the shipped cases' coordinates: x rearward, y right,
z up; a tilt column pitches about it) and the pivot to the upper joint's centre
``P1``. Every other hardpoint stays where it is given.
"""

from __future__ import annotations

import math
from typing import Any

from sso.cases.schema import REQUIRED, Key, number, number_list
from sso.column.tilt import MAX_TILT_DEG, tilted_points

TILT_TABLE = "tilt"
LATERAL_AXIS = (0.0, 1.0, 0.0)


def _axis_default(values: dict[str, Any], path: str) -> tuple[float, ...] | None:
    return LATERAL_AXIS if "tilt.angle_deg" in values else None


def _pivot_default(values: dict[str, Any], path: str) -> tuple[float, ...] | None:
    points: tuple[tuple[float, ...], ...] = values.get("hardpoints.points_mm") or ()
    if "tilt.angle_deg" not in values or len(points) < 2:
        return None
    return tuple(points[1])


TILT_KEYS: tuple[Key, ...] = (
    Key(TILT_TABLE, "angle_deg", number(-MAX_TILT_DEG, MAX_TILT_DEG, "deg"), REQUIRED, "deg",
        f"[-{MAX_TILT_DEG:g}, {MAX_TILT_DEG:g}]: P0 turned by this angle about tilt.axis "
        "through tilt.through_mm (right-hand rule)"),
    Key(TILT_TABLE, "axis", number_list(-math.inf, math.inf, "", max_length=3, min_length=3),
        _axis_default, "", "[x, y, z], not all 0: direction of the pivot axis (default "
        "[0, 1, 0], the lateral axis)"),
    Key(TILT_TABLE, "through_mm", number_list(-math.inf, math.inf, "mm", max_length=3,
                                              min_length=3),
        _pivot_default, "mm", "[x, y, z]: a point of the pivot axis (default P1, the upper "
        "joint's centre)"),
)


def case_points(values: dict[str, Any]) -> tuple[tuple[float, float, float], ...]:
    """``hardpoints.points_mm`` with the ``[tilt]`` applied (as given without it).

    Raises
    ------
    ValueError
        Naming ``tilt.axis`` if it has no direction.
    """
    points = values["hardpoints.points_mm"]
    angle = values.get("tilt.angle_deg")
    if angle is None:
        return tuple(points)
    try:
        return tilted_points(points, angle, values["tilt.axis"], values["tilt.through_mm"])
    except ValueError as error:
        raise ValueError(f"tilt.{error}") from None
