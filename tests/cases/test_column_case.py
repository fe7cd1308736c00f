"""Case kind ``column``: the schema, the cross-key checks, and the shipped column cases.

Reference values: tests/data/columns/*.json (the hardpoints the shipped cases copy).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from sso._cases.column import ColumnCase
from sso._cases.schema import CaseError, load_case, parse_case

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data" / "columns"
SHIPPED = {"column_car_intermediate_shaft": "car_intermediate_shaft",
           "column_truck_three_joints": "truck_three_joints"}
TRUCK = json.loads((DATA / "truck_three_joints.json").read_text())["points_mm"]


def truck(**tables) -> dict:
    document = {"kind": "column", "name": "truck", "hardpoints": {"points_mm": TRUCK}}
    document.update(tables)
    return document


@pytest.mark.parametrize("name", sorted(SHIPPED))
def test_shipped_case_copies_its_hardpoints_and_round_trips(name):
    case = load_case(ROOT / "cases" / f"{name}.toml")
    assert isinstance(case, ColumnCase)
    points = json.loads((DATA / f"{SHIPPED[name]}.json").read_text())["points_mm"]
    assert [list(point) for point in case.values["hardpoints.points_mm"]] == points
    assert parse_case(case.to_dict(), case.source) == case


def test_defaults_fill_a_minimal_case():
    case = parse_case(truck(), "truck.toml")
    assert case.values["phasing.yoke_phase_deg"] == (0.0, 0.0)
    assert case.values["phasing.mode"] == "free"
    assert case.teeth is None and not case.has_joint_boxes
    assert case.excitation_speeds_rpm() == pytest.approx(
        [20.0 + 100.0 * index / 11 for index in range(12)])
    assert case.values["excitation.vehicle"] == "car"
    assert case.geometry().beta_deg == pytest.approx((9.2, 13.3, 19.9), abs=0.03)


def test_joint_position_options_carry_boxes_bounds_and_fixed_phasing():
    boxes = {"min_mm": [[c - 5.0 for c in p] for p in TRUCK[1:-1]],
             "max_mm": [[c + 5.0 for c in p] for p in TRUCK[1:-1]]}
    case = parse_case(truck(joint_boxes=boxes, bounds={"beta_deg": [5.0, 25.0]},
                            phasing={"mode": "fixed", "yoke_phase_deg": [10.0, -80.0]}))
    options = case.joint_position_options()
    assert options["joint_boxes_mm"][0] == [boxes["min_mm"][0], boxes["max_mm"][0]]
    assert options["beta_bounds_deg"] == (5.0, 25.0)
    assert options["yoke_phase_deg"] == (10.0, -80.0)
    assert options["shaft_length_bounds_mm"] is None


@pytest.mark.parametrize("tables, message", [
    ({"hardpoints": {"points_mm": TRUCK[:2]}}, "at least 3"),
    ({"hardpoints": {"points_mm": [[0, 0, 0], [1, 0, 0], [2, 0, 0]]}},
     "hardpoints.points_mm are collinear"),
    ({"hardpoints": {"points_mm": [[0, 0, 0], [1, 0]]}}, r"hardpoints.points_mm\[1\]"),
    ({"splines": {"teeth": [36]}}, "splines.teeth has 1 entries; the column has 2"),
    ({"splines": {"teeth": [36, 0]}}, r"splines.teeth\[1\] = 0 is outside"),
    ({"phasing": {"yoke_phase_deg": [0.0]}}, "phasing.yoke_phase_deg has 1 entries"),
    ({"phasing": {"mode": "loose"}}, "phasing.mode = 'loose' is not one of"),
    ({"excitation": {"rpm": [100.0, 20.0]}}, r"excitation.rpm"),
    ({"excitation": {"vehicle": "bus"}}, "excitation.vehicle = 'bus'"),
    ({"bounds": {"beta_deg": [0.0, 20.0]}}, "bounds.beta_deg lower = 0 must be > 0"),
    ({"joint_boxes": {"min_mm": [[0, 0, 0]] * 3, "max_mm": [[1, 1, 1]] * 3}},
     r"hardpoints.points_mm\[1\] x = -1690.3 mm lies outside joint 1's box"),
    ({"joint_boxes": {"min_mm": [[0, 0, 0]] * 3}}, "joint_boxes.max_mm is missing"),
    ({"splines": {"tooth": [36, 36]}}, "unknown key splines.tooth; did you mean splines.teeth"),
])
def test_bad_column_case_names_the_key(tables, message):
    with pytest.raises(CaseError, match=message):
        parse_case(truck(**tables), "truck.toml")


POSITIONS = json.loads((DATA / "truck_three_positions.json").read_text())["positions"]


def test_shipped_positions_case_copies_its_positions_and_round_trips():
    case = load_case(ROOT / "cases" / "column_truck_three_positions.toml")
    positions = case.values["hardpoints.positions"]
    assert {name: [list(point) for point in points] for name, points in positions.items()} == {
        name: entry["points_mm"] for name, entry in POSITIONS.items()}
    assert [list(point) for point in case.values["hardpoints.points_mm"]] == \
        POSITIONS["tilt_down"]["points_mm"]
    assert parse_case(case.to_dict(), case.source) == case
    assert case.tolerances().samples == 200 and case.feel_options()["lock_deg"] == 600.0


def test_a_case_without_robust_tables_has_none_and_round_trips():
    case = parse_case(truck(), "truck.toml")
    assert case.positions() is None and case.tolerances() is None
    assert case.feel_options() is None
    assert "tolerances" not in case.to_dict() and "feel" not in case.to_dict()
    assert parse_case(case.to_dict(), "truck.toml") == case


FOUR_JOINTS = [*TRUCK[:-1], [-1427.0, 280.0, 312.8], TRUCK[-1]]


@pytest.mark.parametrize("tables, message", [
    ({"hardpoints": {"points_mm": TRUCK, "positions": {"up": TRUCK, "down": FOUR_JOINTS}}},
     r"hardpoints.positions.down has 4 joints \(6 points\) but hardpoints.points_mm has 3"),
    ({"hardpoints": {"points_mm": TRUCK, "positions": {"up": TRUCK}}},
     "hardpoints.positions must be a table of 2 to 20"),
    ({"hardpoints": {"points_mm": TRUCK, "positions": {"up": TRUCK, "down": [[0, 0, 0]] * 5}}},
     "hardpoints.positions.down: "),
    ({"phasing": {"position_weights": {"up": 1.0}}},
     "phasing.position_weights needs"),
    ({"hardpoints": {"points_mm": TRUCK, "positions": {"up": TRUCK, "down": TRUCK}},
      "phasing": {"positions_objective": "mean", "position_weights": {"up": 1.0}}},
     r"phasing.position_weights names \['up'\]; it must name exactly"),
    ({"hardpoints": {"points_mm": TRUCK, "positions": {"up": TRUCK, "down": TRUCK}},
      "phasing": {"position_weights": {"up": 1.0, "down": 1.0}}},
     "phasing.position_weights applies to phasing.positions_objective = 'mean'"),
    ({"tolerances": {"hardpoint_mm": -1.0, "yoke_phase_deg": 1.0}},
     r"tolerances.hardpoint_mm = -1 is outside the allowed range \[0, 100\] mm"),
    ({"tolerances": {"hardpoint_mm": 1.0, "yoke_phase_deg": -0.5}},
     "tolerances.yoke_phase_deg = -0.5 is outside"),
    ({"tolerances": {"hardpoint_mm": 1.0}}, "tolerances.yoke_phase_deg is missing"),
    ({"tolerances": {"hardpoint_mm": 1.0, "yoke_phase_deg": 1.0, "robust_objective": "p100"}},
     "tolerances.robust_objective = 'p100' is not 'mean' or a percentile"),
    ({"tolerances": {"hardpoint_mm": 1.0, "yoke_phase_deg": 1.0, "samples": 10}},
     "tolerances.robust_objective = 'p95' needs at least 20 samples"),
    # The truck column cannot cancel: its least RE is 2.268e-4 (can_cancel, closed form).
    ({"band": {"re_limit": 1e-4}}, r"band.re_limit = 0.0001 is below the least RE .*0.000226"),
    ({"band": {"re_limit": 0.0}}, "band.re_limit = 0 is outside"),
    ({"feel": {"straight_ahead_deg": 0.0}}, "feel.lock_deg is missing"),
    ({"feel": {"straight_ahead_deg": 0.0, "lock_deg": 540.0, "window_deg": 90.0}},
     "feel.window_deg = 90 is outside"),
])
def test_bad_robust_key_names_the_key(tables, message):
    with pytest.raises(CaseError, match=message):
        parse_case(truck(**tables), "truck.toml")


def test_an_error_inside_the_positions_table_names_its_line(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text(f'kind = "column"\n[hardpoints]\npoints_mm = {TRUCK}\n'
                    f'[hardpoints.positions]\nup = {TRUCK}\ndown = [[0, 0, 0], [1, 0, "a"]]\n')
    with pytest.raises(CaseError, match=r"line 4: hardpoints.positions.down\[1\]\[2\] = 'a'"):
        load_case(path)


METRES_AND_SMALL = [
    ([[c / 1000.0 for c in point] for point in TRUCK],
     "hardpoints.points_mm = points 0.15 mm apart (output shaft, P3 to P4) looks like metres "
     "(0.15 m = 149.9 mm)"),
    ([[0, 0, 0], [400, 0, 0], [800, 2.0944, 0], [1200, 100, 30]],
     "hardpoints.points_mm[1]: joint 1 runs at 0.3 deg, below about 0.5 deg (needle bearings "
     "that hardly roll brinell the trunnions"),
]


@pytest.mark.parametrize("points, warning", METRES_AND_SMALL)
def test_a_column_leaving_practice_warns_with_the_reason(points, warning):
    # 2.0944 mm across 400 mm bends joint 1 by atan(2.0944 / 400) = 0.300 deg.
    case = parse_case({"kind": "column", "hardpoints": {"points_mm": points}}, "case.toml")
    (text,) = case.warnings
    assert text.startswith(warning), text


def test_a_named_position_leaving_practice_warns_naming_it():
    tilted = [list(point) for point in TRUCK]
    tilted[0][1] += 300.0  # the steering wheel 300 mm to the right: joint 1 at 32.2 deg
    case = parse_case(truck(hardpoints={"points_mm": TRUCK, "positions": {
        "up": tilted, "down": TRUCK}}, limits={"max_operating_angle_deg": 30.0}), "case.toml")
    (text,) = case.warnings
    assert text.startswith("hardpoints.positions.up[1]: joint 1 runs at 32.2 deg")
    assert "above the maker's limit of 30 deg" in text


BEND_SOURCE = ('kind = "column"\n\n[hardpoints]\npoints_mm = [\n  [0, 0, 0],  # P0\n'
               '  [100, 0, 0],\n  [90, 100, 0],\n  [200, 130, 40],\n]\n')


@pytest.mark.parametrize("source, line, message", [
    (BEND_SOURCE, 6, "hardpoints.points_mm[1]: joint 1 bends by beta = 95.7106 deg, outside "
     "the allowed range [0, 90) deg"),
    (BEND_SOURCE.replace("[90, 100, 0]", "[90, nan, 0]"), 7,
     "hardpoints.points_mm[2][1] = nan"),
    (BEND_SOURCE.replace("[100, 0, 0]", "[0, 0, 0]"), 5,
     "hardpoints.points_mm[0] and points_mm[1] coincide"),
    ('kind = "column"\n[hardpoints]\npoints_mm = [[0, 0, 0], [100, 0, 0], [90, 100, 0], '
     '[200, 130, 40]]\n', 3, "hardpoints.points_mm[1]: joint 1 bends"),
])
def test_a_bad_point_names_its_key_and_the_line_it_is_on(source, line, message):
    # The line of the point itself when the array spans several lines.
    import tomllib

    with pytest.raises(CaseError) as raised:
        parse_case(tomllib.loads(source), "bend.toml", source)
    assert raised.value.line == line
    assert str(raised.value).startswith(f"bend.toml, line {line}: {message}"), str(raised.value)


@pytest.mark.parametrize("value, message", [
    ("90", "limits.yield = 90 is outside the allowed range (0, 1]: the fraction of built "
           "columns that must meet every limit; for 90 % write 0.9"),
    ("0", "limits.yield = 0 is outside the allowed range (0, 1]"),
    ("1.5", "limits.yield = 1.5 is outside the allowed range (0, 1]: the fraction of built "
            "columns that must meet every limit; for 1.5 % write 0.015"),
    ("-0.2", "limits.yield = -0.2 is outside the allowed range (0, 1]"),
    ('"90 %"', "limits.yield = '90 %' must be a number in (0, 1]"),
])
def test_a_required_yield_outside_zero_to_one_names_the_key(tmp_path, value, message):
    text = (ROOT / "cases" / "column_car_limits.toml").read_text()
    path = tmp_path / "car.toml"
    path.write_text(text.replace("yield = 0.9", f"yield = {value}"))
    with pytest.raises(CaseError) as raised:
        load_case(path)
    assert message in str(raised.value)


def test_the_car_columns_required_yield_is_read():
    case = load_case(ROOT / "cases" / "column_car_limits.toml")
    assert case.required_yield == 0.9
    assert load_case(ROOT / "cases" / "column_truck_three_joints.toml").required_yield is None
