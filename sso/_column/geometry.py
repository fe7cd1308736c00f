"""A steering column (or driveline) in 3D from hardpoints: operating angles, bend planes, phases.

Conventions (``docs/column.md`` draws them):

* points ``P0 .. P(n+1)`` in mm: ``P0`` on the input shaft axis, ``P1 .. Pn`` the
  joint centres, ``P(n+1)`` on the output shaft axis; shaft ``k`` (``k = 0..n``)
  runs from ``P(k)`` to ``P(k+1)`` with unit direction ``u_k``;
* operating angle ``beta_k`` (joint ``k = 1..n``): the angle between ``u_(k-1)``
  and ``u_k``;
* bend plane ``k`` is spanned by ``u_(k-1)`` and ``u_k``, normal
  ``n_k = u_(k-1) x u_k / |u_(k-1) x u_k|``;
* bend-plane angle ``gamma_k`` (``k = 1..n-1``): signed angle from ``n_k`` to
  ``n_(k+1)`` about ``u_k`` (right-hand rule);
* yoke phasing ``delta_k`` on intermediate shaft ``k``: angle about ``u_k`` from the
  pin axis of its yoke at joint ``k`` to the pin axis of its yoke at joint ``k+1``;
  ``delta = 0`` is "in phase";
* the model's phase is ``phi_k = 90 + delta_k - gamma_k (mod 180)`` deg;
* in words (:func:`shaft_name`) shaft 0 is the input shaft, shaft ``n`` the output
  shaft, and the intermediate shafts keep their numbers ``1 .. n-1``, everywhere.

A straight joint (``beta_k = 0``) has no bend plane of its own. It borrows one: the
plane of the nearest bent joint upstream, else downstream. Only sums of bend-plane
angles across a straight joint enter the speed ratio, so the borrowed plane changes
the listed ``gamma`` and ``phi`` but never the motion (tested).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from sso._limits import BETA_LIMIT_DEG, CONVENTIONAL_PHASE_DEG, INPUT_MAGNITUDE_RANGE
from sso._record import register_record
from sso._shafts.series import ShaftSeries
from sso._validation import as_float_tuple, check_chain_conditioning, finite_float

# A joint whose |u_(k-1) x u_k| is at or below this is straight (beta = 0 exactly):
# its bend plane is not defined by the points to better than round-off.
STRAIGHT_SINE = 1e-12
# Sines of bend-plane angles this small are round-off (below 1e-11 deg).
ROUND_OFF_SINE = 1e-13
# Consecutive points closer than this fraction of the column's extent coincide.
COINCIDENT_RELATIVE = 1e-9


@register_record
@dataclass(frozen=True)
class ColumnGeometry:
    """Shafts in 3D joined by Hooke joints, given by hardpoints.

    Parameters
    ----------
    points_mm : array_like, shape (n + 2, 3)
        ``P0 .. P(n+1)`` in mm: a point on the input shaft axis, the ``n >= 1``
        joint centres, a point on the output shaft axis.

    Attributes
    ----------
    points_mm : tuple of (float, float, float)
        The points, mm.

    Raises
    ------
    ValueError
        If the array is not ``(n + 2) x 3`` with ``n >= 1``, a coordinate is not
        finite or its magnitude exceeds 1e100 mm, two consecutive points coincide,
        an operating angle reaches the limit of 90 deg, the operating angles are
        too close to 90 deg for float64 to resolve RE
        (:func:`sso._validation.check_chain_conditioning`), or
        every joint is straight (input and output collinear, nothing to analyse).
        The message names the point or joint.
    """

    points_mm: tuple[tuple[float, float, float], ...]
    _directions: np.ndarray = field(init=False, repr=False, compare=False)
    _normals: np.ndarray = field(init=False, repr=False, compare=False)
    _beta_deg: tuple[float, ...] = field(init=False, repr=False, compare=False)
    _straight: tuple[bool, ...] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        points = _validated_points(self.points_mm)
        directions = _shaft_directions(points)
        beta_deg, straight = _operating_angles(directions)
        normals = _bend_normals(directions, straight)
        object.__setattr__(self, "points_mm", tuple(tuple(float(c) for c in row) for row in points))
        object.__setattr__(self, "_directions", directions)
        object.__setattr__(self, "_normals", normals)
        object.__setattr__(self, "_beta_deg", beta_deg)
        object.__setattr__(self, "_straight", straight)

    @property
    def joint_count(self) -> int:
        """Number of joints ``n``."""
        return len(self.points_mm) - 2

    @property
    def shaft_directions(self) -> np.ndarray:
        """Unit directions ``u_0 .. u_n`` of the shafts, shape ``(n + 1, 3)``."""
        return self._directions.copy()

    @property
    def bend_normals(self) -> np.ndarray:
        """Unit normals ``n_1 .. n_n`` of the bend planes, shape ``(n, 3)``.

        A straight joint carries the borrowed plane (see the module notes).
        """
        return self._normals.copy()

    @property
    def straight_joints(self) -> tuple[bool, ...]:
        """True for each joint with ``beta = 0`` (no bend plane of its own)."""
        return self._straight

    @property
    def beta_deg(self) -> tuple[float, ...]:
        """Operating angle of each joint, deg, in ``[0, 90)``."""
        return self._beta_deg

    @property
    def plane_angle_deg(self) -> tuple[float, ...]:
        """Bend-plane angles ``gamma_1 .. gamma_(n-1)``, deg, in ``(-180, 180]``.

        A planar Z (bends in opposite senses) gives 180, never -180, even when
        round-off leaves the sine a few ulp below zero.
        """
        angles = []
        for k in range(self.joint_count - 1):
            first, second, axis = self._normals[k], self._normals[k + 1], self._directions[k + 1]
            sine = float(np.dot(np.cross(first, second), axis))
            cosine = float(np.dot(first, second))
            if cosine < 0.0 and abs(sine) <= ROUND_OFF_SINE:
                sine = 0.0
            angles.append(float(np.degrees(np.arctan2(sine, cosine))))
        return tuple(angles)

    @property
    def shaft_length_mm(self) -> tuple[float, ...]:
        """Length of each shaft ``|P(k+1) - P(k)|``, mm (the end shafts to the given points)."""
        points = np.asarray(self.points_mm)
        return tuple(float(length) for length in np.linalg.norm(np.diff(points, axis=0), axis=1))

    def phase_deg_from_yoke(self, yoke_phase_deg: ArrayLike) -> tuple[float, ...]:
        """Model phases ``phi_k = 90 + delta_k - gamma_k``, deg, wrapped to ``[0, 180)``.

        Parameters
        ----------
        yoke_phase_deg : sequence of float
            Yoke phasing ``delta_k`` of each intermediate shaft, deg (``n - 1`` entries).

        Raises
        ------
        ValueError
            If the count is wrong or a value is not finite.
        """
        delta, gamma = self._per_shaft("yoke_phase_deg", yoke_phase_deg)
        return _floats(np.mod(CONVENTIONAL_PHASE_DEG + delta - gamma, 180.0))

    def yoke_phase_deg_from_phase(self, phase_deg: ArrayLike) -> tuple[float, ...]:
        """Yoke phasings ``delta_k = phi_k - 90 + gamma_k``, deg, wrapped to ``[-90, 90)``.

        A yoke's pin axis is a line, so a phasing and the phasing 180 deg away are
        the same assembly; the one nearest to "in phase" is returned.

        Raises
        ------
        ValueError
            If the count is wrong or a value is not finite.
        """
        phase, gamma = self._per_shaft("phase_deg", phase_deg)
        return _floats(wrap_half_turn(phase - CONVENTIONAL_PHASE_DEG + gamma))

    def mirror_yoke_phase_deg(self, yoke_phase_deg: ArrayLike) -> tuple[float, ...]:
        """The mirror assembly ``delta_k -> 2 gamma_k - delta_k``, deg, in ``[-90, 90)``.

        It has every model phase negated (``phi -> -phi``), so the same RE and
        the same speed curve run backwards in the input angle.

        Raises
        ------
        ValueError
            If the count is wrong or a value is not finite.
        """
        delta, gamma = self._per_shaft("yoke_phase_deg", yoke_phase_deg)
        return _floats(wrap_half_turn(2.0 * gamma - delta))

    def series(self, yoke_phase_deg: ArrayLike | None = None,
               model: str = "exact") -> ShaftSeries:
        """The model of this column with the given yoke phasing.

        Parameters
        ----------
        yoke_phase_deg : sequence of float, optional
            Yoke phasing of each intermediate shaft, deg; default all 0 (in phase).
        model : {"exact", "paper"}
            Chain model of :class:`sso.ShaftSeries`.

        Returns
        -------
        sso.ShaftSeries
            Operating angles from the points, phases from :meth:`phase_deg_from_yoke`.

        Raises
        ------
        ValueError
            If the phasing has the wrong count or the model is unknown.
        """
        if yoke_phase_deg is None:
            yoke_phase_deg = [0.0] * (self.joint_count - 1)
        return ShaftSeries(self.beta_deg, self.phase_deg_from_yoke(yoke_phase_deg), model)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready description: the points and the derived angles."""
        return {"points_mm": [list(point) for point in self.points_mm],
                "beta_deg": list(self.beta_deg),
                "plane_angle_deg": list(self.plane_angle_deg),
                "shaft_length_mm": list(self.shaft_length_mm)}

    def _per_shaft(self, name: str, values: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """The validated per-shaft angles (deg) and the bend-plane angles beside them."""
        numbers = as_float_tuple(name, values)
        expected = self.joint_count - 1
        if len(numbers) != expected:
            raise ValueError(f"{name} has {len(numbers)} entries; a column of "
                             f"{self.joint_count} joints has {expected} intermediate shafts")
        return np.asarray(numbers, dtype=float), np.asarray(self.plane_angle_deg)


def shaft_name(index: int, shafts: int) -> str:
    """The name of shaft ``index`` (0-based, ``P(index)`` to ``P(index + 1)``) of ``shafts``.

    The end shafts are the input and output shafts; the intermediate shafts are
    numbered from 1, as their yoke phasings ``delta_1 .. delta_(n-1)`` are.
    """
    if index == 0:
        return "input shaft"
    if index == shafts - 1:
        return "output shaft"
    return f"intermediate shaft {index}"


def _floats(values: np.ndarray) -> tuple[float, ...]:
    return tuple(float(value) for value in values)


def wrap_half_turn(angle_deg: Any) -> np.ndarray:
    """Angles (deg) modulo 180, in ``[-90, 90)``."""
    wrapped: np.ndarray = np.mod(np.asarray(angle_deg, dtype=float) + 90.0, 180.0) - 90.0
    return wrapped


def _validated_points(points_mm: Any) -> np.ndarray:
    if isinstance(points_mm, (str, bytes)):
        raise TypeError(f"points_mm = {points_mm!r} must be a list of [x, y, z] points in mm")
    try:
        rows = [list(row) for row in points_mm]
    except TypeError:
        raise TypeError(f"points_mm = {points_mm!r} must be a list of [x, y, z] points "
                        "in mm") from None
    if len(rows) < 3:
        raise ValueError(f"points_mm has {len(rows)} points; a column needs at least 3 "
                         "(input point, one joint centre, output point: 2 shafts)")
    points = np.empty((len(rows), 3))
    for index, row in enumerate(rows):
        if len(row) != 3:
            raise ValueError(f"points_mm[{index}] = {row!r} must have 3 coordinates "
                             "[x, y, z] in mm")
        for axis, value in enumerate(row):
            coordinate = finite_float(f"points_mm[{index}][{axis}]", value)
            if abs(coordinate) > INPUT_MAGNITUDE_RANGE[1]:
                # Beyond it the squared distances overflow (1.4e154 mm squared is inf).
                raise ValueError(f"points_mm[{index}][{axis}] = {coordinate:g} mm is outside "
                                 f"the allowed range [-{INPUT_MAGNITUDE_RANGE[1]:g}, "
                                 f"{INPUT_MAGNITUDE_RANGE[1]:g}] mm")
            points[index, axis] = coordinate
    extent = float(np.ptp(points, axis=0).max())
    lengths = np.linalg.norm(np.diff(points, axis=0), axis=1)
    for index, length in enumerate(lengths):
        if length <= COINCIDENT_RELATIVE * max(extent, 1.0):
            raise ValueError(
                f"points_mm[{index}] and points_mm[{index + 1}] coincide "
                f"(distance {length:g} mm): the {shaft_name(index, len(lengths))} has no "
                "direction")
    return points


def _shaft_directions(points: np.ndarray) -> np.ndarray:
    differences = np.diff(points, axis=0)
    directions: np.ndarray = differences / np.linalg.norm(differences, axis=1, keepdims=True)
    return directions


def _operating_angles(directions: np.ndarray) -> tuple[tuple[float, ...], tuple[bool, ...]]:
    beta_deg: list[float] = []
    straight: list[bool] = []
    for joint in range(1, len(directions)):
        before, after = directions[joint - 1], directions[joint]
        sine = float(np.linalg.norm(np.cross(before, after)))
        cosine = float(np.dot(before, after))
        is_straight = sine <= STRAIGHT_SINE and cosine > 0
        beta = 0.0 if is_straight else float(np.degrees(np.arctan2(sine, cosine)))
        if beta >= BETA_LIMIT_DEG:
            raise ValueError(
                f"points_mm[{joint}]: joint {joint} bends by beta = {beta:g} deg, outside the "
                f"allowed range [0, {BETA_LIMIT_DEG:g}) deg")
        beta_deg.append(beta)
        straight.append(is_straight)
    if all(straight):
        raise ValueError("points_mm are collinear: input and output shafts are in line with no "
                         "bend at any joint, so there is no joint angle to analyse")
    check_chain_conditioning("points_mm (the operating angles they give)", beta_deg)
    return tuple(beta_deg), tuple(straight)


def _bend_normals(directions: np.ndarray, straight: tuple[bool, ...]) -> np.ndarray:
    count = len(straight)
    normals = np.zeros((count, 3))
    for joint in range(count):
        if not straight[joint]:
            normal = np.cross(directions[joint], directions[joint + 1])
            normals[joint] = normal / np.linalg.norm(normal)
    bent = [joint for joint in range(count) if not straight[joint]]
    for joint in range(count):
        if straight[joint]:
            upstream = [index for index in bent if index < joint]
            source = upstream[-1] if upstream else bent[0]
            # Borrowed normal, projected off this joint's shaft to stay exactly normal to it.
            axis = directions[joint + 1]
            normal = normals[source] - np.dot(normals[source], axis) * axis
            normals[joint] = normal / np.linalg.norm(normal)
    return normals
