"""``sso.Driveline``: a gearbox, its propshafts and the pinion, as a driveline engineer gives them.

The joints are the column's (:class:`sso._column.geometry.ColumnGeometry`): points
``P0`` on the gearbox axis, the joint centres, ``P(n+1)`` on the pinion axis; the
propshafts are the intermediate shafts ``1 .. n - 1`` and their yoke phasings are the
column's ``delta_k``. :meth:`Driveline.from_measurements` builds the points from a
fitter's slopes, offsets and lengths (:mod:`sso._driveline.layout`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from sso._column.geometry import ColumnGeometry
from sso._driveline.layout import points_from_measurements
from sso._driveline.loads import BearingGeometry
from sso._driveline.tube import SAFE_SPEED_FRACTION, Tube
from sso._limits import DEFAULT_PLAN_ANGLE_DEG
from sso._record import register_record
from sso._validation import as_float_tuple, check_choice, finite_in_range, validate_speed

INERTIA_LIMIT_RAD_S2 = 1000.0
"""Spicer's inertia excitation limit (torsional analysis calculator, as quoted by NZV8)."""
TORSIONAL_LIMIT_RAD_S2 = 300.0
"""Spicer's torsional excitation limit (same source)."""
DEFAULT_END_TOLERANCE_DEG = 1.0
"""Spicer: the two joint angles of a shaft equal within 1 deg (0.5 where the maker says)."""
DESIGN_POSITION = "design"
"""The name of the driveline's own points among its positions."""


@register_record
@dataclass(frozen=True)
class NamedPosition:
    """A named position of the driveline (laden, unladen, jounce, rebound, wind-up).

    Attributes
    ----------
    name : str
    points_mm : tuple of (float, float, float)
        The driveline's points in that position, mm (same count as the design's).
    """

    name: str
    points_mm: tuple[tuple[float, float, float], ...]


@register_record
@dataclass(frozen=True, kw_only=True)
class Driveline:
    """A driveline: gearbox output, propshafts (tubes, centre bearings), pinion.

    Parameters
    ----------
    points_mm : sequence of (x, y, z)
        ``P0`` on the gearbox axis ahead of the first joint, the ``n >= 1`` joint
        centres, ``P(n+1)`` on the pinion axis behind the last, mm, vehicle axes
        (``x`` forward, ``y`` left, ``z`` up).
    tubes : sequence of Tube
        One per propshaft (``n - 1``; none for a single joint).
    max_shaft_speed_rpm : float
        Largest gearbox output (propshaft) speed, rpm, in ``(0, 1e6]`` and below every
        propshaft's critical speed (above its safe speed is a failed rule, not an error).
    torque_n_m : float
        Largest gearbox output torque (low gear, wheel slip), N m, in ``(0, 1e7]``.
    yoke_phase_deg : sequence of float, optional
        Yoke phasing of each propshaft (the column's ``delta_k``), deg; default in phase.
    centre_bearing_mm : sequence of float, optional
        For each propshaft but the rearmost: its centre bearing's distance ahead of its
        rear joint centre, mm, in ``[0, shaft length)``. Required for 3 or more joints.
    gearbox_bearings_mm : (float, float)
        ``(a, b)``: the gearbox output bearings at ``b`` (near) and ``a + b`` (far) ahead
        of the first joint, mm; default ``(100, 50)``.
    pinion_bearings_mm : (float, float)
        ``(e, f)``: the pinion bearings at ``e`` (near) and ``e + f`` (far) behind the
        last joint, mm; default ``(50, 100)``.
    application : {"automotive", "industrial"}
        Safe speed fraction of the critical speed, 0.70 or 0.65 (IMS Ltd).
    safe_speed_fraction : float, optional
        Overrides the application's fraction, in ``(0, 1]``.
    end_tolerance_deg : float
        Largest difference of a propshaft's two joint angles, deg (Spicer 1, or 0.5
        where the maker says so), in ``(0, 10]``.
    inertia_limit_rad_s2, torsional_limit_rad_s2 : float
        Excitation limits, rad/s^2 (Spicer 1,000 and 300), each in ``(0, 1e6]``.
    positions : sequence of NamedPosition
        Further positions (laden, unladen, jounce, rebound, axle wind-up).

    Raises
    ------
    ValueError
        Naming the field, its value and the allowed range.
    """

    points_mm: tuple[tuple[float, float, float], ...]
    tubes: tuple[Tube, ...]
    max_shaft_speed_rpm: float
    torque_n_m: float
    yoke_phase_deg: tuple[float, ...] | None = None
    centre_bearing_mm: tuple[float, ...] = ()
    gearbox_bearings_mm: tuple[float, float] = (100.0, 50.0)
    pinion_bearings_mm: tuple[float, float] = (50.0, 100.0)
    application: str = "automotive"
    safe_speed_fraction: float | None = None
    end_tolerance_deg: float = DEFAULT_END_TOLERANCE_DEG
    inertia_limit_rad_s2: float = INERTIA_LIMIT_RAD_S2
    torsional_limit_rad_s2: float = TORSIONAL_LIMIT_RAD_S2
    positions: tuple[NamedPosition, ...] = ()
    _geometry: ColumnGeometry = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        geometry = ColumnGeometry(self.points_mm)
        set_ = object.__setattr__
        set_(self, "points_mm", geometry.points_mm)
        set_(self, "_geometry", geometry)
        shafts = geometry.joint_count - 1
        tubes = tuple(self.tubes)
        if len(tubes) != shafts or not all(isinstance(tube, Tube) for tube in tubes):
            raise ValueError(f"tubes has {len(tubes)} entries; a driveline of "
                             f"{geometry.joint_count} joints has {shafts} propshafts "
                             "(give one Tube each)")
        set_(self, "tubes", tubes)
        set_(self, "max_shaft_speed_rpm",
             validate_speed("max_shaft_speed_rpm", self.max_shaft_speed_rpm))
        set_(self, "torque_n_m", finite_in_range("torque_n_m", self.torque_n_m, 0.0, 1e7,
                                                 "N m", lower_open=True))
        if self.yoke_phase_deg is not None:
            phases = as_float_tuple("yoke_phase_deg", self.yoke_phase_deg)
            if len(phases) != shafts:
                raise ValueError(f"yoke_phase_deg has {len(phases)} entries; a driveline "
                                 f"of {shafts} propshafts has {shafts}")
            set_(self, "yoke_phase_deg", phases)
        lengths = geometry.shaft_length_mm
        for shaft, tube in enumerate(tubes, start=1):
            critical = tube.critical_speed_rpm(lengths[shaft])
            if self.max_shaft_speed_rpm >= critical:
                raise ValueError(
                    f"max_shaft_speed_rpm = {self.max_shaft_speed_rpm:g} rpm is outside the "
                    f"allowed range (0, {critical:.6g}) rpm: propshaft {shaft} "
                    f"({lengths[shaft]:.6g} mm of {tube.outside_diameter_mm:g} x "
                    f"{tube.wall_mm:g} mm tube) whirls at its critical speed {critical:.6g} "
                    "rpm; split the shaft or choose a larger tube")
        centres = as_float_tuple("centre_bearing_mm", self.centre_bearing_mm)
        if len(centres) != max(shafts - 1, 0):
            raise ValueError(f"centre_bearing_mm has {len(centres)} entries; every propshaft "
                             f"but the rearmost needs a centre bearing ({max(shafts - 1, 0)})")
        for index, distance in enumerate(centres):
            finite_in_range(f"centre_bearing_mm[{index}]", distance, 0.0, lengths[index + 1],
                            "mm", upper_open=True)
        set_(self, "centre_bearing_mm", centres)
        for name in ("gearbox_bearings_mm", "pinion_bearings_mm"):
            pair = as_float_tuple(name, getattr(self, name))
            if len(pair) != 2:
                raise ValueError(f"{name} has {len(pair)} entries; give 2 distances in mm")
            finite_in_range(f"{name}[0]", pair[0], 0.0, 1e5, "mm", lower_open=True)
            finite_in_range(f"{name}[1]", pair[1], 0.0, 1e5, "mm")
            set_(self, name, pair)
        check_choice("application", self.application, tuple(SAFE_SPEED_FRACTION))
        if self.safe_speed_fraction is not None:
            set_(self, "safe_speed_fraction",
                 finite_in_range("safe_speed_fraction", self.safe_speed_fraction, 0.0, 1.0,
                                 lower_open=True))
        set_(self, "end_tolerance_deg", finite_in_range(
            "end_tolerance_deg", self.end_tolerance_deg, 0.0, 10.0, "deg", lower_open=True))
        for name in ("inertia_limit_rad_s2", "torsional_limit_rad_s2"):
            set_(self, name, finite_in_range(name, getattr(self, name), 0.0, 1e6, "rad/s^2",
                                             lower_open=True))
        positions = tuple(self.positions)
        names = [DESIGN_POSITION]
        for position in positions:
            if not isinstance(position, NamedPosition):
                raise TypeError("positions must hold NamedPosition entries")
            if position.name in names:
                raise ValueError(f"positions: the name {position.name!r} is used twice "
                                 f"(or is {DESIGN_POSITION!r}, the driveline's own points)")
            names.append(position.name)
            other = _position_geometry(position)
            if other.joint_count != geometry.joint_count:
                raise ValueError(f"positions[{position.name!r}] has {other.joint_count} "
                                 f"joints; the driveline has {geometry.joint_count}")
        set_(self, "positions", positions)

    @classmethod
    def from_measurements(
        cls, *, gearbox_slope_deg: float, shaft_slope_deg: Sequence[float],
        shaft_length_mm: Sequence[float], pinion_slope_deg: float,
        shaft_offset_mm: Sequence[float] | None = None,
        gearbox_plan_deg: float = DEFAULT_PLAN_ANGLE_DEG,
        pinion_plan_deg: float = DEFAULT_PLAN_ANGLE_DEG,
        positions: Mapping[str, Mapping[str, Any]] | None = None, **options: Any,
    ) -> Driveline:
        """A driveline from a fitter's measurements (:mod:`sso._driveline.layout`).

        Parameters
        ----------
        gearbox_slope_deg, shaft_slope_deg, shaft_length_mm, pinion_slope_deg,
        shaft_offset_mm, gearbox_plan_deg, pinion_plan_deg
            As :func:`sso._driveline.layout.points_from_measurements`: side-view slopes
            front higher positive, deg; lengths and plan-view offsets, mm.
        positions : mapping of str to mapping, optional
            Each named position's measurements that differ from these (for example
            ``{"laden": {"pinion_slope_deg": 1.5}}``).
        **options
            The other fields of :class:`Driveline` (``tubes``, ``max_shaft_speed_rpm``,
            ``torque_n_m``, ...).

        Raises
        ------
        ValueError
            Naming the field (and the position), its value and the allowed range.
        """
        measured: dict[str, Any] = {
            "gearbox_slope_deg": gearbox_slope_deg, "shaft_slope_deg": shaft_slope_deg,
            "shaft_length_mm": shaft_length_mm, "pinion_slope_deg": pinion_slope_deg,
            "shaft_offset_mm": shaft_offset_mm, "gearbox_plan_deg": gearbox_plan_deg,
            "pinion_plan_deg": pinion_plan_deg}
        named = []
        for name, changes in (positions or {}).items():
            unknown = sorted(set(changes) - set(measured))
            if unknown:
                raise ValueError(f"positions[{name!r}]: {unknown[0]!r} is not a measurement "
                                 f"(one of {', '.join(sorted(measured))})")
            try:
                points = points_from_measurements(**{**measured, **changes})
            except ValueError as error:
                raise ValueError(f"positions[{name!r}]: {error}") from None
            named.append(NamedPosition(str(name), points))
        points = points_from_measurements(**measured)
        try:
            ColumnGeometry(points)
        except ValueError as error:
            raise ValueError(f"the measurements, as the points P0 .. P(n+1) they give: "
                             f"{error}") from None
        return cls(points_mm=points, positions=tuple(named), **options)

    @property
    def geometry(self) -> ColumnGeometry:
        """The joints as the column's geometry (the design position)."""
        return self._geometry

    @property
    def joint_count(self) -> int:
        """Number of joints ``n`` (``n - 1`` propshafts)."""
        return self._geometry.joint_count

    @property
    def phasing_deg(self) -> tuple[float, ...]:
        """The yoke phasing of each propshaft, deg (0 where none was given: in phase)."""
        if self.yoke_phase_deg is None:
            return (0.0,) * (self.joint_count - 1)
        return self.yoke_phase_deg

    @property
    def safe_fraction(self) -> float:
        """The safe fraction of the critical speed in force."""
        if self.safe_speed_fraction is not None:
            return self.safe_speed_fraction
        return SAFE_SPEED_FRACTION[self.application]

    @property
    def bearings(self) -> BearingGeometry:
        """The bearing positions for :mod:`sso._driveline.loads`."""
        return BearingGeometry(self.gearbox_bearings_mm[0], self.gearbox_bearings_mm[1],
                               self.pinion_bearings_mm[0], self.pinion_bearings_mm[1],
                               self.centre_bearing_mm)

    def named_geometries(self) -> dict[str, ColumnGeometry]:
        """The design position and each named position, by name."""
        return {DESIGN_POSITION: self._geometry,
                **{position.name: _position_geometry(position) for position in self.positions}}

    @staticmethod
    def shaft_speed_from_engine(engine_speed_rpm: float, top_gear_ratio: float) -> float:
        """The largest propshaft speed, rpm: engine speed over the top gear's ratio.

        Raises
        ------
        ValueError
            If either is not finite and positive (the ratio at most 100).
        """
        return shaft_speed_from_engine(engine_speed_rpm, top_gear_ratio)

    def with_phasing(self, yoke_phase_deg: Sequence[float]) -> Driveline:
        """This driveline with another yoke phasing."""
        from dataclasses import replace

        return replace(self, yoke_phase_deg=tuple(yoke_phase_deg))


def shaft_speed_from_engine(engine_speed_rpm: float, top_gear_ratio: float) -> float:
    """The largest propshaft speed, rpm: engine speed over the top gear's ratio.

    Raises
    ------
    ValueError
        If either is not finite and positive.
    """
    engine = validate_speed("engine_speed_rpm", engine_speed_rpm)
    ratio = finite_in_range("top_gear_ratio", top_gear_ratio, 0.0, 100.0, lower_open=True)
    return engine / ratio


def _position_geometry(position: NamedPosition) -> ColumnGeometry:
    try:
        return ColumnGeometry(position.points_mm)
    except ValueError as error:
        raise ValueError(f"positions[{position.name!r}]: {error}") from None

