"""The driveline as laid out within its box, and every rule it makes worse.

:func:`sso._driveline.phasing.recommend_phasing` chooses the layout variables (pinion
slope, centre-bearing heights) with the phasing; :class:`LayoutAdvice` holds the
driveline so laid out and phased, its rules, and the trade: each rule whose margin to
its limit shrinks against the layout as given (an excitation, a joint angle, the
difference of a shaft's two ends, a critical speed).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

from sso._display import Part, TextTable, format_number
from sso._driveline.layout_box import LayoutBox, laid_out_points, pinion_slope_of
from sso._driveline.model import Driveline, NamedPosition
from sso._driveline.rules import Rule
from sso._record import register_record

MARGIN_TIE = 1e-9
"""A margin that shrinks by less than this (relative to its limit, or absolute where the
limit is 0) is unchanged."""


@register_record
@dataclass(frozen=True)
class RuleChange:
    """One rule whose margin shrinks from the layout as given to the recommended one."""

    rule: str
    where: str
    given_value: float
    recommended_value: float
    limit: float
    unit: str
    given_passed: bool
    recommended_passed: bool


@register_record
@dataclass(frozen=True)
class LayoutAdvice:
    """The recommended layout and phasing, analysed.

    Attributes
    ----------
    driveline : sso.Driveline
        The driveline laid out (pinion slope, centre-bearing heights) and phased as
        recommended.
    rules : tuple of Rule
        Every rule checked on it (as :attr:`sso.DrivelineResult.rules`).
    trades : tuple of RuleChange
        Every rule whose margin shrinks against the layout as given.
    """

    driveline: Driveline
    rules: tuple[Rule, ...]
    trades: tuple[RuleChange, ...]

    @property
    def passed(self) -> bool:
        """True when every judged rule passes on the recommended layout."""
        return all(rule.passed is not False for rule in self.rules)

    def summary_parts(self) -> list[Part]:
        """The trade for a summary."""
        failed = sum(rule.passed is False for rule in self.rules)
        parts: list[Part] = [
            "Recommended layout: " + ("every rule passes" if not failed else
                                      f"{failed} rule checks FAIL")
            + "; rules whose margin shrinks against the layout as given:"
            + ("" if self.trades else " none")]
        if self.trades:
            parts.append(TextTable(
                ("rule", "where", "given", "recommended", "limit"),
                tuple((change.rule, change.where,
                       f"{format_number(change.given_value)} {change.unit}",
                       f"{format_number(change.recommended_value)} {change.unit}",
                       f"{format_number(change.limit)} {change.unit}")
                      for change in self.trades)))
        return parts


def rule_changes(given: tuple[Rule, ...], recommended: tuple[Rule, ...]
                 ) -> tuple[RuleChange, ...]:
    """The rules (same order in both) whose margin shrinks from ``given`` to ``recommended``.

    Raises
    ------
    ValueError
        If the two lists do not check the same rules at the same places.
    """
    changes = []
    for before, after in zip(given, recommended, strict=True):
        if (before.rule, before.where) != (after.rule, after.where):
            raise ValueError(f"rule lists differ: {before.rule!r} at {before.where!r} "
                             f"against {after.rule!r} at {after.where!r}")
        if before.margin is None or after.margin is None or after.limit is None:
            continue
        if after.margin < before.margin - MARGIN_TIE * max(abs(after.limit), 1.0):
            changes.append(RuleChange(
                rule=after.rule, where=after.where, given_value=before.value,
                recommended_value=after.value, limit=after.limit, unit=after.unit,
                given_passed=bool(before.passed), recommended_passed=bool(after.passed)))
    return tuple(changes)


def laid_out_driveline(driveline: Driveline, box: LayoutBox, layout_values: Sequence[float],
                       yoke_phase_deg: Sequence[float]) -> Driveline:
    """``driveline`` with the layout variables (:attr:`LayoutBox.bounds` order) and phasing.

    Raises
    ------
    ValueError
        If the driveline so laid out is refused (a tube at its critical speed).
    """
    values = list(layout_values)
    change = 0.0
    if box.pinion_slope_deg is not None:
        change = values.pop(0) - pinion_slope_of(driveline.points_mm)
    positions = tuple(NamedPosition(position.name,
                                    laid_out_points(position.points_mm, change, values))
                      for position in driveline.positions)
    return replace(driveline, points_mm=laid_out_points(driveline.points_mm, change, values),
                   positions=positions, yoke_phase_deg=tuple(yoke_phase_deg))
