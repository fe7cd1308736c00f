"""Steering criteria: limits a case sets judge the figures; unset limits judge nothing.

Reference figures: the shipped truck column (tests/data/columns/truck_three_joints.json)
with its best 36-tooth assembly (10, -80 deg): 4.260 % speed-ratio fluctuation and a
largest transmission error of 0.611 deg over whole turns (checked against the 3D
simulation in test_column_steering_range.py); yokes in phase: 19.73 % and 4.158 deg.
"""

from __future__ import annotations

import pytest
from column_cases import load

from sso._cases.schema import parse_case
from sso._column.geometry import ColumnGeometry
from sso._column.steering_criteria import (
    NO_PUBLISHED_LIMIT,
    SteeringLimits,
    assess_steering,
)

TRUCK = load("truck_three_joints")["points_mm"]
DESIGNS = [("best", "best on the splines", (10.0, -80.0)), ("in_phase", "in phase", (0.0, 0.0))]


def by_name(design):
    return {criterion.name.split(",")[0]: criterion for criterion in design.criteria}


def test_unset_limits_judge_nothing_and_say_no_limit_is_published():
    assessment = assess_steering(ColumnGeometry(TRUCK), DESIGNS, lock_deg=900.0)
    best = by_name(assessment.designs[0])
    for name in ("speed-ratio fluctuation", "output-torque fluctuation",
                 "largest transmission error"):
        assert best[name].within is None and best[name].limit is None
        assert best[name].source == NO_PUBLISHED_LIMIT
    assert best["speed-ratio fluctuation"].value == pytest.approx(4.2600, abs=1e-4)
    assert best["smallest operating angle"].within is True  # 9.2 >= 0.5
    assert best["largest operating angle"].limit == 35.0
    assert "do not judge a steering column" in assessment.excitation_note


def test_limits_set_by_the_case_pass_the_best_and_fail_the_in_phase_assembly():
    limits = SteeringLimits(speed_fluctuation_percent=5.0, transmission_error_deg=1.0,
                            max_operating_angle_deg=15.0)
    best, in_phase = (by_name(design) for design in assess_steering(
        ColumnGeometry(TRUCK), DESIGNS, lock_deg=900.0, limits=limits).designs)
    assert best["speed-ratio fluctuation"].within is True
    assert best["largest transmission error"].value == pytest.approx(0.6112, abs=1e-4)
    assert best["largest transmission error"].within is True
    assert in_phase["speed-ratio fluctuation"].value == pytest.approx(19.732, abs=1e-3)
    assert in_phase["speed-ratio fluctuation"].within is False
    assert in_phase["largest transmission error"].within is False  # 4.158 deg
    assert best["largest operating angle"].within is False  # 19.9 > 15


def test_the_case_sets_the_range_and_limits_and_feel_gives_their_defaults():
    case = parse_case({"kind": "column", "hardpoints": {"points_mm": TRUCK},
                       "feel": {"straight_ahead_deg": 45.0, "lock_deg": 600.0},
                       "limits": {"transmission_error_deg": 2.0}}, "truck.toml")
    assert case.steering_options() == {"lock_deg": 600.0, "straight_ahead_deg": 45.0,
                                       "on_centre_deg": 30.0}
    assert case.steering_limits() == SteeringLimits(transmission_error_deg=2.0)
    plain = parse_case({"kind": "column", "hardpoints": {"points_mm": TRUCK}}, "truck.toml")
    assert plain.steering_options() == {"lock_deg": 540.0, "straight_ahead_deg": 0.0,
                                        "on_centre_deg": 30.0}


@pytest.mark.parametrize("keywords, match", [
    ({"speed_fluctuation_percent": 0.0}, r"speed_fluctuation_percent = 0 .*\(0, inf\)"),
    ({"max_operating_angle_deg": 90.0}, r"max_operating_angle_deg = 90 .*\(0, 90\)"),
])
def test_bad_limits_name_the_field(keywords, match):
    with pytest.raises(ValueError, match=match):
        SteeringLimits(**keywords)


def test_limits_of_another_type_are_refused():
    with pytest.raises(TypeError, match="limits must be an sso.SteeringLimits, not dict"):
        assess_steering(ColumnGeometry(TRUCK), DESIGNS, limits={"transmission_error_deg": 1.0})
    with pytest.raises(ValueError, match="designs is empty"):
        assess_steering(ColumnGeometry(TRUCK), [])
