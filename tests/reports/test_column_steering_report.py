"""The report section "Steering from lock to lock", from the steering part of a document.

Reference figures: the shipped truck column (tests/data/columns/truck_three_joints.json)
over 2.5 turns each way, checked against the 3D simulation in
tests/column/test_column_steering_range.py: the best 36-tooth assembly (10, -80 deg)
4.260 % and 0.6112 deg, yokes in phase 19.73 % and 4.158 deg.
"""

from __future__ import annotations

import json
from pathlib import Path

from sso._column.geometry import ColumnGeometry
from sso._column.steering_criteria import SteeringLimits, assess_steering
from sso._reports.column_steering_report import steering_blocks
from sso._reports.summary import Heading, Paragraph, Table

TRUCK = json.loads((Path(__file__).resolve().parents[1] / "data" / "columns"
                    / "truck_three_joints.json").read_text())["points_mm"]
DESIGNS = [("splines", "best on the splines", (10.0, -80.0)),
           ("in_phase", "yokes in phase", (0.0, 0.0))]


def document(application: str = "steering", limits: SteeringLimits | None = None) -> dict:
    steering = assess_steering(ColumnGeometry(TRUCK), DESIGNS, lock_deg=900.0, limits=limits)
    return {"steering": steering.to_dict(), "excitation": {"application": application}}


def test_the_section_tabulates_every_assembly_and_judges_nothing_without_limits():
    blocks = steering_blocks(document())
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


def test_limits_set_by_the_case_pass_one_assembly_and_fail_the_other():
    limits = SteeringLimits(speed_fluctuation_percent=5.0, transmission_error_deg=1.0)
    criteria = [block for block in steering_blocks(document(limits=limits))
                if isinstance(block, Table)][1]
    assert criteria.rows[0][1:3] == ("at most 5 %", "set by the case")
    assert criteria.rows[0][3:] == ("4.26 (within)", "19.73 (OUTSIDE)")
    assert criteria.rows[2][3:] == ("0.6112 (within)", "4.158 (OUTSIDE)")


def test_a_driveline_says_the_driveline_limits_judge_its_excitation():
    note = steering_blocks(document(application="driveline"))[-1]
    assert "the SAE AE-7 driveline limits judge the excitation rows" in note.text


def test_a_document_without_steering_figures_has_no_section():
    assert steering_blocks({"excitation": {"application": "steering"}}) == []
