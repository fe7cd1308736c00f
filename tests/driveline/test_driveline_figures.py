"""The figures of a driveline's result on the truck two-piece (joints at 3, 2.5 and 4 deg in
side view; reference values worked by hand from those angles)."""

from __future__ import annotations

import math

import pytest
from driveline_cases import compound_pickup, truck_two_piece

from sso._driveline.figures import DrivelineResult, analyse_driveline, yoke_words


@pytest.fixture(scope="module")
def truck() -> DrivelineResult:
    return analyse_driveline(truck_two_piece(), phasing=False)


def test_joint_views_and_rules_of_the_planar_truck(truck: DrivelineResult) -> None:
    design = truck.positions[0]
    assert design.slope_deg == pytest.approx((3.0, 0.0, 2.5, -1.5), abs=1e-12)
    assert design.side_view_deg == pytest.approx((3.0, -2.5, 4.0), abs=1e-12)
    assert design.plan_view_deg == pytest.approx((0.0, 0.0, 0.0), abs=1e-12)
    assert design.joint_angle_deg == pytest.approx((3.0, 2.5, 4.0), abs=1e-9)
    assert design.signed_square_deg == pytest.approx(math.sqrt(9 - 6.25 + 16), abs=1e-9)
    verdicts = {(rule.rule, rule.where): rule.passed for rule in truck.rules}
    assert verdicts[("shaft ends within 1 deg", "design, propshaft 1")] is True  # 0.5 deg
    assert verdicts[("shaft ends within 1 deg", "design, propshaft 2")] is False  # 1.5 deg
    assert verdicts[("carrier minus gearbox joint at most 1.5 deg", "design, joints")] is True
    assert not truck.passed


def test_two_view_estimate_of_a_compound_joint() -> None:
    # Spicer J3311 p. 13: sqrt(T^2 + S^2); for the pickup's pinion joint, side 0.42 deg and
    # plan 3.01 deg give 3.039 deg, the exact true angle 3.0391 (second-order difference).
    design = analyse_driveline(compound_pickup(), phasing=False).positions[0]
    assert design.compound_estimate_deg[1] == pytest.approx(math.hypot(0.42, 3.01), abs=1e-9)
    assert design.joint_angle_deg[1] == pytest.approx(design.compound_estimate_deg[1],
                                                      abs=2e-3)
    assert design.signed_square_deg is None


def test_result_round_trips_through_its_record(truck: DrivelineResult) -> None:
    assert DrivelineResult.from_dict(truck.to_dict()) == truck
    assert "torsional" in truck.summary()
    assert "propshaft 2 out of phase (90 deg)" in yoke_words((0.0, 90.0))
