"""A tilt position of a column: the input shaft's point turned about a pivot axis.

A tilting column turns the steering wheel, and with it the input shaft, about a
pivot axis near the upper joint. Here that is the point ``P0`` (on the input shaft's
axis) turned by ``angle_deg`` about the line through ``through_mm`` along ``axis``
(right-hand rule); every other hardpoint stays. By Rodrigues' formula, with ``k`` the
unit axis and ``v = P0 - through``::

    P0' = through + v cos a + (k x v) sin a + k (k . v) (1 - cos a)
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

MAX_TILT_DEG = 90.0
"""Largest tilt either way, deg: a quarter turn of the steering wheel about its pivot."""


def tilted_points(points_mm: Sequence[Sequence[float]], angle_deg: float,
                  axis: Sequence[float], through_mm: Sequence[float]
                  ) -> tuple[tuple[float, float, float], ...]:
    """The hardpoints with ``P0`` turned by ``angle_deg`` about ``axis`` through ``through_mm``.

    Parameters
    ----------
    points_mm : sequence of (x, y, z)
        ``P0 .. P(n+1)``, mm.
    angle_deg : float
        Tilt angle, deg (right-hand rule about ``axis``); 0 returns the points as given.
    axis : (x, y, z)
        Direction of the pivot axis (any length but 0).
    through_mm : (x, y, z)
        A point of the pivot axis, mm.

    Raises
    ------
    ValueError
        If ``axis`` has no length.
    """
    points = tuple((float(x), float(y), float(z)) for x, y, z in points_mm)
    direction = np.asarray(axis, dtype=float)
    length = float(np.linalg.norm(direction))
    if not length > 0.0 or not math.isfinite(length):
        raise ValueError(f"axis = {list(axis)} has no direction: give a non-zero finite vector")
    if angle_deg == 0.0:
        return points
    unit = direction / length
    pivot = np.asarray(through_mm, dtype=float)
    offset = np.asarray(points[0]) - pivot
    angle = math.radians(angle_deg)
    turned = (pivot + offset * math.cos(angle) + np.cross(unit, offset) * math.sin(angle)
              + unit * float(unit @ offset) * (1.0 - math.cos(angle)))
    first = (float(turned[0]), float(turned[1]), float(turned[2]))
    return (first, *points[1:])
