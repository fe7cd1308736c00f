"""Case files of a 3D steering column (kind ``column``).

Hardpoints, splines, excitation, joint boxes.

Tables (every key is listed in the README):

* ``[hardpoints] points_mm``: ``P0 .. P(n+1)`` in mm (input-shaft point, joint
  centres, output-shaft point);
* ``[phasing]``: the yoke phasing as assembled (``yoke_phase_deg``, default in
  phase) and whether the joint-position design may change it (``mode``);
* ``[splines] teeth``: spline teeth per intermediate shaft (optional table);
* ``[excitation]``: rpm range, rows, vehicle class of the published limits;
* ``[steering]``: the lock-to-lock range of the steering figures (``lock_deg``,
  ``straight_ahead_deg``, ``on_centre_deg``; default from ``[feel]`` when given);
* ``[limits]``: limits of the steering criteria and the joint maker's largest
  operating angle (:mod:`sso._column.steering_criteria`), and the yield of built
  columns required to meet them all (``yield``, :mod:`sso._column.yields`);
* ``[tilt]``: a tilt position, ``P0`` turned about a pivot axis
  (:mod:`sso._cases.column_tilt`);
* ``[joint_boxes] min_mm / max_mm``: a box per joint centre (optional table);
  with it ``sso run`` also moves the joints, within ``[bounds]`` on every
  operating angle and shaft length;
* ``[solver]``: as for a shaft series;
* robust phasing (:mod:`sso._cases.column_robust`): ``[hardpoints.positions]``,
  ``phasing.positions_objective`` / ``position_weights``, ``[tolerances]``,
  ``[band]``, ``[feel]``.

The builder checks the keys against each other: the points make a column
(:class:`sso.ColumnGeometry`), counts match the joints and shafts, every joint
lies in its box; it notes where the column leaves practice
(:mod:`sso._column.practice`) in the case's warnings.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

from sso._cases.column_points import point_list
from sso._cases.column_robust import ROBUST_KEYS, ROBUST_TABLES, check_robust
from sso._cases.column_tilt import TILT_KEYS, TILT_TABLE, case_points
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
    whole_number,
)
from sso._cases.shaft_series import checked_solvers, solver_keys
from sso._column.excitation import APPLICATIONS, INERTIAL_LIMIT_RAD_S2
from sso._column.geometry import ColumnGeometry
from sso._column.practice import practice_notes
from sso._column.splines import MAX_TEETH
from sso._column.steering_criteria import SteeringLimits
from sso._column.steering_range import MAX_LOCK_DEG
from sso._column.tolerances import Tolerances
from sso._limits import (
    BETA_LIMIT_DEG,
    DEFAULT_COLUMN_STARTS,
    DEFAULT_JOINT_BETA_BOUNDS_DEG,
    DEFAULT_LOCK_DEG,
    DEFAULT_MAX_OPERATING_ANGLE_DEG,
    DEFAULT_STRAIGHT_AHEAD_DEG,
    DEFAULT_WINDOW_DEG,
)
from sso._record import register_record

COLUMN_KIND = "column"
MAX_EXCITATION_ROWS = 1000
PHASING_MODES = ("free", "fixed")
DEFAULT_RPM = (20.0, 120.0)


def teeth_list(label: str, value: Any) -> tuple[int, ...]:
    """Parser of spline teeth: a list of whole numbers in ``[1, MAX_TEETH]``."""
    if not isinstance(value, list) or not value:
        raise ValueError(f"{label} = {value!r} must be a list of whole numbers in "
                         f"[1, {MAX_TEETH}], one per intermediate shaft")
    item = whole_number(1, MAX_TEETH)
    return tuple(item(f"{label}[{index}]", entry) for index, entry in enumerate(value))


def yield_fraction(label: str, value: Any) -> float:
    """Parser of a required yield: a fraction in ``(0, 1]`` (a percentage is refused
    with the fraction it likely means)."""
    try:
        return number(0.0, 1.0, lower_open=True)(label, value)
    except ValueError as error:
        if isinstance(value, (int, float)) and not isinstance(value, bool) \
                and 1.0 < value <= 100.0:
            raise ValueError(f"{error}: the fraction of built columns that must meet every "
                             f"limit; for {value:g} % write {value / 100.0:g}") from None
        raise


def _rpm_range(label: str, value: Any) -> tuple[float, float]:
    low, high = bounds_list(0.0, math.inf, "rpm")(label, value)
    if not isinstance(low, float) or not isinstance(high, float) or low <= 0.0:
        raise ValueError(f"{label} = {value!r} must be one [min, max] pair of speeds in "
                         "(0, inf) rpm")
    return (low, high)


def _from_feel(label: str, default: float) -> Any:
    """A default that is the ``[feel]`` key ``label`` when the case gives one."""
    def value(values: dict[str, Any], path: str) -> Any:
        given = values.get(label)
        return default if given is None else given

    return value


def _default_yoke_phases(values: dict[str, Any], path: str) -> tuple[float, ...]:
    points = values.get("hardpoints.points_mm") or ()
    return (0.0,) * max(len(points) - 3, 0)


COLUMN_SOLVER_DEFAULTS = {"starts": DEFAULT_COLUMN_STARTS}
COLUMN_KEYS: tuple[Key, ...] = (
    Key("hardpoints", "points_mm", point_list, REQUIRED, "mm",
        "P0 (input shaft), the joint centres, P(n+1) (output shaft): at least 3 [x, y, z] "
        "points, mm"),
    Key("phasing", "yoke_phase_deg", number_list(-180.0, 180.0, "deg", min_length=0),
        _default_yoke_phases, "deg",
        "one per intermediate shaft, each in [-180, 180]; the assembly as built "
        "(default all 0: in phase)"),
    Key("phasing", "mode", choice(PHASING_MODES), "free", "",
        "'free' (the joint-position design re-phases the yokes) or 'fixed' (keeps "
        "phasing.yoke_phase_deg)"),
    Key("splines", "teeth", teeth_list, REQUIRED, "",
        f"one whole number in [1, {MAX_TEETH}] per intermediate shaft"),
    Key("excitation", "rpm", _rpm_range, DEFAULT_RPM, "rpm",
        "[min, max] input speeds, each in (0, inf), min <= max"),
    Key("excitation", "rows", whole_number(2, MAX_EXCITATION_ROWS), 12, "",
        f"[2, {MAX_EXCITATION_ROWS}] speeds, evenly spaced from min to max"),
    Key("excitation", "vehicle", choice(tuple(INERTIAL_LIMIT_RAD_S2)), "car", "",
        "'car' (inertial 1000, torsional 300 rad/s^2) or 'truck' (2000, 500)"),
    Key("excitation", "application", choice(APPLICATIONS), "steering", "",
        "'steering' (the SAE AE-7 driveline limits judge nothing) or 'driveline' (they judge "
        "every row)"),
    Key("joint_boxes", "min_mm", point_list, REQUIRED, "mm",
        "lower corner [x, y, z] of each joint centre's box, one per joint"),
    Key("joint_boxes", "max_mm", point_list, REQUIRED, "mm",
        "upper corner [x, y, z] of each joint centre's box, one per joint"),
    Key("bounds", "beta_deg", bounds_list(0.0, BETA_LIMIT_DEG, "deg", upper_open=True),
        DEFAULT_JOINT_BETA_BOUNDS_DEG, "deg",
        "[lower, upper] or one pair per joint, lower > 0 (a joint must stay bent), upper < 90"),
    Key("bounds", "shaft_length_mm", bounds_list(0.0, math.inf, "mm"), None, "mm",
        "[lower, upper] or one pair per shaft, lower > 0 (default: each shaft at least half "
        "its given length)"),
    *TILT_KEYS,
    *ROBUST_KEYS,
    # After [feel], whose keys are their defaults.
    Key("steering", "lock_deg", number(0.0, MAX_LOCK_DEG, "deg", lower_open=True),
        _from_feel("feel.lock_deg", DEFAULT_LOCK_DEG), "deg",
        f"(0, {MAX_LOCK_DEG:g}]: steering-wheel angle from straight ahead to each lock"),
    Key("steering", "straight_ahead_deg", number(-360.0, 360.0, "deg"),
        _from_feel("feel.straight_ahead_deg", DEFAULT_STRAIGHT_AHEAD_DEG), "deg",
        "[-360, 360]: input angle theta at straight ahead (from the first bend plane's normal)"),
    Key("steering", "on_centre_deg", number(0.0, 90.0, "deg", lower_open=True, upper_open=True),
        _from_feel("feel.window_deg", DEFAULT_WINDOW_DEG), "deg",
        "(0, 90): half-width of the on-centre window, steering-wheel deg"),
    Key("limits", "speed_fluctuation_percent",
        number(0.0, math.inf, "%", lower_open=True, upper_open=True), None, "%",
        "(0, inf): largest speed-ratio fluctuation from lock to lock (no published default)"),
    Key("limits", "torque_fluctuation_percent",
        number(0.0, math.inf, "%", lower_open=True, upper_open=True), None, "%",
        "(0, inf): largest output-torque fluctuation from lock to lock (no published default)"),
    Key("limits", "transmission_error_deg",
        number(0.0, math.inf, "deg", lower_open=True, upper_open=True), None, "deg",
        "(0, inf): largest |transmission error| from lock to lock (no published default)"),
    Key("limits", "max_operating_angle_deg",
        number(0.0, BETA_LIMIT_DEG, "deg", lower_open=True, upper_open=True),
        DEFAULT_MAX_OPERATING_ANGLE_DEG, "deg",
        "(0, 90): the joint maker's largest operating angle"),
    Key("limits", "yield", yield_fraction, None, "",
        "(0, 1]: the fraction of built columns ([tolerances]) that must meet every limit "
        "(judged on its 95 % confidence interval; no default)"),
    *solver_keys(COLUMN_SOLVER_DEFAULTS),
)

"""Place of each dotted label in the schema (the order :meth:`ColumnCase.to_dict` writes)."""


@register_record
@dataclass(frozen=True)
class ColumnCase(TabledCase):
    """A 3D-column case as read from a case file, after defaults.

    Attributes: those of :class:`sso._cases.schema.TabledCase`.
    """

    def geometry(self) -> ColumnGeometry:
        """The column from ``hardpoints.points_mm`` (in the ``[tilt]`` position, if given)."""
        return ColumnGeometry(case_points(self.values))

    @property
    def teeth(self) -> tuple[int, ...] | None:
        """Spline teeth per intermediate shaft, or None without ``[splines]``."""
        teeth: tuple[int, ...] | None = self.values.get("splines.teeth")
        return teeth

    @property
    def has_joint_boxes(self) -> bool:
        """True when the case moves the joints (``[joint_boxes]`` given)."""
        return "joint_boxes.min_mm" in self.values

    @property
    def joint_boxes_mm(self) -> tuple[tuple[tuple[float, ...], tuple[float, ...]], ...]:
        """Lower and upper corner of each joint's box, mm (``[joint_boxes]``), or none."""
        if not self.has_joint_boxes:
            return ()
        return tuple(zip(self.values["joint_boxes.min_mm"], self.values["joint_boxes.max_mm"],
                         strict=True))

    def positions(self) -> dict[str, ColumnGeometry] | None:
        """The named positions (``[hardpoints.positions]``), or None."""
        positions = self.values.get("hardpoints.positions")
        if positions is None:
            return None
        return {name: ColumnGeometry(points) for name, points in positions.items()}

    def tolerances(self) -> Tolerances | None:
        """The ``[tolerances]`` as :class:`sso._column.tolerances.Tolerances`, or None."""
        if self.values.get("tolerances.hardpoint_mm") is None:
            return None
        return Tolerances(**{name: self.values[f"tolerances.{name}"]
                             for name in ("hardpoint_mm", "yoke_phase_deg", "samples", "seed",
                                          "distribution")})

    def feel_options(self) -> dict[str, float] | None:
        """Keyword arguments of :func:`sso._column.feel.steering_feel` (``[feel]``), or None."""
        if self.values.get("feel.lock_deg") is None:
            return None
        return {name: self.values[f"feel.{name}"]
                for name in ("straight_ahead_deg", "window_deg", "lock_deg", "on_centre_weight")}

    def steering_options(self) -> dict[str, float]:
        """Keyword arguments of :func:`sso._column.steering_range.steering_range`."""
        return {name: self.values[f"steering.{name}"]
                for name in ("lock_deg", "straight_ahead_deg", "on_centre_deg")}

    def steering_limits(self) -> SteeringLimits:
        """The ``[limits]`` as :class:`sso._column.steering_criteria.SteeringLimits`."""
        return SteeringLimits(**{name: self.values[f"limits.{name}"]
                                 for name in ("speed_fluctuation_percent",
                                              "torque_fluctuation_percent",
                                              "transmission_error_deg",
                                              "max_operating_angle_deg")})

    @property
    def required_yield(self) -> float | None:
        """``[limits] yield``: the fraction of built columns that must meet every limit,
        or None."""
        value: float | None = self.values.get("limits.yield")
        return value

    @property
    def yield_samples(self) -> int | None:
        """Built columns the yield against ``[limits]`` is judged on (``[tolerances]
        yield_samples``, else ``samples``), or None without ``[tolerances]``."""
        count: int | None = self.values.get("tolerances.yield_samples")
        return self.values.get("tolerances.samples") if count is None else count

    def excitation_speeds_rpm(self) -> tuple[float, ...]:
        """The excitation table's speeds, evenly spaced, rpm."""
        low, high = self.values["excitation.rpm"]
        rows = self.values["excitation.rows"]
        return tuple(low + (high - low) * index / (rows - 1) for index in range(rows))

    def joint_position_options(self) -> dict[str, Any]:
        """Keyword arguments of :func:`sso.optimise_joint_centres` (with ``[joint_boxes]``)."""
        values = self.values
        fixed = values["phasing.mode"] == "fixed"
        return {
            "joint_boxes_mm": [[list(low), list(high)] for low, high in
                               zip(values["joint_boxes.min_mm"], values["joint_boxes.max_mm"],
                                    strict=True)],
            "beta_bounds_deg": values["bounds.beta_deg"],
            "shaft_length_bounds_mm": values["bounds.shaft_length_mm"],
            "yoke_phase_deg": values["phasing.yoke_phase_deg"] if fixed else None,
            **self.solver_options(),
        }

    def solver_options(self) -> dict[str, Any]:
        """The ``[solver]`` keys as keyword arguments."""
        return {name: self.values[f"solver.{name}"]
                for name in ("solvers", "starts", "solver_tol", "max_iterations", "seed")}

    def summary(self) -> str:
        """One line for ``sso validate``."""
        geometry = self.geometry()
        angles = ", ".join(f"{beta:.1f}" for beta in geometry.beta_deg)
        extras = ([f"spline teeth {', '.join(str(count) for count in self.teeth)}"]
                  if self.teeth else [])
        extras += ["joint boxes"] if self.has_joint_boxes else []
        if self.values.get("tilt.angle_deg") is not None:
            extras.append(f"tilted {self.values['tilt.angle_deg']:g} deg")
        positions = self.values.get("hardpoints.positions")
        if positions is not None:
            extras.append(f"positions {', '.join(positions)} "
                          f"({self.values['phasing.positions_objective']})")
        if self.values.get("tolerances.hardpoint_mm") is not None:
            extras.append(f"tolerances ({self.values['tolerances.robust_objective']}, "
                          f"{self.values['tolerances.samples']} samples)")
        extras += [name for name, label in (("band", "band.re_limit"),
                                            ("steering feel", "feel.lock_deg"))
                   if self.values.get(label) is not None]
        return (f"column: {geometry.joint_count} joints, operating angles {angles} deg"
                + "".join(f"; {extra}" for extra in extras))

    def with_overrides(self, solvers: tuple[str, ...] | None = None,
                       formats: tuple[str, ...] | None = None) -> ColumnCase:
        """A copy with the solvers and/or report formats replaced.

        Raises
        ------
        ValueError
            If ``solvers`` breaks the ``solver.solvers`` key (``"lm"`` included: these
            problems have no residual form).
        """
        values = dict(self.values)
        if solvers is not None:
            values["solver.solvers"] = checked_solvers(COLUMN_KEYS, solvers)
        return replace(self, values=values,
                       formats=self.formats if formats is None else tuple(formats))

    def to_dict(self) -> dict[str, Any]:
        """The case in the case-file layout, every default filled in (``None`` left out).

        :func:`sso._cases.schema.parse_case` reads it back into an equal case.
        """
        return case_document(self, COLUMN_KEYS)


def _build(values: dict[str, Any], path: str) -> ColumnCase:
    """Check the keys against each other, then build the :class:`ColumnCase`."""
    points = case_points(values)
    try:
        geometry = ColumnGeometry(points)
    except ValueError as error:
        where = "hardpoints." if points == values["hardpoints.points_mm"] else (
            f"hardpoints tilted by tilt.angle_deg = {values['tilt.angle_deg']:g}: ")
        raise ValueError(f"{where}{error}") from None
    joints, shafts = geometry.joint_count, geometry.joint_count - 1
    if joints < 2:
        raise ValueError("hardpoints.points_mm has 3 points (1 joint): a column case needs at "
                         "least 2 joints (4 points) to phase its yokes")
    _check_count("phasing.yoke_phase_deg", values["phasing.yoke_phase_deg"], shafts,
                 "intermediate shafts")
    if "splines.teeth" in values:
        _check_count("splines.teeth", values["splines.teeth"], shafts, "intermediate shafts")
    low_rpm, high_rpm = values["excitation.rpm"]
    if low_rpm > high_rpm:
        raise ValueError(f"excitation.rpm = [{low_rpm:g}, {high_rpm:g}]: min exceeds max")
    if "joint_boxes.min_mm" in values:
        _check_boxes(values, geometry)
    _check_bounds(values, joints)
    check_robust(values, geometry)
    return ColumnCase(kind=values["kind"], name=values["name"],
                      description=values["description"],
                      values={label: value for label, value in values.items()
                              if "." in label and not label.startswith("output.")},
                      formats=values["output.formats"], source=path,
                      warnings=_practice_warnings(values, geometry))


def _practice_warnings(values: dict[str, Any], geometry: ColumnGeometry) -> tuple[str, ...]:
    """Where the hardpoints, and every named position, leave practice (hardpoints that
    look like metres unless ``[units] confirm`` names them)."""
    limit = values["limits.max_operating_angle_deg"]
    columns = {"hardpoints.points_mm": geometry}
    for name, points in (values.get("hardpoints.positions") or {}).items():
        columns[f"hardpoints.positions.{name}"] = ColumnGeometry(points)
    confirmed = values["units.confirm"]
    return tuple(note.unit.text if note.unit is not None else note.text
                 for label, column in columns.items()
                 for note in practice_notes(column, max_operating_angle_deg=limit, label=label)
                 if not (note.unit is not None and _points_key(label) in confirmed))


def _points_key(label: str) -> str:
    """The case key of a column's points: ``hardpoints.positions`` for every named one."""
    return label if label == "hardpoints.points_mm" else "hardpoints.positions"


def _check_count(label: str, items: tuple[Any, ...], expected: int, what: str) -> None:
    if len(items) != expected:
        noun = what[:-1] if expected == 1 else what
        raise ValueError(f"{label} has {len(items)} entries; the column has {expected} {noun}")


def _check_boxes(values: dict[str, Any], geometry: ColumnGeometry) -> None:
    lows, highs = values["joint_boxes.min_mm"], values["joint_boxes.max_mm"]
    _check_count("joint_boxes.min_mm", lows, geometry.joint_count, "joints")
    _check_count("joint_boxes.max_mm", highs, geometry.joint_count, "joints")
    for index, (low, high) in enumerate(zip(lows, highs, strict=False)):
        point = geometry.points_mm[index + 1]
        for axis, name in enumerate("xyz"):
            if low[axis] > high[axis]:
                raise ValueError(f"joint_boxes.min_mm[{index}] {name} = {low[axis]:g} exceeds "
                                 f"joint_boxes.max_mm[{index}] {name} = {high[axis]:g} mm")
            if not low[axis] <= point[axis] <= high[axis]:
                raise ValueError(f"hardpoints.points_mm[{index + 1}] {name} = {point[axis]:g} mm "
                                 f"lies outside joint {index + 1}'s box [{low[axis]:g}, "
                                 f"{high[axis]:g}] mm (joint_boxes.min_mm / max_mm[{index}])")


def _check_bounds(values: dict[str, Any], joints: int) -> None:
    for label, count, what in (("bounds.beta_deg", joints, "joints"),
                               ("bounds.shaft_length_mm", joints + 1, "shafts")):
        bounds = values[label]
        if bounds is None:
            continue
        pairs = [bounds] if not isinstance(bounds[0], tuple) else list(bounds)
        if len(pairs) not in (1, count):
            raise ValueError(f"{label} has {len(pairs)} pairs; give one pair or one per "
                             f"{what[:-1]} ({count} {what})")
        for index, (low, _) in enumerate(pairs):
            if low <= 0.0:
                name = label if len(pairs) == 1 else f"{label}[{index}]"
                reason = ("a joint must stay bent (a straight joint has no bend plane)"
                          if label == "bounds.beta_deg" else "a shaft needs a length")
                raise ValueError(f"{name} lower = {low:g} must be > 0: {reason}")


register_case_kind(COLUMN_KIND, COLUMN_KEYS, _build,
                   optional_tables=frozenset({"splines", "joint_boxes", TILT_TABLE,
                                             *ROBUST_TABLES}))
