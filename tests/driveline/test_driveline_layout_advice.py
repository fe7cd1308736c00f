"""The trade of a recommended layout (sso/_driveline/layout_advice.py): every rule whose
margin to its limit shrinks from the layout as given, on either side of its limit."""

from __future__ import annotations

from sso._driveline.layout_advice import rule_changes
from sso._driveline.rules import at_least, at_most


def test_a_rule_whose_margin_shrinks_is_a_trade_either_way_of_its_limit() -> None:
    given = (at_most("torsional", "design", 100.0, 300.0, "rad/s^2", "s"),
             at_least("joint angle", "design", 3.0, 0.5, "deg", "s"),
             at_most("coast", "design", 500.0, 1000.0, "rad/s^2", "s"))
    chosen = (at_most("torsional", "design", 120.0, 300.0, "rad/s^2", "s"),
              at_least("joint angle", "design", 2.0, 0.5, "deg", "s"),
              at_most("coast", "design", 400.0, 1000.0, "rad/s^2", "s"))
    trades = rule_changes(given, chosen)
    assert [(change.rule, change.given_value, change.recommended_value)
            for change in trades] == [("torsional", 100.0, 120.0), ("joint angle", 3.0, 2.0)]
