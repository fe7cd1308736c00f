"""Public API of sso._linkages.mechanisms: validation, assembly failures and MechanismTable."""

import csv
import dataclasses
import json
import math
import os
import pickle
import subprocess
import sys

import numpy as np
import pytest

from sso._linkages.mechanisms import (
    FourBar,
    MechanismTable,
    QuickReturn,
    SliderCrank,
    slider_crank_method_difference,
)

PAPER_FOURBAR = FourBar(ground=12, crank=2, coupler=15, rocker=9)
PAPER_QUICK_RETURN = QuickReturn(
    crank=50, coupler=237.5, rocker=100, slider_link=250, ground=230.51
)
FOURBAR_COLUMNS = [
    "crank_angle_deg",
    "coupler_angle_deg",
    "rocker_angle_deg",
    "transmission_angle_deg",
    "joint_a_x",
    "joint_a_y",
    "joint_b_x",
    "joint_b_y",
    "coupler_angular_velocity_rad_s",
    "rocker_angular_velocity_rad_s",
    "coupler_angular_accel_rad_s2",
    "rocker_angular_accel_rad_s2",
]
BAD_LENGTHS = [0, -1.5, math.nan, math.inf, "three", True, None]


@pytest.mark.parametrize("field", ["ground", "crank", "coupler", "rocker"])
@pytest.mark.parametrize("value", BAD_LENGTHS)
def test_fourbar_rejects_a_bad_length_naming_field_value_and_range(field, value):
    lengths = {"ground": 12, "crank": 2, "coupler": 15, "rocker": 9, field: value}
    with pytest.raises(ValueError, match=rf"^FourBar\.{field} = ") as error:
        FourBar(**lengths)
    assert repr(value) in str(error.value)
    assert "(0, inf) length units" in str(error.value)


@pytest.mark.parametrize("field", ["crank", "coupler", "rocker", "slider_link", "ground"])
def test_quick_return_rejects_a_bad_length(field):
    lengths = dataclasses.asdict(PAPER_QUICK_RETURN)
    message = rf"QuickReturn\.{field} = -2 is outside the allowed range \(0, inf\) length units"
    with pytest.raises(ValueError, match=message):
        QuickReturn(**lengths | {field: -2.0})


@pytest.mark.parametrize(("field", "value"), [("crank", 0.0), ("rod", math.inf)])
def test_slider_crank_rejects_a_bad_length(field, value):
    lengths = {"crank": 0.05, "rod": 0.3, field: value}
    with pytest.raises(ValueError, match=rf"SliderCrank\.{field} = .*\(0, inf\) length units"):
        SliderCrank(**lengths)


@pytest.mark.parametrize("offset", [math.nan, -math.inf, "zero"])
def test_slider_crank_rejects_a_non_finite_offset(offset):
    message = rf"SliderCrank\.offset = {offset!r} must be (finite|a number)"
    with pytest.raises(ValueError, match=message):
        SliderCrank(crank=0.05, rod=0.3, offset=offset)


@pytest.mark.parametrize("mechanism", [FourBar, QuickReturn])
def test_unknown_branch_is_rejected_with_the_allowed_ones(mechanism):
    fields = [field.name for field in dataclasses.fields(mechanism) if field.name != "branch"]
    with pytest.raises(
        ValueError, match=r"\.branch = 'diagonal' is not one of 'open', 'crossed'"
    ):
        mechanism(**dict.fromkeys(fields, 1.0), branch="diagonal")


def test_mechanisms_are_frozen_and_hold_floats():
    assert PAPER_FOURBAR.ground == 12.0
    assert type(PAPER_FOURBAR.ground) is float
    assert SliderCrank(crank=1, rod=3).offset == 0.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        PAPER_FOURBAR.crank = 3.0  # type: ignore[misc]


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        ({"crank_angle_deg": []}, r"crank_angle_deg = \[\] must be a non-empty one-dim"),
        ({"crank_angle_deg": [[0.0, 10.0]]}, "crank_angle_deg = .* must be a non-empty one-dim"),
        ({"crank_angle_deg": [0.0, math.nan]}, "crank_angle_deg = .* finite numbers"),
        ({"crank_angle_deg": "ten"}, "crank_angle_deg = 'ten' must be .* finite numbers"),
        ({"crank_speed": math.nan}, r"crank_speed = nan must be finite"),
        ({"crank_speed": "five"}, r"crank_speed = 'five' must be a number"),
        ({"crank_accel": math.inf}, r"crank_accel = inf must be finite"),
        ({"on_unassembled": "ignore"}, "on_unassembled = 'ignore' is not one of 'raise', 'mark'"),
    ],
)
def test_analyse_rejects_bad_drive_arguments(arguments, message):
    call = {"crank_angle_deg": [0.0, 90.0], "crank_speed": 5.0, **arguments}
    with pytest.raises(ValueError, match=rf"FourBar.analyse: {message}"):
        PAPER_FOURBAR.analyse(**call)


def test_a_scalar_crank_angle_gives_one_row():
    table = PAPER_FOURBAR.analyse(30, crank_speed=5)
    assert len(table) == 1
    assert table["joint_a_x"][0] == pytest.approx(2 * math.cos(math.radians(30)), rel=1e-15)


def test_fourbar_columns_and_units():
    table = PAPER_FOURBAR.analyse(np.arange(0, 361, 20), crank_speed=5.0, crank_accel=0.0)
    assert table.name == "four-bar"
    assert list(table.columns) == FOURBAR_COLUMNS
    assert list(table.units) == FOURBAR_COLUMNS
    assert table.units["rocker_angle_deg"] == "deg"
    assert table.units["joint_b_x"] == "length"
    assert table.units["rocker_angular_accel_rad_s2"] == "rad/s^2"
    assert len(table) == 19


def test_direction_angles_stay_in_the_half_open_range():
    # At 180 deg the rod angle is -1e-15 deg by rounding; np.mod alone would give 360.0
    # (the paper prints 360.00 there). Direction angles are kept in [0, 360).
    table = SliderCrank(crank=0.05, rod=0.3).analyse([0.0, 180.0, 360.0], crank_speed=188.4)
    rod_angle = table["rod_angle_deg"]
    assert np.all((rod_angle >= 0.0) & (rod_angle < 360.0))
    np.testing.assert_allclose(rod_angle, 0.0, rtol=0, atol=1e-9)


def non_grashof_assembled(crank_angle_deg: np.ndarray) -> np.ndarray:
    """Independent assembly test of FourBar(11, 7, 9, 8): 9 - 8 <= |A O_B| <= 9 + 8."""
    diagonal = np.sqrt(7**2 + 11**2 - 2 * 7 * 11 * np.cos(np.radians(crank_angle_deg)))
    return (diagonal >= 1.0) & (diagonal <= 17.0)


NON_GRASHOF = FourBar(ground=11, crank=7, coupler=9, rocker=8)


def test_unassembled_angles_raise_naming_them():
    # A non-Grashof linkage cannot turn its crank through 140.6..219.4 deg.
    assert NON_GRASHOF.grashof() == "non-Grashof triple-rocker"
    angles = np.arange(0.0, 360.0, 10.0)
    expected = angles[~non_grashof_assembled(angles)]
    np.testing.assert_array_equal(expected, [150, 160, 170, 180, 190, 200, 210])
    with pytest.raises(
        ValueError,
        match=r"cannot be assembled at crank angle\(s\) \[150, 160, 170, 180, 190, 200, 210\] deg",
    ):
        NON_GRASHOF.analyse(angles, crank_speed=1.0)


def test_many_unassembled_angles_are_listed_with_a_count():
    with pytest.raises(ValueError, match=r"\[141, 142, .*, 152, \.\.\. \(79 in all\)\]"):
        NON_GRASHOF.analyse(np.arange(0.0, 360.0, 1.0), crank_speed=1.0)


def test_mark_puts_nan_only_in_the_unassembled_rows():
    angles = np.arange(0.0, 360.0, 10.0)
    table = NON_GRASHOF.analyse(angles, crank_speed=1.0, on_unassembled="mark")
    expected = non_grashof_assembled(angles)
    np.testing.assert_array_equal(table["assembled"], expected)
    assert table.units["assembled"] == ""
    for column in FOURBAR_COLUMNS:
        values = table[column]
        assert np.all(np.isfinite(values[expected])), column
        if column in ("crank_angle_deg", "joint_a_x", "joint_a_y"):
            assert np.all(np.isfinite(values)), column  # the crank alone is always placed
        else:
            assert np.all(np.isnan(values[~expected])), column


def test_mark_adds_the_column_even_when_every_angle_assembles():
    table = PAPER_FOURBAR.analyse([0.0, 90.0], crank_speed=5.0, on_unassembled="mark")
    np.testing.assert_array_equal(table["assembled"], [True, True])


def test_slider_crank_with_a_short_rod_marks_where_it_cannot_reach_the_line():
    # |crank sin(t)| > rod for 0.4 sin(t) > 0.3, i.e. 48.6..131.4 and 228.6..311.4 deg.
    angles = np.arange(0.0, 360.0, 15.0)
    mechanism = SliderCrank(crank=0.4, rod=0.3)
    with pytest.raises(ValueError, match=r"\[60, 75, 90, 105, 120, 240, 255, 270, 285, 300\]"):
        mechanism.analyse(angles, crank_speed=1.0)
    table = mechanism.analyse(angles, crank_speed=1.0, on_unassembled="mark")
    expected = np.abs(0.4 * np.sin(np.radians(angles))) <= 0.3
    np.testing.assert_array_equal(table["assembled"], expected)
    for column in ("piston_velocity", "piston_accel_approximate", "rod_angle_deg"):
        np.testing.assert_array_equal(np.isnan(table[column]), ~expected)


def test_quick_return_with_a_short_slider_link_marks_where_c_cannot_reach_the_line():
    # B stays 79.6..100 mm below the slider line; a 90 mm link reaches it only part way.
    lengths = dataclasses.asdict(PAPER_QUICK_RETURN) | {"slider_link": 90.0}
    mechanism = QuickReturn(**lengths)
    angles = np.arange(0.0, 360.0, 30.0)
    reference = PAPER_QUICK_RETURN.analyse(angles, crank_speed=2.0)
    expected = np.abs(reference["joint_b_y"]) <= 90.0
    assert 0 < expected.sum() < len(angles)
    with pytest.raises(ValueError, match="QuickReturn.*cannot be assembled"):
        mechanism.analyse(angles, crank_speed=2.0)
    table = mechanism.analyse(angles, crank_speed=2.0, on_unassembled="mark")
    np.testing.assert_array_equal(table["assembled"], expected)
    np.testing.assert_array_equal(np.isnan(table["joint_c_speed"]), ~expected)
    np.testing.assert_allclose(table["joint_b_y"], reference["joint_b_y"], rtol=1e-14)


@pytest.mark.parametrize("on_unassembled", ["raise", "mark"])
def test_a_dead_point_raises_in_either_mode(on_unassembled):
    # Change-point linkage at 0 deg: A, O_B and B in line, velocities not determined.
    message = r"is at a dead point .* at crank angle\(s\) \[0\] deg"
    with pytest.raises(ValueError, match=message):
        FourBar(ground=4, crank=2, coupler=4, rocker=2).analyse(
            [0.0, 45.0], crank_speed=1.0, on_unassembled=on_unassembled
        )


def test_swing_angle_needs_a_crank_rocker():
    assert PAPER_FOURBAR.swing_angle_deg() == pytest.approx(32.2614, abs=1e-4)
    with pytest.raises(ValueError, match="needs a crank-rocker, but FourBar.* is a non-Grashof"):
        NON_GRASHOF.swing_angle_deg()


def test_method_difference_validates_through_slider_crank():
    with pytest.raises(ValueError, match=r"SliderCrank\.crank = -0.1 is outside .*\(0, inf\)"):
        slider_crank_method_difference([0.05, -0.1], 0.3, 188.4, [0.0, 90.0])


def small_table() -> MechanismTable:
    return NON_GRASHOF.analyse([0.0, 180.0], crank_speed=1.0, on_unassembled="mark")


def test_table_access_by_key_attribute_and_length():
    table = small_table()
    assert len(table) == 2
    assert table.crank_angle_deg is table["crank_angle_deg"]
    np.testing.assert_array_equal(table.assembled, [True, False])
    with pytest.raises(KeyError, match="no column 'speed'; columns are"):
        table["speed"]
    with pytest.raises(AttributeError, match="has no attribute 'speed'"):
        table.speed  # noqa: B018


def test_table_columns_are_read_only():
    table = small_table()
    with pytest.raises(ValueError, match="read-only"):
        table["joint_b_x"][0] = 1.0


def test_table_rejects_ragged_columns_and_mismatched_units():
    with pytest.raises(ValueError, match="one-dimensional and of equal length"):
        MechanismTable(name="t", columns={"a": [1.0, 2.0], "b": [1.0]}, units={"a": "", "b": ""})
    with pytest.raises(ValueError, match=r"units must name the columns \['a'\] in order"):
        MechanismTable(name="t", columns={"a": [1.0]}, units={"b": ""})


def test_to_dict_is_strict_json_and_reads_back_equal():
    table = small_table()
    data = json.loads(json.dumps(table.to_dict(), allow_nan=False))
    assert data["name"] == "four-bar"
    assert data["units"] == table.units
    assert data["columns"]["assembled"]["data"] == [True, False]
    assert data["columns"]["joint_b_x"]["data"][1] == {"float": "nan"}
    assert data["columns"]["joint_b_x"]["data"][0] == float(table["joint_b_x"][0])
    assert MechanismTable.from_dict(data) == table


def test_to_csv_round_trips_exactly(tmp_path):
    table = small_table()
    path = table.to_csv(tmp_path / "fourbar.csv")
    assert path == tmp_path / "fourbar.csv"
    with path.open(newline="") as handle:
        rows = list(csv.reader(handle))
    assert rows[0] == list(table.columns)
    assert len(rows) == 1 + len(table)
    for index, name in enumerate(table.columns):
        cells = [row[index] for row in rows[1:]]
        if name == "assembled":
            assert cells == ["True", "False"]
        else:
            np.testing.assert_array_equal([float(cell) for cell in cells], table[name])
    assert os.listdir(tmp_path) == ["fourbar.csv"]


def test_to_csv_leaves_the_old_file_whole_when_the_write_fails(tmp_path, monkeypatch):
    path = tmp_path / "table.csv"
    path.write_text("previous\n")

    def failing_replace(source, destination):
        raise OSError("disk full")

    monkeypatch.setattr(os, "replace", failing_replace)
    with pytest.raises(OSError, match="disk full"):
        small_table().to_csv(path)
    assert path.read_text() == "previous\n"
    assert os.listdir(tmp_path) == ["table.csv"]


def test_to_csv_into_a_missing_folder_raises(tmp_path):
    with pytest.raises(OSError):
        small_table().to_csv(tmp_path / "missing" / "table.csv")
    assert os.listdir(tmp_path) == []


def test_table_survives_pickling():
    table = small_table()
    copy = pickle.loads(pickle.dumps(table))
    assert list(copy.columns) == list(table.columns)
    np.testing.assert_array_equal(copy["joint_b_x"], table["joint_b_x"])


def test_importing_mechanisms_loads_neither_casadi_nor_matplotlib():
    # DESIGN.md: the kinematics layer must not import casadi at module level.
    code = (
        "import sys, sso._linkages.mechanisms\n"
        "print(sorted({'casadi', 'matplotlib'} & set(sys.modules)))"
    )
    output = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout
    assert output.strip() == "[]"



def test_an_analysis_table_reads_well_and_writes_its_report(tmp_path):
    import sso

    table = sso.FourBar(ground=12, crank=2, coupler=15, rocker=9).analyse(
        np.arange(0.0, 360.0, 30.0), crank_speed=5.0)
    text = repr(table)
    assert len(text) <= 400 and "\n" not in text and text.startswith("MechanismTable('")
    summary = table.summary()
    # The transmission angle of this linkage spans about 42..120 deg (the design test's
    # start lies inside [40, 120]); the summary shows each column's range.
    row = next(line for line in summary.splitlines() if line.startswith("transmission_angle"))
    low, high = (float(value) for value in row.split()[2:4])
    assert 40.0 < low < high < 130.0
    written = sso.write_report(table, tmp_path / "table", formats=("csv", "json", "md", "html"))
    assert sorted(path.name for path in written) == ["report.html", "report.md", "result.json",
                                                     "table.csv"]
    lines = (tmp_path / "table" / "table.csv").read_text().splitlines()
    assert "joint_b_y_length" in lines[0].split(",")
    assert len(lines) == 13
    cells = lines[2].split(",")
    assert all(len(cell.replace("-", "").replace(".", "").lstrip("0")) <= 6
               for cell in cells if "e" not in cell)
    assert 'class="table"' in (tmp_path / "table" / "report.html").read_text()
