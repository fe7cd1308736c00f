"""sweep.csv cells and the manifest: every cell reads back as the value written, rows are
appended, and a resumed run refuses a folder that holds a different sweep or rows that
do not belong to this one.

Reference for floats: ``repr`` is the shortest string that reads back to the same
double (Python's float repr guarantee), so the round trip must be exact.
"""

from __future__ import annotations

import json
import math
from types import SimpleNamespace

import pytest
from hypothesis import given
from hypothesis import strategies as st

from sso._studies.columns import RowTable
from sso._studies.table import (
    CSV_NAME,
    HASH_COLUMN,
    MANIFEST_NAME,
    RESULT_COLUMNS,
    append_rows,
    columns,
    done_rows,
    format_cell,
    format_row,
    manifest,
    parse_cell,
    read_rows,
    render_rows,
    start_file,
    sweep_columns,
    typed_rows,
)

NUMBER_COLUMN = "residual_error"


@given(st.floats(allow_nan=False, allow_infinity=True))
def test_floats_read_back_exactly(value):
    assert parse_cell(NUMBER_COLUMN, format_cell(value)) == value


@pytest.mark.parametrize(
    "value, cell",
    [
        (None, ""),
        (True, "true"),
        (False, "false"),
        (3, "3"),
        (0.1, "0.1"),
        ("ok", "ok"),
    ],
)
def test_cells(value, cell):
    assert format_cell(value) == cell
    assert parse_cell(NUMBER_COLUMN if value != "ok" else "status", cell) == value


def test_text_columns_stay_text():
    assert parse_cell("status", "true") == "true"
    assert parse_cell("ipopt_message", "12") == "12"
    assert parse_cell("best_solver", "") is None
    assert math.isnan(parse_cell(NUMBER_COLUMN, "nan"))


def test_rows_are_appended_and_read_back_typed(tmp_path):
    header = columns(["design.beta_deg[0]"])
    assert header[:2] == ["point", "design.beta_deg[0]"]
    assert header[2:] == [*RESULT_COLUMNS, HASH_COLUMN]
    values = [{"point": index, "design.beta_deg[0]": beta, "status": "ok",
               NUMBER_COLUMN: beta / 1e4, "success": True}
              for index, beta in ((2, 30.0), (0, 10.0), (1, 20.0))]
    rows = [format_row(row, header) for row in values]
    path = tmp_path / CSV_NAME
    start_file(path, header)
    append_rows(path, RowTable.from_rows(header, values[:1]).csv_text())
    append_rows(path, RowTable.from_rows(header, values[1:]).csv_text())
    back = typed_rows(read_rows(path))
    assert [row["point"] for row in back] == [2, 0, 1]  # in the order they were appended
    assert [row[NUMBER_COLUMN] for row in back] == [0.003, 0.001, 0.002]
    assert back[1]["success"] is True and back[1]["error"] is None
    assert [item.name for item in tmp_path.iterdir()] == [CSV_NAME]
    assert render_rows(header, rows).splitlines()[1].startswith("0,10.0,ok")


AXES = [SimpleNamespace(path="design.beta_deg[0]", values=(10.0, 20.0, 30.0))]
HEADER = sweep_columns({"design": {"beta_deg": [1.0]}}, AXES)


def _expected():
    return manifest({"design": {"beta_deg": [1.0]}}, AXES, "product", "optimise", 3)


def _axis_cells(index):
    return [format_cell(AXES[0].values[index])]


def _write(folder, rows, identity=None):
    identity = identity or _expected()
    (folder / MANIFEST_NAME).write_text(json.dumps(identity), encoding="utf-8")
    text = render_rows(HEADER, [format_row({HASH_COLUMN: identity[HASH_COLUMN], **row}, HEADER)
                                for row in rows])
    (folder / CSV_NAME).write_text(text, encoding="utf-8")
    return folder / CSV_NAME


def _row(point, status="ok", value=None):
    beta = AXES[0].values[point] if value is None else value
    figures = {NUMBER_COLUMN: 1e-3, "design_beta_deg[0]": beta} if status == "ok" else {}
    return {"point": point, "design.beta_deg[0]": beta, "status": status, **figures}


def test_resume_takes_the_finished_rows_of_the_same_sweep_only(tmp_path):
    assert done_rows(tmp_path, _expected(), HEADER, _axis_cells) == {}
    _write(tmp_path, [_row(0), _row(1, "lost"), _row(2, "failed")])
    (tmp_path / MANIFEST_NAME).unlink()
    with pytest.raises(ValueError, match="has no sweep.json beside it"):
        done_rows(tmp_path, _expected(), HEADER, _axis_cells)
    _write(tmp_path, [_row(0), _row(1, "lost"), _row(2, "failed")])
    assert sorted(done_rows(tmp_path, _expected(), HEADER, _axis_cells)) == [0, 2]  # "lost" again
    other = manifest({"design": {"beta_deg": [1.0]}}, AXES, "product", "evaluate", 3)
    with pytest.raises(ValueError, match=r"holds a different sweep \(differs in action\)"):
        done_rows(tmp_path, other, HEADER, _axis_cells)
    with pytest.raises(ValueError, match="columns of .* are not those of this sweep"):
        done_rows(tmp_path, _expected(), columns(["design.phase_deg[0]"]), _axis_cells)


def test_a_sweep_of_the_list_layout_is_refused_saying_why(tmp_path):
    # A sweep written by sso before each list element had a column of its own: its
    # manifest says schema 2 and its rows hold design_beta_deg = "[10.0]".
    older = {**_expected(), "schema_version": 2}
    (tmp_path / MANIFEST_NAME).write_text(json.dumps(older), encoding="utf-8")
    (tmp_path / CSV_NAME).write_text('point,design_beta_deg\n0,"[10.0]"\n', encoding="utf-8")
    with pytest.raises(ValueError, match=r"holds a sweep written by an older sso \(sweep "
                                         r"schema 2; this sso writes 3, each element of a list "
                                         r"in a column of its own, design_beta_deg\[0\]"):
        done_rows(tmp_path, _expected(), HEADER, _axis_cells)


def test_a_lost_row_is_replaced_by_the_row_computed_later(tmp_path):
    _write(tmp_path, [_row(1, "lost"), _row(0), _row(1)])
    rows = done_rows(tmp_path, _expected(), HEADER, _axis_cells)
    assert sorted(rows) == [0, 1] and rows[1]["status"] == "ok"


# Each reproduction of a foreign or damaged sweep.csv (issue: --resume accepted another
# sweep's rows, a negative point, and failed with AttributeError on a truncated file).
@pytest.mark.parametrize("rows, message", [
    ([_row(0), {**_row(1), "point": 5}], r"line 3: point '5' is outside this sweep's points "
                                         r"\[0, 2\]"),
    ([{**_row(0), "point": -1}], r"line 2: point '-1' is outside"),
    ([_row(0, value=15.0)], r"line 2: point 0 has axis values \['15.0'\], this sweep's point 0 "
                            r"has \['10.0'\]"),
    ([_row(0), _row(0)], "line 3: point 0 is there twice"),
    ([_row(0, status="done")], "line 2: status 'done' is not one of ok, failed, lost"),
])
def test_a_row_that_does_not_belong_is_refused_naming_its_line(tmp_path, rows, message):
    _write(tmp_path, rows)
    with pytest.raises(ValueError, match=message):
        done_rows(tmp_path, _expected(), HEADER, _axis_cells)


def test_rows_of_another_sweep_with_the_same_layout_are_refused(tmp_path):
    # A 200-point sweep's file copied beside a 3-point sweep's manifest.
    wider = [SimpleNamespace(path="design.beta_deg[0]", values=tuple(range(200)))]
    foreign = manifest({"design": {"beta_deg": [1.0]}}, wider, "product", "optimise", 200)
    _write(tmp_path, [_row(0)], identity=foreign)
    (tmp_path / MANIFEST_NAME).write_text(json.dumps(_expected()), encoding="utf-8")
    with pytest.raises(ValueError, match="line 2 belongs to another sweep"):
        done_rows(tmp_path, _expected(), HEADER, _axis_cells)


def test_a_torn_last_line_is_dropped_and_a_cut_row_refused(tmp_path):
    path = _write(tmp_path, [_row(0), _row(1), _row(2)])
    text = path.read_text()
    path.write_text(text[:-7])  # a killed append: the last line has no end
    rows = done_rows(tmp_path, _expected(), HEADER, _axis_cells)
    assert sorted(rows) == [0, 1]
    assert path.read_text() == text[:text.rindex("\n", 0, len(text) - 1) + 1]
    lines = text.splitlines(keepends=True)
    path.write_text(lines[0] + lines[1][:40] + "\n")  # a row cut and ended
    with pytest.raises(ValueError, match="line 2 has .* cells, not the .* of its header"):
        done_rows(tmp_path, _expected(), HEADER, _axis_cells)
    path.write_bytes(b"\xff\xfe garbage\n")
    with pytest.raises(ValueError, match="is not a sweep.csv written by sso"):
        done_rows(tmp_path, _expected(), HEADER, _axis_cells)


def test_manifest_is_json_ready_and_hashes_what_the_sweep_is():
    axes = [SimpleNamespace(path="option", values=(1, 2))]
    document = manifest({"name": "x"}, axes, "product", "evaluate", 2)
    identity = {key: value for key, value in document.items() if key != HASH_COLUMN}
    assert json.loads(json.dumps(identity)) == {
        "schema_version": 3,
        "case": {"name": "x"},
        "axes": [{"path": "option", "values": [1, 2]}],
        "mode": "product",
        "action": "evaluate",
        "points": 2,
    }
    assert len(document[HASH_COLUMN]) == 16
    assert manifest({"name": "y"}, axes, "product", "evaluate", 2)[HASH_COLUMN] != \
        document[HASH_COLUMN]
