"""The rules a driveline maker checks, each with its limit and its published source."""

from __future__ import annotations

from dataclasses import dataclass

from sso._record import register_record

SPICER_CALCULATOR = "Spicer driveline operating angle calculator (spicerparts.com)"
SPICER_TORSIONAL = ("Spicer torsional analysis calculator, limits as quoted by NZV8 "
                    "(29 Oct 2018)")
MERITOR = "Meritor MM-96147 (rev. 03-21) pp. 79-97"
IMS = "IMS Ltd, SAE joint selection graph (critical speed, safe fraction)"
SPICER_J3311 = "Spicer installation manual J3311 pp. 8, 13, 20"
MINIMUM_JOINT_ANGLE_DEG = 0.5
VIBRATION_FREE_ANGLE_DEG = 3.0
MAXIMUM_COMPOUND_DEG = 5.0
CARRIER_MINUS_GEARBOX_DEG = 1.5
SPEED_TABLE = ((1500.0, 11.5), (2000.0, 8.0 + 40.0 / 60.0), (2500.0, 7.0),
               (3000.0, 5.0 + 50.0 / 60.0), (3500.0, 5.0), (4000.0, 4.2), (4500.0, 3.7),
               (5000.0, 3.2))
"""Largest operating angle (deg) against shaft speed (rpm): Spicer's calculator (3,500 to
5,000 rpm) and Spicer's figures quoted by a Parker Chelsea PTO manual p. 9 (1,500 to
3,000 rpm; 11 deg 30' at 1,500 and below)."""
SPEED_TABLE_SOURCE = (f"{SPICER_CALCULATOR}; Parker Chelsea PTO manual p. 9 quoting "
                      "Spicer")


@register_record
@dataclass(frozen=True)
class Rule:
    """One rule checked: what, where, the figure, its limit and the verdict.

    Attributes
    ----------
    rule : str
    where : str
        The joint, shaft or position it was checked at.
    value : float
    limit : float or None
        None where the rule has no limit at this figure (outside the maker's table).
    unit : str
    passed : bool or None
        None when not judged (no limit).
    source : str
    bound : {"at most", "at least"}
        Which side of the limit passes.
    """

    rule: str
    where: str
    value: float
    limit: float | None
    unit: str
    passed: bool | None
    source: str
    bound: str = "at most"

    @property
    def margin(self) -> float | None:
        """How far the value is inside its limit (negative when over it); None unjudged."""
        if self.limit is None:
            return None
        return self.limit - self.value if self.bound == "at most" else self.value - self.limit


def speed_limit_deg(shaft_speed_rpm: float) -> float | None:
    """The largest joint angle at a shaft speed, deg: the entry of the next tabulated speed
    at or above it (conservative between entries); None above 5,000 rpm (no entry)."""
    for speed, angle in SPEED_TABLE:
        if shaft_speed_rpm <= speed:
            return angle
    return None


def at_most(rule: str, where: str, value: float, limit: float | None, unit: str,
            source: str) -> Rule:
    """A rule ``value <= limit`` (not judged without a limit)."""
    passed = None if limit is None else value <= limit
    return Rule(rule, where, value, limit, unit, passed, source)


def at_least(rule: str, where: str, value: float, limit: float, unit: str, source: str) -> Rule:
    """A rule ``value >= limit``."""
    return Rule(rule, where, value, limit, unit, value >= limit, source, "at least")
