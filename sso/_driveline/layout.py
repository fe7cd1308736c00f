"""A driveline's joint centres from what a fitter measures, and the views of its joints.

Axes (ISO 8855): ``x`` forward, ``y`` to the left, ``z`` up, mm. The driveline runs
rearward, from the gearbox output through the propshafts to the axle pinion.

* A component's side-view slope ``s`` (deg) is what an inclinometer on it reads,
  positive when its front is higher than its rear (Meritor MM-96147 p. 79; Spicer).
* A propshaft's plan-view offset ``y`` (mm) is its rear joint centre's lateral
  position minus its front joint centre's, positive to the left.
* A propshaft of length ``L`` (joint centre to joint centre) therefore runs from its
  front joint by ``(-sqrt(L^2 - y^2) cos s, y, -sqrt(L^2 - y^2) sin s)``: its side
  view rises ``tan s`` per unit run and its plan view turns by ``atan(y / run)``.
* The gearbox output shaft and the pinion are given by their slope and plan angle
  ``p`` (deg, rear end to the left positive): direction ``(-1, tan p, -tan s)``
  normalised.

The points handed to :class:`sso._column.geometry.ColumnGeometry` are ``P0`` a point
on the gearbox axis ahead of the first joint, the joint centres, and ``P(n+1)`` a
point on the pinion axis behind the last joint.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from sso._validation import finite_float

MAX_SLOPE_DEG = 45.0
"""Largest side-view slope or plan angle accepted, deg (a driveline runs near level)."""
END_POINT_DISTANCE_MM = 100.0
"""How far ``P0`` lies ahead of the first joint and ``P(n+1)`` behind the last, mm."""


def _angle(name: str, value: float) -> float:
    angle = finite_float(name, value)
    if not -MAX_SLOPE_DEG <= angle <= MAX_SLOPE_DEG:
        raise ValueError(f"{name} = {angle:g} deg is outside the allowed range "
                         f"[-{MAX_SLOPE_DEG:g}, {MAX_SLOPE_DEG:g}] deg")
    return angle


def end_direction(slope_deg: float, plan_deg: float) -> np.ndarray:
    """Unit direction, front to rear, of a component with the given slope and plan angle."""
    vector = np.array([-1.0, math.tan(math.radians(plan_deg)),
                       -math.tan(math.radians(slope_deg))])
    direction: np.ndarray = vector / np.linalg.norm(vector)
    return direction


def shaft_vector(length_mm: float, slope_deg: float, offset_mm: float) -> np.ndarray:
    """Front joint to rear joint of a propshaft, mm (see the module notes)."""
    run = math.sqrt(length_mm**2 - offset_mm**2)
    slope = math.radians(slope_deg)
    return np.array([-run * math.cos(slope), offset_mm, -run * math.sin(slope)])


def points_from_measurements(
    *, gearbox_slope_deg: float, shaft_slope_deg: Sequence[float],
    shaft_length_mm: Sequence[float], pinion_slope_deg: float,
    shaft_offset_mm: Sequence[float] | None = None, gearbox_plan_deg: float = 0.0,
    pinion_plan_deg: float = 0.0,
) -> tuple[tuple[float, float, float], ...]:
    """The points ``P0 .. P(n+1)`` (mm) of a driveline measured by a fitter.

    The first joint centre (gearbox output) is at the origin.

    Parameters
    ----------
    gearbox_slope_deg, pinion_slope_deg : float
        Side-view slopes of the gearbox and of the pinion (axle), deg, front higher
        positive, each in ``[-45, 45]``.
    shaft_slope_deg : sequence of float
        Side-view slope of each propshaft, front to rear, deg, in ``[-45, 45]``.
    shaft_length_mm : sequence of float
        Each propshaft's length between its joint centres, mm, > 0.
    shaft_offset_mm : sequence of float, optional
        Each propshaft's plan-view offset (rear joint left of front joint
        positive), mm, ``|offset| < length``; default 0 (no plan-view angle).
    gearbox_plan_deg, pinion_plan_deg : float
        Plan-view angles of the gearbox and pinion axes, deg (rear end to the left
        positive), in ``[-45, 45]``; default 0.

    Raises
    ------
    ValueError
        If the counts differ, there is no propshaft, or a value is out of range
        (the message names the field and entry).
    """
    slopes = [_angle(f"shaft_slope_deg[{k}]", value) for k, value in enumerate(shaft_slope_deg)]
    if not slopes:
        raise ValueError("shaft_slope_deg is empty: a driveline needs at least one propshaft")
    lengths = [finite_float(f"shaft_length_mm[{k}]", value)
               for k, value in enumerate(shaft_length_mm)]
    offsets = ([0.0] * len(slopes) if shaft_offset_mm is None else
               [finite_float(f"shaft_offset_mm[{k}]", value)
                for k, value in enumerate(shaft_offset_mm)])
    for name, values in (("shaft_length_mm", lengths), ("shaft_offset_mm", offsets)):
        if len(values) != len(slopes):
            raise ValueError(f"{name} has {len(values)} entries; shaft_slope_deg has "
                             f"{len(slopes)} (one per propshaft)")
    for k, (length, offset) in enumerate(zip(lengths, offsets, strict=True)):
        if length <= 0.0:
            raise ValueError(f"shaft_length_mm[{k}] = {length:g} mm is outside the allowed "
                             "range (0, inf) mm: a propshaft needs a length")
        if abs(offset) >= length:
            raise ValueError(f"shaft_offset_mm[{k}] = {offset:g} mm is outside the allowed "
                             f"range (-{length:g}, {length:g}) mm (less than the shaft's "
                             "length)")
    gearbox = end_direction(_angle("gearbox_slope_deg", gearbox_slope_deg),
                            _angle("gearbox_plan_deg", gearbox_plan_deg))
    pinion = end_direction(_angle("pinion_slope_deg", pinion_slope_deg),
                           _angle("pinion_plan_deg", pinion_plan_deg))
    joints = [np.zeros(3)]
    for length, slope, offset in zip(lengths, slopes, offsets, strict=True):
        joints.append(joints[-1] + shaft_vector(length, slope, offset))
    points = [joints[0] - END_POINT_DISTANCE_MM * gearbox, *joints,
              joints[-1] + END_POINT_DISTANCE_MM * pinion]
    return tuple((float(p[0]), float(p[1]), float(p[2])) for p in points)


def side_slope_deg(direction: np.ndarray) -> float:
    """Side-view slope (front higher positive), deg, of a front-to-rear direction."""
    return float(math.degrees(math.atan2(-direction[2], -direction[0])))


def plan_angle_deg(direction: np.ndarray) -> float:
    """Plan-view angle (rear end to the left positive), deg, of a front-to-rear direction."""
    return float(math.degrees(math.atan2(direction[1], -direction[0])))
