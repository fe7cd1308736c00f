"""The report section "Steering from lock to lock", from a column run's steering assessment.

Reference figures: the shipped truck column (tests/data/columns/truck_three_joints.json)
over 2.5 turns each way, checked against the 3D simulation in
tests/column/test_column_steering_range.py: the best 36-tooth assembly (10, -80 deg)
4.260 % and 0.6112 deg, yokes in phase 19.73 % and 4.158 deg.
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import pytest

from sso._cases.schema import parse_case
from sso._column.steering_criteria import SteeringLimits, assess_steering
from sso._reports.column_steering_report import steering_blocks
from sso._reports.summary import Heading, Paragraph, Table
from sso._run.column import ColumnRun, run_column

TRUCK = json.loads((Path(__file__).resolve().parents[1] / "data" / "columns"
                    / "truck_three_joints.json").read_text())["points_mm"]
DESIGNS = [("splines", "best on the splines", (10.0, -80.0)),
           ("in_phase", "yokes in phase", (0.0, 0.0))]


@pytest.fixture(scope="module")
def analysed() -> dict[str, ColumnRun]:
    """The truck column analysed as built, as a steering column and as a driveline."""
    return {application: run_column(parse_case(
        {"kind": "column", "hardpoints": {"points_mm": TRUCK},
         "excitation": {"application": application}}, "truck"), optimising=False)
        for application in ("steering", "driveline")}


def document(analysed: dict[str, ColumnRun], application: str = "steering",
             limits: SteeringLimits | None = None) -> ColumnRun:
    """The analysed run with the steering assessment of ``DESIGNS`` over 2.5 turns."""
    run = analysed[application]
    return replace(run, steering=assess_steering(run.geometry, DESIGNS, lock_deg=900.0,
                                                 limits=limits))


def test_the_section_tabulates_every_assembly_and_judges_nothing_without_limits(analysed):
    blocks = steering_blocks(document(analysed))
    assert blocks[0] == Heading(2, "Steering from lock to lock")
    assert "from -900 to +900 deg (steering.lock_deg; 5 turns lock to lock)" in blocks[1].text
    figures, criteria = (block for block in blocks if isinstance(block, Table))
    assert [row[:3] for row in figures.rows] == [("best on the splines", "4.26", "4.26"),
                                                 ("yokes in phase", "19.73", "19.73")]
    assert figures.rows[0][3] == "-0.6112 / 0.6091, 1.22"
    speed = criteria.rows[0]
    assert speed[:2] == ("speed-ratio fluctuation, lock to lock (peak to peak) (%)", "not set")
    assert speed[3:] == ("4.26 (no limit)", "19.73 (no limit)")
    assert criteria.rows[3][1] == "at least 0.5 deg" and "brinell" in criteria.rows[3][2]
    assert blocks[-1] == Paragraph(
        "Excitation limits: SAE AE-7 inertial and torsional excitation limits are for "
        "drivelines at propeller-shaft speeds; they do not judge a steering column.")


def test_limits_set_by_the_case_pass_one_assembly_and_fail_the_other(analysed):
    limits = SteeringLimits(speed_fluctuation_percent=5.0, transmission_error_deg=1.0)
    criteria = [block for block in steering_blocks(document(analysed, limits=limits))
                if isinstance(block, Table)][1]
    assert criteria.rows[0][1:3] == ("at most 5 %", "set by the case")
    assert criteria.rows[0][3:] == ("4.26 (within)", "19.73 (OUTSIDE)")
    assert criteria.rows[2][3:] == ("0.6112 (within)", "4.158 (OUTSIDE)")


def test_a_driveline_says_the_driveline_limits_judge_its_excitation(analysed):
    note = steering_blocks(document(analysed, application="driveline"))[-1]
    assert "the SAE AE-7 driveline limits judge the excitation rows" in note.text
