"""The first bending critical speed of a tube.

References: the Euler-Bernoulli critical speed of a simply supported uniform tube,
written out with I and A; calcady's worked example (45 in, 3.5 x 0.083 in steel tube,
30 Mpsi, 0.283 lb/in^3: 11,390 rpm).
"""

from __future__ import annotations

import math

import pytest

from sso._driveline.tube import Tube


def test_critical_speed_against_the_hand_formula_and_a_worked_example() -> None:
    tube = Tube(outside_diameter_mm=101.6, wall_mm=2.4)
    length = 1400.0
    outside, inside = 0.1016, 0.1016 - 2 * 0.0024
    inertia = math.pi * (outside**4 - inside**4) / 64
    area = math.pi * (outside**2 - inside**2) / 4
    expected = 30 / math.pi * (math.pi / 1.4) ** 2 * math.sqrt(207e9 * inertia / (7850 * area))
    assert tube.critical_speed_rpm(length) == pytest.approx(expected, rel=1e-6)
    # calcady: 45 in, 3.5 x 0.083 in, E 30 Mpsi, 0.283 lb/in^3 -> 11,390 rpm. We get 11,378.5
    # (0.10 % lower); the page does not give its unit constants in full, so the published
    # figure is held to 0.2 %.
    inch = 25.4
    calcady = Tube(outside_diameter_mm=3.5 * inch, wall_mm=0.083 * inch,
                   youngs_modulus_gpa=30e6 * 6894.757293168 / 1e9,
                   density_kg_m3=0.283 * 0.45359237 / (inch / 1000) ** 3)
    assert calcady.critical_speed_rpm(45 * inch) == pytest.approx(11390, rel=2e-3)
    # split length: where 0.7 of critical equals the speed
    split = tube.split_length_mm(length, 5000.0, 0.7)
    assert 0.7 * tube.critical_speed_rpm(split) == pytest.approx(5000.0, rel=1e-12)
