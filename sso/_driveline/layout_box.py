"""The layout a driveline engineer may still choose: the pinion angle and centre-bearing heights.

Each is a box the case gives, and each moves the design position and every named
position alike (a shim under the axle, a spacer under a centre bearing's bracket):

* the pinion's side-view slope (deg, front higher positive, as
  :mod:`sso._driveline.layout`), chosen within ``[low, high]``; the pinion axis turns
  about the lateral (``y``, the axle's) axis through the pinion joint centre, so the
  pinion joint stays where it is and every position's pinion slope changes by exactly
  the same amount (a pinion angled in plan view keeps its lateral component, so its
  plan angle changes at second order);
* the height change of each centre bearing (mm, up positive) within its box: the
  joint at the rear of that propshaft (the centre bearing's joint) moves vertically by
  that much in every position; the propshafts' lengths follow it (a few tenths of a
  millimetre for the usual boxes).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from sso._column.geometry import ColumnGeometry
from sso._driveline.layout import MAX_SLOPE_DEG, side_slope_deg
from sso._record import register_record
from sso._validation import per_item_bounds

MAX_HEIGHT_CHANGE_MM = 500.0
"""Largest centre-bearing height change a box may reach, mm (either way)."""

Points = tuple[tuple[float, float, float], ...]


@register_record
@dataclass(frozen=True)
class LayoutBox:
    """The layout variables a driveline's layout may be chosen within.

    Parameters
    ----------
    pinion_slope_deg : (float, float), optional
        ``[low, high]`` of the design position's pinion side-view slope, deg, front
        higher positive, each in ``[-45, 45]``; None keeps the pinion as given.
    centre_bearing_height_mm : sequence of (float, float), optional
        For each centre bearing (front to rear), ``[low, high]`` of its height change,
        mm, up positive, each in ``[-500, 500]``; empty keeps them as given.

    Raises
    ------
    ValueError
        Naming the field, its value and the allowed range (or a low end above the
        high end).
    """

    pinion_slope_deg: tuple[float, float] | None = None
    centre_bearing_height_mm: tuple[tuple[float, float], ...] = ()

    def __post_init__(self) -> None:
        if self.pinion_slope_deg is not None:
            object.__setattr__(self, "pinion_slope_deg", per_item_bounds(
                "pinion_slope_deg", self.pinion_slope_deg, 1, -MAX_SLOPE_DEG, MAX_SLOPE_DEG,
                "deg")[0])
        heights = tuple(per_item_bounds(f"centre_bearing_height_mm[{index}]", box, 1,
                                        -MAX_HEIGHT_CHANGE_MM, MAX_HEIGHT_CHANGE_MM, "mm")[0]
                        for index, box in enumerate(self.centre_bearing_height_mm))
        object.__setattr__(self, "centre_bearing_height_mm", heights)
        if self.pinion_slope_deg is None and not heights:
            raise ValueError("a layout box needs pinion_slope_deg or centre_bearing_height_mm")

    @property
    def bounds(self) -> tuple[tuple[float, float], ...]:
        """The box of the layout variables, in the order :func:`laid_out_points` takes."""
        pinion = () if self.pinion_slope_deg is None else (self.pinion_slope_deg,)
        return (*pinion, *self.centre_bearing_height_mm)

    def check_fits(self, joint_count: int) -> None:
        """Refuse a box of more centre bearings than the driveline has.

        Raises
        ------
        ValueError
            Naming ``centre_bearing_height_mm`` and the count allowed.
        """
        bearings = max(joint_count - 2, 0)
        if len(self.centre_bearing_height_mm) > bearings:
            raise ValueError(f"centre_bearing_height_mm has {len(self.centre_bearing_height_mm)}"
                             f" boxes; the driveline has {bearings} centre bearings")


def pinion_slope_of(points_mm: Points) -> float:
    """The pinion's side-view slope, deg, of a driveline's points."""
    direction = np.subtract(points_mm[-1], points_mm[-2])
    return side_slope_deg(direction / np.linalg.norm(direction))


def laid_out_points(points_mm: Points, pinion_change_deg: float,
                    height_change_mm: Sequence[float]) -> Points:
    """The points with the pinion slope raised by ``pinion_change_deg`` and each centre
    bearing's joint (joints 2 .. in order) raised by its height change, mm."""
    moved = np.array(points_mm, dtype=float)
    for index, change in enumerate(height_change_mm):
        moved[index + 2, 2] += change
    # A rise of the slope (front higher) by d turns the front-to-rear axis by -d about y.
    angle = -math.radians(pinion_change_deg)
    rotation = np.array([[math.cos(angle), 0.0, math.sin(angle)], [0.0, 1.0, 0.0],
                         [-math.sin(angle), 0.0, math.cos(angle)]])
    moved[-1] = moved[-2] + rotation @ (moved[-1] - moved[-2])
    return tuple((float(p[0]), float(p[1]), float(p[2])) for p in moved)


def laid_out_geometries(named_points: Sequence[Points], box: LayoutBox,
                        variables: Sequence[float]) -> list[ColumnGeometry]:
    """Each position's geometry with the layout variables (in :attr:`LayoutBox.bounds`
    order; the pinion variable is the design position's slope, the first points given).

    Raises
    ------
    ValueError
        If a position's points make no driveline (as :class:`ColumnGeometry`).
    """
    values = list(variables)
    change = 0.0
    if box.pinion_slope_deg is not None:
        change = values.pop(0) - pinion_slope_of(named_points[0])
    return [ColumnGeometry(laid_out_points(points, change, values)) for points in named_points]
