"""Case files of a vehicle driveline (kind ``driveline``).

Tables:

* ``[measurements]``: what a fitter measures (side-view slopes, front higher positive;
  propshaft lengths and plan-view offsets; gearbox and pinion plan angles), with
  ``[measurements.positions.<name>]`` the measurements that differ in each named
  position (laden, unladen, jounce, rebound, wind-up); or ``[hardpoints] points_mm``
  (gearbox point, joint centres, pinion point, mm) and ``[hardpoints.positions]``;
* ``[tubes]``: each propshaft's outside diameter and wall, the material's E and density;
* ``[speed]``: the largest shaft speed, or the engine speed and top gear ratio;
* ``[loads]``: torque, centre bearings, gearbox and pinion bearing spacings;
* ``[phasing] yoke_phase_deg``: the yoke phasing as assembled;
* ``[rules]``: application (safe speed fraction), end tolerance, excitation limits;
* ``[layout]``: the boxes the pinion slope and the centre-bearing heights are chosen
  within, with the phasing, by ``sso run``.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

from sso._cases.column_points import point_list
from sso._cases.schema import (
    REQUIRED,
    Key,
    TabledCase,
    bounds_list,
    case_document,
    choice,
    number,
    number_list,
    register_case_kind,
)
from sso._driveline.layout import MAX_SLOPE_DEG
from sso._driveline.layout_box import MAX_HEIGHT_CHANGE_MM, LayoutBox
from sso._driveline.model import (
    DEFAULT_END_TOLERANCE_DEG,
    INERTIA_LIMIT_RAD_S2,
    TORSIONAL_LIMIT_RAD_S2,
    Driveline,
    NamedPosition,
    shaft_speed_from_engine,
)
from sso._driveline.tube import (
    SAFE_SPEED_FRACTION,
    STEEL_DENSITY_KG_M3,
    STEEL_YOUNGS_MODULUS_GPA,
    Tube,
)
from sso._limits import DEFAULT_PLAN_ANGLE_DEG
from sso._record import register_record

DRIVELINE_KIND = "driveline"
MEASUREMENT_NAMES = ("gearbox_slope_deg", "shaft_slope_deg", "shaft_length_mm",
                     "shaft_offset_mm", "pinion_slope_deg", "gearbox_plan_deg",
                     "pinion_plan_deg")
REQUIRED_MEASUREMENTS = ("gearbox_slope_deg", "shaft_slope_deg", "shaft_length_mm",
                         "pinion_slope_deg")
MAX_POSITIONS = 20


MILLIMETRES = number_list(-1e5, 1e5, "mm")
ANGLE = number(-MAX_SLOPE_DEG, MAX_SLOPE_DEG, "deg")
ANGLES = number_list(-MAX_SLOPE_DEG, MAX_SLOPE_DEG, "deg")
DISTANCES = number_list(0.0, 1e5, "mm")
MEASUREMENT_PARSERS = {"gearbox_slope_deg": ANGLE, "shaft_slope_deg": ANGLES,
                       "shaft_length_mm": MILLIMETRES, "shaft_offset_mm": MILLIMETRES,
                       "pinion_slope_deg": ANGLE, "gearbox_plan_deg": ANGLE,
                       "pinion_plan_deg": ANGLE}
"""How each measurement of a named position is read (the lengths are checked later,
against each other and against the offsets)."""


def positions_of_measurements(label: str, value: Any) -> dict[str, dict[str, Any]]:
    """Parser of ``[measurements.positions]``: name -> the measurements that differ."""
    if not isinstance(value, dict) or not 1 <= len(value) <= MAX_POSITIONS:
        raise ValueError(f"{label} must be 1 to {MAX_POSITIONS} tables of measurements, "
                         "one per named position")
    positions: dict[str, dict[str, Any]] = {}
    for name, changes in value.items():
        if not isinstance(changes, dict) or not changes:
            raise ValueError(f"{label}.{name} must be a table of the measurements that "
                             "differ in that position")
        checked: dict[str, Any] = {}
        for key, item in changes.items():
            if key not in MEASUREMENT_PARSERS:
                raise ValueError(f"{label}.{name}.{key} is not a measurement (one of "
                                 f"{', '.join(MEASUREMENT_NAMES)})")
            checked[key] = MEASUREMENT_PARSERS[key](f"{label}.{name}.{key}", item)
        positions[str(name)] = checked
    return positions


def positions_of_points(label: str, value: Any) -> dict[str, tuple[tuple[float, ...], ...]]:
    """Parser of ``[hardpoints.positions]``: name -> points (mm)."""
    if not isinstance(value, dict) or not 1 <= len(value) <= MAX_POSITIONS:
        raise ValueError(f"{label} must be 1 to {MAX_POSITIONS} named lists of points")
    return {str(name): point_list(f"{label}.{name}", points) for name, points in value.items()}


def bearing_pair(label: str, value: Any) -> tuple[float, ...]:
    """Parser of a pair of bearing distances, mm, each in ``[0, 1e5]``."""
    pair = DISTANCES(label, value)
    if len(pair) != 2:
        raise ValueError(f"{label} = {value!r} must be 2 distances in mm")
    return pair


DRIVELINE_KEYS: tuple[Key, ...] = (
    Key("measurements", "gearbox_slope_deg", ANGLE, None, "deg",
        "side-view slope of the gearbox, front higher positive, in [-45, 45]"),
    Key("measurements", "shaft_slope_deg", ANGLES, None, "deg",
        "side-view slope of each propshaft, front to rear, in [-45, 45]"),
    Key("measurements", "shaft_length_mm", number_list(0.0, 1e5, "mm"), None, "mm",
        "each propshaft's length between joint centres, > 0"),
    Key("measurements", "shaft_offset_mm", number_list(-1e5, 1e5, "mm"), None, "mm",
        "each propshaft's plan-view offset, rear joint left of front positive"),
    Key("measurements", "pinion_slope_deg", ANGLE, None, "deg",
        "side-view slope of the pinion, front higher positive, in [-45, 45]"),
    Key("measurements", "gearbox_plan_deg", ANGLE, DEFAULT_PLAN_ANGLE_DEG, "deg",
        "plan-view angle of the gearbox, rear to the left positive"),
    Key("measurements", "pinion_plan_deg", ANGLE, DEFAULT_PLAN_ANGLE_DEG, "deg",
        "plan-view angle of the pinion, rear to the left positive"),
    Key("measurements", "positions", positions_of_measurements, None, "",
        "tables of the measurements that differ in each named position"),
    Key("hardpoints", "points_mm", point_list, None, "mm",
        "gearbox point, joint centres, pinion point: [[x, y, z], ...] in mm"),
    Key("hardpoints", "positions", positions_of_points, None, "mm",
        "named lists of points, one per position"),
    Key("tubes", "outside_diameter_mm", number_list(0.0, 2000.0, "mm"), REQUIRED, "mm",
        "each propshaft's tube outside diameter"),
    Key("tubes", "wall_mm", number_list(0.0, 1000.0, "mm"), REQUIRED, "mm",
        "each propshaft's tube wall, below the radius"),
    Key("tubes", "youngs_modulus_gpa", number(0.0, 1000.0, "GPa", lower_open=True),
        STEEL_YOUNGS_MODULUS_GPA, "GPa", "E of the tubes' material (steel 207)"),
    Key("tubes", "density_kg_m3", number(0.0, 25000.0, "kg/m^3", lower_open=True),
        STEEL_DENSITY_KG_M3, "kg/m^3", "density of the tubes' material (steel 7850)"),
    Key("speed", "max_shaft_speed_rpm", number(0.0, 1e6, "rpm", lower_open=True), None, "rpm",
        "largest propshaft speed; or engine_speed_rpm and top_gear_ratio"),
    Key("speed", "engine_speed_rpm", number(0.0, 1e6, "rpm", lower_open=True), None, "rpm",
        "largest engine speed (with top_gear_ratio)"),
    Key("speed", "top_gear_ratio", number(0.0, 100.0, "", lower_open=True), None, "",
        "the top gear's ratio (engine over propshaft speed)"),
    Key("loads", "torque_n_m", number(0.0, 1e7, "N m", lower_open=True), REQUIRED, "N m",
        "largest gearbox output torque (low gear, wheel slip)"),
    Key("loads", "centre_bearing_mm", number_list(0.0, 1e5, "mm"), None, "mm",
        "each centre bearing's distance ahead of its shaft's rear joint"),
    Key("loads", "gearbox_bearings_mm", bearing_pair, (100.0, 50.0), "mm",
        "[a, b]: gearbox bearings at b and a + b ahead of the first joint"),
    Key("loads", "pinion_bearings_mm", bearing_pair, (50.0, 100.0), "mm",
        "[e, f]: pinion bearings at e and e + f behind the last joint"),
    Key("phasing", "yoke_phase_deg", number_list(-360.0, 360.0, "deg"), None, "deg",
        "each propshaft's yoke phasing (0 in phase); default in phase"),
    Key("rules", "application", choice(tuple(SAFE_SPEED_FRACTION)), "automotive", "",
        "'automotive' (0.70 of critical) or 'industrial' (0.65)"),
    Key("rules", "safe_speed_fraction", number(0.0, 1.0, "", lower_open=True), None, "",
        "overrides the application's safe fraction of the critical speed"),
    Key("rules", "end_tolerance_deg", number(0.0, 10.0, "deg", lower_open=True),
        DEFAULT_END_TOLERANCE_DEG, "deg", "largest difference of a shaft's two joint angles"),
    Key("rules", "inertia_limit_rad_s2", number(0.0, 1e6, "rad/s^2", lower_open=True),
        INERTIA_LIMIT_RAD_S2, "rad/s^2", "inertia excitation limit (Spicer 1000)"),
    Key("layout", "pinion_slope_deg", number_list(-MAX_SLOPE_DEG, MAX_SLOPE_DEG, "deg",
                                                  min_length=2, max_length=2), None, "deg",
        "[low, high] of the pinion's side-view slope to choose (sso run), in [-45, 45]"),
    Key("layout", "centre_bearing_height_mm",
        bounds_list(-MAX_HEIGHT_CHANGE_MM, MAX_HEIGHT_CHANGE_MM, "mm"), None, "mm",
        "[low, high] of each centre bearing's height change (up +) to choose (sso run)"),
    Key("rules", "torsional_limit_rad_s2", number(0.0, 1e6, "rad/s^2", lower_open=True),
        TORSIONAL_LIMIT_RAD_S2, "rad/s^2", "torsional excitation limit (Spicer 300)"),
)


@register_record
@dataclass(frozen=True)
class DrivelineCase(TabledCase):
    """A driveline case as read from a case file, after defaults.

    Attributes: those of :class:`sso._cases.schema.TabledCase`.
    """

    def driveline(self) -> Driveline:
        """The :class:`sso.Driveline` the case describes.

        Raises
        ------
        ValueError
            Naming the key at fault.
        """
        return _driveline(self.values)

    def layout_box(self) -> LayoutBox | None:
        """The ``[layout]`` box, or None where the case gives none.

        Raises
        ------
        ValueError
            Naming the ``layout`` key at fault.
        """
        return _layout_box(self.values)

    def summary(self) -> str:
        """One line for ``sso validate``."""
        driveline = self.driveline()
        angles = ", ".join(f"{beta:.3g}" for beta in driveline.geometry.beta_deg)
        box = self.layout_box()
        chosen = ("" if box is None else
                  ", layout chosen by sso run: " + ", ".join(
                      ([] if box.pinion_slope_deg is None else
                       [f"pinion slope in [{box.pinion_slope_deg[0]:g}, "
                        f"{box.pinion_slope_deg[1]:g}] deg"])
                      + [f"centre bearing {index} height in [{low:g}, {high:g}] mm"
                         for index, (low, high) in enumerate(box.centre_bearing_height_mm,
                                                             start=1)]))
        return (f"driveline: {driveline.joint_count} joints, true angles {angles} deg, "
                f"{driveline.max_shaft_speed_rpm:g} rpm{chosen}")

    def with_overrides(self, solvers: tuple[str, ...] | None = None,
                       formats: tuple[str, ...] | None = None) -> DrivelineCase:
        """A copy with the report formats replaced (a driveline runs no NLP solver).

        Raises
        ------
        ValueError
            If solvers are given: a driveline case has none to choose.
        """
        if solvers is not None:
            raise ValueError("a driveline case runs no NLP solver; leave --solvers out")
        return replace(self, formats=self.formats if formats is None else tuple(formats))

    def to_dict(self) -> dict[str, Any]:
        """The case in the case-file layout (``None`` left out)."""
        return case_document(self, DRIVELINE_KEYS)


def _driveline(values: dict[str, Any]) -> Driveline:
    """The driveline of checked values (the keys checked against each other here)."""
    measured: dict[str, Any] = {name: values.get(f"measurements.{name}")
                                for name in MEASUREMENT_NAMES}
    points = values.get("hardpoints.points_mm")
    given = [name for name in REQUIRED_MEASUREMENTS if measured[name] is not None]
    if (points is None) == (not given):
        raise ValueError("give either [measurements] (gearbox_slope_deg, shaft_slope_deg, "
                         "shaft_length_mm, pinion_slope_deg) or hardpoints.points_mm, "
                         "not both and not neither")
    speed = values.get("speed.max_shaft_speed_rpm")
    engine: Any = values.get("speed.engine_speed_rpm")
    ratio: Any = values.get("speed.top_gear_ratio")
    engine_given = engine is not None or ratio is not None
    if (speed is not None and engine_given) or (speed is None and (engine is None
                                                                   or ratio is None)):
        raise ValueError("give either speed.max_shaft_speed_rpm or both "
                         "speed.engine_speed_rpm and speed.top_gear_ratio")
    if speed is None:
        speed = shaft_speed_from_engine(engine, ratio)
    diameters, walls = values["tubes.outside_diameter_mm"], values["tubes.wall_mm"]
    if len(diameters) != len(walls):
        raise ValueError(f"tubes.wall_mm has {len(walls)} entries; "
                         f"tubes.outside_diameter_mm has {len(diameters)}")
    tubes = []
    for index, (diameter, wall) in enumerate(zip(diameters, walls, strict=True)):
        try:
            tubes.append(Tube(diameter, wall, values["tubes.youngs_modulus_gpa"],
                              values["tubes.density_kg_m3"]))
        except ValueError as error:
            raise ValueError(f"tubes[{index}]: {error}") from None
    options: dict[str, Any] = {
        "tubes": tuple(tubes), "max_shaft_speed_rpm": speed,
        "torque_n_m": values["loads.torque_n_m"],
        "yoke_phase_deg": values.get("phasing.yoke_phase_deg"),
        "centre_bearing_mm": values.get("loads.centre_bearing_mm") or (),
        "gearbox_bearings_mm": values["loads.gearbox_bearings_mm"],
        "pinion_bearings_mm": values["loads.pinion_bearings_mm"],
        "application": values["rules.application"],
        "safe_speed_fraction": values.get("rules.safe_speed_fraction"),
        "end_tolerance_deg": values["rules.end_tolerance_deg"],
        "inertia_limit_rad_s2": values["rules.inertia_limit_rad_s2"],
        "torsional_limit_rad_s2": values["rules.torsional_limit_rad_s2"]}
    if points is not None:
        named = values.get("hardpoints.positions") or {}
        return Driveline(points_mm=points, positions=tuple(
            NamedPosition(name, position) for name, position in named.items()), **options)
    missing = [name for name in REQUIRED_MEASUREMENTS if measured[name] is None]
    if missing:
        raise ValueError(f"measurements.{missing[0]} is missing")
    return Driveline.from_measurements(
        gearbox_slope_deg=measured["gearbox_slope_deg"],
        shaft_slope_deg=measured["shaft_slope_deg"], shaft_length_mm=measured["shaft_length_mm"],
        pinion_slope_deg=measured["pinion_slope_deg"],
        shaft_offset_mm=measured["shaft_offset_mm"],
        gearbox_plan_deg=measured["gearbox_plan_deg"],
        pinion_plan_deg=measured["pinion_plan_deg"],
        positions=values.get("measurements.positions"), **options)


def _layout_box(values: dict[str, Any]) -> LayoutBox | None:
    """The box of ``[layout]`` (None without one)."""
    pinion = values.get("layout.pinion_slope_deg")
    heights = values.get("layout.centre_bearing_height_mm")
    if pinion is None and heights is None:
        return None
    if heights is not None and not isinstance(heights[0], tuple):
        heights = (heights,)
    try:
        return LayoutBox(pinion_slope_deg=pinion, centre_bearing_height_mm=heights or ())
    except ValueError as error:
        raise ValueError(f"layout.{error}") from None


def _build(values: dict[str, Any], path: str) -> DrivelineCase:
    """Check the keys against each other, then build the :class:`DrivelineCase`."""
    driveline = _driveline(values)
    box = _layout_box(values)
    if box is not None:
        if driveline.joint_count < 2:
            raise ValueError("layout: a single joint has no propshaft to lay out; leave "
                             "[layout] out")
        try:
            box.check_fits(driveline.joint_count)
        except ValueError as error:
            raise ValueError(f"layout.{error}") from None
    return DrivelineCase(kind=values["kind"], name=values["name"],
                         description=values["description"],
                         values={label: value for label, value in values.items()
                                 if "." in label and not label.startswith("output.")},
                         formats=values["output.formats"], source=path)


register_case_kind(DRIVELINE_KIND, DRIVELINE_KEYS, _build,
                   optional_tables=frozenset({"measurements", "hardpoints"}))
