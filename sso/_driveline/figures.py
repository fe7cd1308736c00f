"""The figures a driveline is signed off on, and :class:`DrivelineResult` that holds them."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from sso._column.geometry import ColumnGeometry
from sso._display import Part, Readable, TextTable, format_number
from sso._driveline.excitation import effective_angle_deg, excitations, signed_square_deg
from sso._driveline.layout import plan_angle_deg, side_slope_deg
from sso._driveline.layout_advice import LayoutAdvice, laid_out_driveline, rule_changes
from sso._driveline.layout_box import LayoutBox
from sso._driveline.loads import bearing_names, load_state
from sso._driveline.model import Driveline
from sso._driveline.phasing import PhasingAdvice, recommend_phasing
from sso._driveline.rules import (
    CARRIER_MINUS_GEARBOX_DEG,
    IMS,
    MAXIMUM_COMPOUND_DEG,
    MERITOR,
    MINIMUM_JOINT_ANGLE_DEG,
    SPEED_TABLE_SOURCE,
    SPICER_CALCULATOR,
    SPICER_TORSIONAL,
    Rule,
    at_least,
    at_most,
    speed_limit_deg,
)
from sso._record import Record, register_record

LOAD_SAMPLES = 360
"""Gearbox angles of the bearing-load curves over one revolution (1 deg apart)."""
JOINT_LIFE_NOTE = (
    "Joint life is not computed: no complete public formula was found. A maker rates the "
    "cross bearings as roller bearings with the oscillation taken as rotation (life linear "
    "in speed and cubic in torque, Seherr-Thoss); computing a life needs the maker's "
    "rating of the joint size (its basic torque rating, the angle floor it uses) and the "
    "duty cycle.")


@register_record
@dataclass(frozen=True)
class DrivelinePosition:
    """Angles and excitations of one position (the design or a named one).

    Attributes
    ----------
    name : str
    slope_deg : tuple of float
        Side-view slope of each component, gearbox to pinion, deg (front higher +).
    plan_deg : tuple of float
        Plan-view angle of each component, deg (rear end to the left +).
    joint_angle_deg : tuple of float
        True (compound) angle of each joint, exact from the 3D points, deg.
    side_view_deg, plan_view_deg : tuple of float
        Each joint's angle in side and plan view (component ahead minus behind), deg.
    compound_estimate_deg : tuple of float
        ``sqrt(side^2 + plan^2)`` of each joint (Spicer J3311 p. 13, Meritor p. 87), deg.
    plane_angle_deg : tuple of float
        Angle between consecutive joint planes about the shaft between them, deg.
    effective_angle_deg : float
        Phase-aware effective angle, deg.
    signed_square_deg : float or None
        The signed-square rule, where it applies (planar, phased 0 or 90 deg).
    drive_peak_rad_s2, coast_peak_rad_s2 : tuple of float
        See :class:`sso._driveline.excitation.Excitations`.
    inertia_drive_rad_s2, inertia_coast_rad_s2, torsional_rad_s2 : float
    """

    name: str
    slope_deg: tuple[float, ...]
    plan_deg: tuple[float, ...]
    joint_angle_deg: tuple[float, ...]
    side_view_deg: tuple[float, ...]
    plan_view_deg: tuple[float, ...]
    compound_estimate_deg: tuple[float, ...]
    plane_angle_deg: tuple[float, ...]
    effective_angle_deg: float
    signed_square_deg: float | None
    drive_peak_rad_s2: tuple[float, ...]
    coast_peak_rad_s2: tuple[float, ...]
    inertia_drive_rad_s2: float
    inertia_coast_rad_s2: float
    torsional_rad_s2: float


@register_record
@dataclass(frozen=True)
class TubeFigures:
    """A propshaft's critical speed.

    Attributes
    ----------
    length_mm : float
        Joint centre to joint centre (the span of the simply supported tube), mm.
    critical_speed_rpm, safe_speed_rpm : float
    split_length_mm : float
        The length at which the safe speed equals the maximum shaft speed, mm.
    """

    length_mm: float
    critical_speed_rpm: float
    safe_speed_rpm: float
    split_length_mm: float


@register_record
@dataclass(frozen=True)
class BearingCurve:
    """A bearing's radial load over a revolution of the gearbox, N."""

    name: str
    force_n: tuple[float, ...]
    peak_n: float


@register_record
@dataclass(frozen=True)
class CoupleCurve:
    """A joint's secondary couple over a revolution, N m (on the shaft ahead and behind)."""

    joint: int
    ahead_n_m: tuple[float, ...]
    behind_n_m: tuple[float, ...]


@register_record
@dataclass(frozen=True)
class LoadCurves:
    """The design position's couples and bearing loads at the torque, over a revolution."""

    theta_deg: tuple[float, ...]
    couples: tuple[CoupleCurve, ...]
    bearings: tuple[BearingCurve, ...]


@dataclass(frozen=True, eq=False, repr=False)
class DrivelineResult(Record, Readable):
    """What a driveline is signed off on (:func:`sso.analyse_driveline`).

    Attributes
    ----------
    driveline : sso.Driveline
    positions : tuple of DrivelinePosition
        The design position first, then the named ones.
    tubes : tuple of TubeFigures
        One per propshaft.
    rules : tuple of Rule
        Every rule checked, with its source.
    loads : LoadCurves
    phasing : PhasingAdvice or None
        The yoke phasing recommended for the excitation limits (None if not asked).
    joint_life : str
        Why no joint life is given.
    layout : LayoutAdvice or None
        The driveline laid out within the box and phased as recommended, its rules and
        the rules it makes worse (None without a box).
    """

    driveline: Driveline
    positions: tuple[DrivelinePosition, ...]
    tubes: tuple[TubeFigures, ...]
    rules: tuple[Rule, ...]
    loads: LoadCurves
    phasing: PhasingAdvice | None
    joint_life: str
    layout: LayoutAdvice | None = None
    report_kind: ClassVar[str] = "driveline"

    @property
    def passed(self) -> bool:
        """True when every judged rule passes."""
        return all(rule.passed is not False for rule in self.rules)

    def _repr_text(self) -> str:
        failed = sum(rule.passed is False for rule in self.rules)
        return (f"{self.driveline.joint_count} joints, "
                f"{len(self.tubes)} propshafts, {failed} rules failed")

    def _summary_parts(self) -> list[Part]:
        driveline = self.driveline
        parts: list[Part] = [
            f"Driveline: {driveline.joint_count} joints, {len(self.tubes)} propshafts, "
            f"max shaft speed {format_number(driveline.max_shaft_speed_rpm)} rpm, torque "
            f"{format_number(driveline.torque_n_m)} N m, yokes "
            f"{yoke_words(driveline.phasing_deg)}",
            f"Verdict: {'every rule passes' if self.passed else 'a rule FAILS'}"]
        for figures in self.positions:
            parts.append(f"Position {figures.name}: effective angle "
                         f"{format_number(figures.effective_angle_deg)} deg"
                         + ("" if figures.signed_square_deg is None else
                            f" (signed-square rule "
                            f"{format_number(figures.signed_square_deg)} deg)"))
            parts.append(TextTable(
                ("joint", "true angle (deg)", "side view (deg)", "plan view (deg)",
                 "sqrt(side^2+plan^2) (deg)"),
                tuple((joint_name(k, driveline.joint_count),
                       format_number(figures.joint_angle_deg[k]),
                       format_number(figures.side_view_deg[k]),
                       format_number(figures.plan_view_deg[k]),
                       format_number(figures.compound_estimate_deg[k]))
                      for k in range(driveline.joint_count))))
            parts.append(
                f"excitation at {format_number(driveline.max_shaft_speed_rpm)} rpm (rad/s^2): "
                f"inertia drive {format_number(figures.inertia_drive_rad_s2)}, coast "
                f"{format_number(figures.inertia_coast_rad_s2)} (limit "
                f"{format_number(driveline.inertia_limit_rad_s2)}), torsional "
                f"{format_number(figures.torsional_rad_s2)} (limit "
                f"{format_number(driveline.torsional_limit_rad_s2)})")
        if self.tubes:
            parts.append(TextTable(
                ("propshaft", "length (mm)", "critical (rpm)", "safe (rpm)",
                 "split above (mm)"),
                tuple((f"propshaft {k + 1}", format_number(tube.length_mm),
                       format_number(tube.critical_speed_rpm),
                       format_number(tube.safe_speed_rpm),
                       format_number(tube.split_length_mm))
                      for k, tube in enumerate(self.tubes))))
        parts.append(TextTable(
            ("rule", "where", "value", "limit", "verdict", "source"),
            tuple((rule.rule, rule.where, f"{format_number(rule.value)} {rule.unit}",
                   "-" if rule.limit is None else f"{format_number(rule.limit)} {rule.unit}",
                   verdict_word(rule.passed), rule.source) for rule in self.rules)))
        parts.append(TextTable(
            ("bearing", f"peak radial load at {format_number(driveline.torque_n_m)} N m (N)"),
            tuple((curve.name, format_number(curve.peak_n)) for curve in self.loads.bearings)))
        if self.phasing is not None:
            parts.extend(self.phasing.summary_parts())
        if self.layout is not None:
            parts.extend(self.layout.summary_parts())
        parts.append(self.joint_life)
        return parts


def verdict_word(passed: bool | None) -> str:
    """``pass``, ``FAIL`` or ``not judged``."""
    return "not judged" if passed is None else "pass" if passed else "FAIL"


def yoke_words(phasing_deg: tuple[float, ...]) -> str:
    """The yoke phasing in a fitter's words."""
    if not phasing_deg:
        return "(single joint)"
    words = []
    for shaft, phase in enumerate(phasing_deg, start=1):
        wrapped = float(np.mod(phase + 90.0, 180.0) - 90.0)
        if abs(wrapped) < 1e-9:
            words.append(f"propshaft {shaft} in phase")
        elif abs(abs(wrapped) - 90.0) < 1e-9:
            words.append(f"propshaft {shaft} out of phase (90 deg)")
        else:
            words.append(f"propshaft {shaft} turned {format_number(wrapped)} deg")
    return ", ".join(words)


def joint_name(joint: int, joints: int) -> str:
    """A joint in the trade's words (0-based index)."""
    if joints == 1:
        return "joint 1 (power take-off)"
    if joint == 0:
        return "joint 1 (gearbox)"
    if joint == joints - 1:
        return f"joint {joint + 1} (pinion)"
    return f"joint {joint + 1} (centre bearing {joint})"


def position_figures(name: str, geometry: ColumnGeometry, phasing: tuple[float, ...],
                     speed_rpm: float) -> DrivelinePosition:
    """Angles and excitations of one position."""
    directions = geometry.shaft_directions
    slopes = tuple(side_slope_deg(direction) for direction in directions)
    plans = tuple(plan_angle_deg(direction) for direction in directions)
    side = tuple(slopes[k] - slopes[k + 1] for k in range(geometry.joint_count))
    plan = tuple(plans[k] - plans[k + 1] for k in range(geometry.joint_count))
    figures = excitations(geometry, phasing, speed_rpm)
    return DrivelinePosition(
        name=name, slope_deg=slopes, plan_deg=plans, joint_angle_deg=geometry.beta_deg,
        side_view_deg=side, plan_view_deg=plan,
        compound_estimate_deg=tuple(math.hypot(s, p) for s, p in zip(side, plan, strict=True)),
        plane_angle_deg=geometry.plane_angle_deg,
        effective_angle_deg=effective_angle_deg(geometry, phasing),
        signed_square_deg=signed_square_deg(geometry, phasing),
        drive_peak_rad_s2=figures.drive_peak_rad_s2, coast_peak_rad_s2=figures.coast_peak_rad_s2,
        inertia_drive_rad_s2=figures.inertia_drive_rad_s2,
        inertia_coast_rad_s2=figures.inertia_coast_rad_s2,
        torsional_rad_s2=figures.torsional_rad_s2)


def tube_figures(driveline: Driveline) -> tuple[TubeFigures, ...]:
    """Critical and safe speeds of each propshaft."""
    lengths = driveline.geometry.shaft_length_mm[1:-1]
    tubes = []
    for tube, length in zip(driveline.tubes, lengths, strict=True):
        critical = tube.critical_speed_rpm(length)
        tubes.append(TubeFigures(
            length_mm=length, critical_speed_rpm=critical,
            safe_speed_rpm=driveline.safe_fraction * critical,
            split_length_mm=tube.split_length_mm(length, driveline.max_shaft_speed_rpm,
                                                 driveline.safe_fraction)))
    return tuple(tubes)


def load_curves(driveline: Driveline) -> LoadCurves:
    """Couples and bearing loads of the design position over a revolution."""
    theta_deg = tuple(360.0 * index / LOAD_SAMPLES for index in range(LOAD_SAMPLES))
    states = [load_state(driveline.geometry, driveline.phasing_deg, driveline.bearings,
                         driveline.torque_n_m, math.radians(angle)) for angle in theta_deg]
    couples = tuple(CoupleCurve(
        joint=joint + 1,
        ahead_n_m=tuple(float(state.bending_ahead_n_m[joint]) for state in states),
        behind_n_m=tuple(float(state.bending_behind_n_m[joint]) for state in states))
        for joint in range(driveline.joint_count))
    bearings = []
    for name in bearing_names(driveline.joint_count):
        force = tuple(float(np.linalg.norm(state.bearing_force_n[name])) for state in states)
        bearings.append(BearingCurve(name=name, force_n=force, peak_n=max(force)))
    return LoadCurves(theta_deg=theta_deg, couples=couples, bearings=tuple(bearings))


def rules(driveline: Driveline, positions: tuple[DrivelinePosition, ...],
          tubes: tuple[TubeFigures, ...]) -> tuple[Rule, ...]:
    """Every maker's rule at every position."""
    checked: list[Rule] = []
    joints = driveline.joint_count
    speed = driveline.max_shaft_speed_rpm
    speed_limit = speed_limit_deg(speed)
    for figures in positions:
        where = f"{figures.name}, "
        for k, angle in enumerate(figures.joint_angle_deg):
            name = where + joint_name(k, joints)
            checked.append(at_least("joint angle at least 0.5 deg", name, angle,
                                    MINIMUM_JOINT_ANGLE_DEG, "deg", SPICER_CALCULATOR))
            checked.append(at_most("compound angle at most 5 deg", name, angle,
                                   MAXIMUM_COMPOUND_DEG, "deg", MERITOR))
            checked.append(at_most(f"joint angle for {format_number(speed)} rpm", name, angle,
                                   speed_limit, "deg", SPEED_TABLE_SOURCE))
        for shaft in range(1, joints):
            difference = abs(figures.joint_angle_deg[shaft - 1] - figures.joint_angle_deg[shaft])
            checked.append(at_most(
                f"shaft ends within {format_number(driveline.end_tolerance_deg)} deg",
                where + f"propshaft {shaft}", difference, driveline.end_tolerance_deg, "deg",
                SPICER_CALCULATOR))
        if joints > 1:
            checked.append(at_most(
                "carrier minus gearbox joint at most 1.5 deg", where + "joints",
                figures.joint_angle_deg[-1] - figures.joint_angle_deg[0],
                CARRIER_MINUS_GEARBOX_DEG, "deg", MERITOR))
        for rule, value, limit in (
                ("inertia excitation, drive", figures.inertia_drive_rad_s2,
                 driveline.inertia_limit_rad_s2),
                ("inertia excitation, coast", figures.inertia_coast_rad_s2,
                 driveline.inertia_limit_rad_s2),
                ("torsional excitation", figures.torsional_rad_s2,
                 driveline.torsional_limit_rad_s2)):
            checked.append(at_most(rule, where + f"{format_number(speed)} rpm", value, limit,
                                   "rad/s^2", SPICER_TORSIONAL))
    for shaft, tube in enumerate(tubes, start=1):
        checked.append(at_most(
            f"shaft speed at most {format_number(driveline.safe_fraction)} of critical",
            f"propshaft {shaft}", speed, tube.safe_speed_rpm, "rpm", IMS))
    return tuple(checked)


def analyse_driveline(driveline: Driveline, *, phasing: bool = True,
                      layout: LayoutBox | None = None) -> DrivelineResult:
    """Every figure of :class:`DrivelineResult` for ``driveline``.

    Parameters
    ----------
    phasing : bool
        Also recommend a yoke phasing for the excitation limits (default True).
    layout : LayoutBox, optional
        Also choose the pinion slope and centre-bearing heights within this box, with
        the phasing (:mod:`sso._driveline.phasing`); needs ``phasing``.

    Raises
    ------
    ValueError
        If a layout box is given without ``phasing``, to a single joint, or with more
        centre bearings than the driveline has.
    """
    if layout is not None and not phasing:
        raise ValueError("layout: a layout box is chosen with the phasing; give phasing=True")
    positions = analysed_positions(driveline)
    tubes = tube_figures(driveline)
    checked = rules(driveline, positions, tubes)
    advice = None
    if layout is not None or (phasing and driveline.joint_count > 1):
        advice = recommend_phasing(driveline, layout)
    laid_out = None
    if layout is not None and advice is not None:
        chosen = laid_out_driveline(driveline, layout, advice.layout_values,
                                    advice.yoke_phase_deg)
        chosen_positions = analysed_positions(chosen)
        chosen_rules = rules(chosen, chosen_positions, tube_figures(chosen))
        laid_out = LayoutAdvice(driveline=chosen, rules=chosen_rules,
                                trades=rule_changes(checked, chosen_rules))
    return DrivelineResult(driveline=driveline, positions=positions, tubes=tubes,
                           rules=checked, loads=load_curves(driveline), phasing=advice,
                           joint_life=JOINT_LIFE_NOTE, layout=laid_out)


def analysed_positions(driveline: Driveline) -> tuple[DrivelinePosition, ...]:
    """The figures of every position of ``driveline`` at its own phasing."""
    return tuple(position_figures(name, geometry, driveline.phasing_deg,
                                  driveline.max_shaft_speed_rpm)
                 for name, geometry in driveline.named_geometries().items())
