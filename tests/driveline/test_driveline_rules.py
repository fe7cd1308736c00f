"""The makers' speed table and the rule verdicts.

Reference values: Spicer's operating angle calculator (5,000 rpm 3.2 deg ... 3,500 rpm
5.0 deg) and Spicer's figures quoted by a Parker Chelsea PTO manual p. 9 (3,000 rpm
5 deg 50', 2,500 rpm 7 deg, 2,000 rpm 8 deg 40', 1,500 rpm and below 11 deg 30').
"""

from __future__ import annotations

import pytest

from sso._driveline.rules import at_least, at_most, speed_limit_deg


@pytest.mark.parametrize(("speed_rpm", "limit_deg"), [
    (5000.0, 3.2), (4500.0, 3.7), (4000.0, 4.2), (3500.0, 5.0), (3000.0, 5.0 + 50 / 60),
    (2500.0, 7.0), (2000.0, 8.0 + 40 / 60), (1500.0, 11.5), (800.0, 11.5),
    (3200.0, 5.0),  # between entries: the next tabulated speed above (conservative)
])
def test_speed_table(speed_rpm: float, limit_deg: float) -> None:
    assert speed_limit_deg(speed_rpm) == pytest.approx(limit_deg, abs=1e-12)


def test_no_limit_above_the_table_is_not_judged() -> None:
    assert speed_limit_deg(5000.1) is None
    rule = at_most("joint angle for 6000 rpm", "joint 1", 2.0, speed_limit_deg(6000.0), "deg",
                   "Spicer")
    assert rule.passed is None


def test_verdicts_at_the_limit() -> None:
    assert at_most("r", "w", 1.0, 1.0, "deg", "s").passed is True
    assert at_most("r", "w", 1.0 + 1e-12, 1.0, "deg", "s").passed is False
    assert at_least("r", "w", 0.5, 0.5, "deg", "s").passed is True
    assert at_least("r", "w", 0.49, 0.5, "deg", "s").passed is False
