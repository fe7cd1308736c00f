"""Steering criteria: each assembly's steering figures against limits a case can set.

Limits and where their defaults come from:

* speed-ratio and output-torque fluctuation from lock to lock (percent) and the
  largest transmission error (deg): no published limit for steering columns that
  sso can cite, so none is set by default; a design team sets its own;
* the smallest operating angle: at least 0.5 deg (needle-bearing brinelling, see
  :mod:`sso._column.practice`);
* the largest operating angle: the joint maker's limit, default 35 deg
  (:mod:`sso._column.practice`);
* SAE AE-7 driveline excitation limits (inertial 1000 / 2000, torsional 300 / 500
  rad/s^2): for propeller shafts at driveline speeds (thousands of rpm). They never
  judge a steering column, whose wheel turns at tens of rpm; the excitation table
  judges drivelines only (:func:`sso._column.excitation.excitation_table`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from sso._column.geometry import ColumnGeometry
from sso._column.practice import BRINELLING_SOURCE, MAKER_LIMIT_SOURCE, MIN_OPERATING_ANGLE_DEG
from sso._column.steering_range import SteeringRange, steering_range
from sso._display import Part, Readable, TextTable, format_number, format_numbers
from sso._limits import (
    DEFAULT_LOCK_DEG,
    DEFAULT_MAX_OPERATING_ANGLE_DEG,
    DEFAULT_ON_CENTRE_DEG,
    DEFAULT_STRAIGHT_AHEAD_DEG,
)
from sso._record import Record, register_record
from sso._validation import finite_in_range

NO_PUBLISHED_LIMIT = "no published limit for steering columns; none set by the case"
CASE_LIMIT = "set by the case"
AE7_NOT_APPLICABLE = ("SAE AE-7 inertial and torsional excitation limits are for drivelines at "
                      "propeller-shaft speeds; they do not judge a steering column")


@register_record
@dataclass(frozen=True)
class SteeringLimits:
    """Limits of the steering criteria (``None``: not set).

    Attributes
    ----------
    speed_fluctuation_percent, torque_fluctuation_percent : float or None
        Largest peak-to-peak speed-ratio and output-torque fluctuation from lock to
        lock, percent; no default (none published).
    transmission_error_deg : float or None
        Largest ``|transmission error|`` from lock to lock, deg; no default.
    max_operating_angle_deg : float
        The joint maker's largest operating angle, deg; default 35.
    """

    speed_fluctuation_percent: float | None = None
    torque_fluctuation_percent: float | None = None
    transmission_error_deg: float | None = None
    max_operating_angle_deg: float = DEFAULT_MAX_OPERATING_ANGLE_DEG

    def __post_init__(self) -> None:
        for name in ("speed_fluctuation_percent", "torque_fluctuation_percent",
                     "transmission_error_deg"):
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, finite_in_range(name, value, 0.0, float("inf"),
                                                               lower_open=True, upper_open=True))
        object.__setattr__(self, "max_operating_angle_deg", finite_in_range(
            "max_operating_angle_deg", self.max_operating_angle_deg, 0.0, 90.0, "deg",
            lower_open=True, upper_open=True))


@register_record
@dataclass(frozen=True)
class Criterion:
    """One steering criterion of one assembly.

    Attributes
    ----------
    name : str
        What is judged, in words.
    value : float
    unit : str
    limit : float or None
        ``None`` when no limit is set.
    sense : {"at most", "at least"}
        Which side of the limit passes.
    source : str
        Where the limit comes from, or why there is none.
    within : bool or None
        ``None`` when there is no limit to judge by.
    """

    name: str
    value: float
    unit: str
    limit: float | None
    sense: str
    source: str
    within: bool | None


@register_record
@dataclass(frozen=True, eq=False)
class AssessedDesign:
    """One assembly's steering range and criteria.

    Attributes
    ----------
    role, label : str
        Which assembly (``"as_built"``, ``"best"``, ...) and its name in words.
    yoke_phase_deg : tuple of float
    range : SteeringRange
    criteria : tuple of Criterion
    """

    role: str
    label: str
    yoke_phase_deg: tuple[float, ...]
    range: SteeringRange
    criteria: tuple[Criterion, ...]


@dataclass(frozen=True, eq=False, repr=False)
class SteeringAssessment(Record, Readable):
    """The steering figures and criteria of every assembly a column report compares.

    Attributes
    ----------
    lock_deg, straight_ahead_deg, on_centre_deg : float
        As :func:`sso._column.steering_range.steering_range`.
    limits : SteeringLimits
    designs : tuple of AssessedDesign
    excitation_note : str
        Why the SAE AE-7 limits do not judge the steering figures.
    """

    lock_deg: float
    straight_ahead_deg: float
    on_centre_deg: float
    limits: SteeringLimits
    designs: tuple[AssessedDesign, ...]
    excitation_note: str = AE7_NOT_APPLICABLE

    def _repr_text(self) -> str:
        judged = [criterion.within for design in self.designs for criterion in design.criteria
                  if criterion.within is not None]
        verdict = ("no limits set" if not judged else "within every limit" if all(judged)
                   else f"{judged.count(False)} limit(s) exceeded")
        return (f"{len(self.designs)} assemblies, lock +-{format_number(self.lock_deg)} deg: "
                f"{verdict}")

    def _summary_parts(self) -> list[Part]:
        def judged(value: bool | None) -> str:
            return "no limit" if value is None else "yes" if value else "NO"

        parts: list[Part] = [f"Steering assessment, lock +-{format_number(self.lock_deg)} deg"]
        for design in self.designs:
            parts += [f"{design.label} (yoke phasing "
                      f"[{format_numbers(design.yoke_phase_deg)}] deg)",
                      TextTable(("criterion", "value", "limit", "within"), tuple(
                          (criterion.name, f"{format_number(criterion.value)} {criterion.unit}",
                           "none" if criterion.limit is None
                           else f"{criterion.sense} {format_number(criterion.limit)}",
                           judged(criterion.within)) for criterion in design.criteria))]
        return [*parts, self.excitation_note]


def assess_steering(geometry: ColumnGeometry,
                    designs: Sequence[tuple[str, str, Sequence[float]]], *,
                    lock_deg: float = DEFAULT_LOCK_DEG,
                    straight_ahead_deg: float = DEFAULT_STRAIGHT_AHEAD_DEG,
                    on_centre_deg: float = DEFAULT_ON_CENTRE_DEG,
                    limits: SteeringLimits | None = None) -> SteeringAssessment:
    """Steering range and criteria of each ``(role, label, yoke_phase_deg)`` assembly.

    Raises
    ------
    TypeError, ValueError
        For a bad design or option, naming the field, no designs, or limits that are
        not a :class:`SteeringLimits`.
    """
    if not designs:
        raise ValueError("designs is empty: give at least one (role, label, yoke_phase_deg)")
    limits = SteeringLimits() if limits is None else limits
    if not isinstance(limits, SteeringLimits):
        raise TypeError(f"limits must be an sso.SteeringLimits, not {type(limits).__name__}")
    options = {"lock_deg": lock_deg, "straight_ahead_deg": straight_ahead_deg,
               "on_centre_deg": on_centre_deg}
    assessed = []
    for role, label, yoke in designs:
        figures = steering_range((geometry, yoke), **options)
        assessed.append(AssessedDesign(role, label, tuple(float(value) for value in yoke),
                                       figures, criteria(geometry, figures, limits)))
    first = assessed[0].range
    return SteeringAssessment(lock_deg=first.lock_deg, straight_ahead_deg=first.straight_ahead_deg,
                              on_centre_deg=first.on_centre_deg, limits=limits,
                              designs=tuple(assessed))


def criteria(geometry: ColumnGeometry, figures: SteeringRange,
             limits: SteeringLimits) -> tuple[Criterion, ...]:
    """The steering criteria of one assembly (module notes)."""
    return (
        _criterion("speed-ratio fluctuation, lock to lock (peak to peak)",
                   figures.speed_fluctuation_percent, "%", limits.speed_fluctuation_percent),
        _criterion("output-torque fluctuation, lock to lock (peak to peak)",
                   figures.torque_fluctuation_percent, "%", limits.torque_fluctuation_percent),
        _criterion("largest transmission error, lock to lock",
                   figures.largest_transmission_error_deg, "deg", limits.transmission_error_deg),
        Criterion("smallest operating angle", min(geometry.beta_deg), "deg",
                  MIN_OPERATING_ANGLE_DEG, "at least", BRINELLING_SOURCE,
                  min(geometry.beta_deg) >= MIN_OPERATING_ANGLE_DEG),
        Criterion("largest operating angle", max(geometry.beta_deg), "deg",
                  limits.max_operating_angle_deg, "at most", MAKER_LIMIT_SOURCE,
                  max(geometry.beta_deg) <= limits.max_operating_angle_deg),
    )


def _criterion(name: str, value: float, unit: str, limit: float | None) -> Criterion:
    if limit is None:
        return Criterion(name, value, unit, None, "at most", NO_PUBLISHED_LIMIT, None)
    return Criterion(name, value, unit, limit, "at most", CASE_LIMIT, value <= limit)
