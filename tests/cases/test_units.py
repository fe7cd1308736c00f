"""Values implausible in their unit warn, naming the key, the value and the unit they
look like; ``[units] confirm`` silences the key it names; every shipped case is silent.

Situations from issue 35, item 1: ``lock_deg = 1.5`` meant as turns, the truck
column's operating angles and yoke phasing entered in radians, its hardpoints in
metres. The truck column's points: tests/data/columns/truck_three_joints.json; its
shortest shaft (P3 to P4) is 149.9 mm (cases/column_truck_three_joints.toml's report).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from sso._cases.schema import CaseError, load_case, parse_case

ROOT = Path(__file__).resolve().parents[2]
TRUCK = json.loads((ROOT / "tests" / "data" / "columns" / "truck_three_joints.json")
                   .read_text())["points_mm"]
SHIPPED = sorted((ROOT / "cases").rglob("*.toml"))


def column(**tables) -> dict:
    document = {"kind": "column", "name": "truck", "hardpoints": {"points_mm": TRUCK}}
    document.update(tables)
    return document


def unit_warnings(case) -> list[str]:
    return [text for text in case.warnings if " looks like " in text]


def test_a_lock_in_turns_warns_with_its_value_in_deg():
    (text,) = unit_warnings(parse_case(column(steering={"lock_deg": 1.5})))
    assert text.startswith("steering.lock_deg = 1.5 looks like turns (1.5 turns = 540 deg)")
    assert 'list "steering.lock_deg" in [units] confirm' in text


def test_a_confirmed_lock_is_silent_and_others_still_warn():
    case = parse_case(column(steering={"lock_deg": 1.5}, units={"confirm": ["steering.lock_deg"]},
                             phasing={"yoke_phase_deg": [0.1745, -1.3963]}))
    (text,) = unit_warnings(case)
    assert text.startswith("phasing.yoke_phase_deg = [0.1745, -1.3963] looks like radians")
    # 0.1745 rad = 9.998 deg, -1.3963 rad = -80.00 deg (180 / pi)
    assert f"= [{math.degrees(0.1745):.4g}, {math.degrees(-1.3963):.4g}] deg" in text


def test_operating_angles_in_radians_warn_in_a_shaft_series_case():
    case = parse_case({"design": {"beta_deg": [0.0524, 0.0873]}, "name": "radians"})
    (text,) = unit_warnings(case)
    assert text.startswith("design.beta_deg = [0.0524, 0.0873] looks like radians")
    assert "[3.002, 5.002] deg" in text  # 0.0524 and 0.0873 rad times 180/pi


def test_hardpoints_in_metres_warn_once_and_can_be_confirmed():
    metres = [[coordinate / 1000.0 for coordinate in point] for point in TRUCK]
    (text,) = [text for text in parse_case(column(hardpoints={"points_mm": metres})).warnings
               if "metres" in text]
    assert text.startswith("hardpoints.points_mm = points 0.15 mm apart (output shaft, P3 to P4) "
                           "looks like metres (0.15 m = 149.9 mm)")
    confirmed = parse_case(column(hardpoints={"points_mm": metres},
                                  units={"confirm": ["hardpoints.points_mm"]}))
    assert not [text for text in confirmed.warnings if "metres" in text]


@pytest.mark.parametrize("document", [
    column(steering={"lock_deg": 540.0}),
    column(phasing={"yoke_phase_deg": [10.0, -80.0]}),
    column(phasing={"yoke_phase_deg": [0.0, 1.0]}),  # whole numbers are deg
    {"name": "column", "design": {"beta_deg": [22.0, 30.0], "phase_deg": [90.0]}},
])
def test_plausible_values_are_silent(document):
    assert unit_warnings(parse_case(document)) == []


def test_a_confirmed_key_the_kind_lacks_is_refused():
    with pytest.raises(CaseError, match=r"units.confirm\[0\] = 'steering.lock' is not a key"):
        parse_case(column(units={"confirm": ["steering.lock"]}))


@pytest.mark.parametrize("path", SHIPPED, ids=lambda path: path.name)
def test_every_shipped_case_is_silent(path):
    assert unit_warnings(load_case(path)) == []


def test_several_unknown_keys_are_all_named():
    document = column(solver={"strats": 3}, hardpoints={"points_mm": TRUCK, "bar": 2})
    document["foo"] = 1
    with pytest.raises(CaseError) as raised:
        parse_case(document)
    message = str(raised.value)
    assert "3 unknown keys or tables" in message
    for part in ("unknown key foo", "unknown key hardpoints.bar",
                 "unknown key solver.strats; did you mean solver.starts?"):
        assert part in message


@pytest.mark.parametrize("document", [
    {"name": "radians", "design": {"beta_deg": [0.0524, 0.0873]},
     "units": {"confirm": ["design.beta_deg"]}},
    column(steering={"lock_deg": 1.5}, units={"confirm": ["steering.lock_deg"]}),
])
def test_a_confirmation_is_saved_with_the_case_and_read_back(document):
    case = parse_case(document)
    again = parse_case(case.to_dict())
    assert again == case and unit_warnings(again) == []


def test_phases_in_radians_warn_up_to_a_turn():
    # pi/2 and pi rad: beyond the operating angles' pi/2, within a phase's 2 pi
    case = parse_case({"name": "phases", "design": {"beta_deg": [22.0, 30.0, 25.0],
                                                    "phase_deg": [1.5708, 3.1416]},
                       "bounds": {"phase_deg": [0.0, 6.2832]}})
    texts = unit_warnings(case)
    assert [text.split(" = ")[0] for text in texts] == ["design.phase_deg", "bounds.phase_deg"]
    assert "[1.5708, 3.1416] rad = [90, 180] deg" in texts[0]
