"""sweep.csv cells and the manifest: every cell reads back as the value written, rows are
sorted, and a resumed run refuses a folder that holds a different sweep.

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

from sso.batch.table import (
    CSV_NAME,
    MANIFEST_NAME,
    RESULT_COLUMNS,
    SOLVER_FIELDS,
    columns,
    done_rows,
    format_cell,
    format_row,
    manifest,
    parse_cell,
    read_rows,
    typed_rows,
    write_rows,
)

NUMBER_COLUMN = "residual_error"


@given(st.floats(allow_nan=False, allow_infinity=True))
def test_floats_read_back_exactly(value):
    assert parse_cell(NUMBER_COLUMN, format_cell(value)) == value


@given(st.lists(st.floats(allow_nan=False, allow_infinity=False), max_size=6))
def test_lists_read_back_exactly(values):
    assert parse_cell("design_beta_deg", format_cell(values)) == values


@pytest.mark.parametrize(
    "value, cell",
    [
        (None, ""),
        (True, "true"),
        (False, "false"),
        (3, "3"),
        (0.1, "0.1"),
        ((1.5, 2.0), "[1.5, 2.0]"),
        ("ok", "ok"),
    ],
)
def test_cells(value, cell):
    assert format_cell(value) == cell
    expected = list(value) if isinstance(value, tuple) else value
    assert parse_cell(NUMBER_COLUMN if value != "ok" else "status", cell) == expected


def test_text_columns_stay_text():
    assert parse_cell("status", "true") == "true"
    assert parse_cell("ipopt_message", "12") == "12"
    assert parse_cell("best_solver", "") is None
    assert math.isnan(parse_cell(NUMBER_COLUMN, "nan"))


def test_rows_are_written_sorted_and_read_back_typed(tmp_path):
    header = columns(["design.beta_deg[0]"])
    assert header[:2] == ["point", "design.beta_deg[0]"] and header[2:] == list(RESULT_COLUMNS)
    rows = [
        format_row(
            {
                "point": index,
                "design.beta_deg[0]": beta,
                "status": "ok",
                NUMBER_COLUMN: beta / 1e4,
                "success": True,
            },
            header,
        )
        for index, beta in ((2, 30.0), (0, 10.0), (1, 20.0))
    ]
    path = tmp_path / CSV_NAME
    write_rows(path, header, rows)
    back = typed_rows(read_rows(path))
    assert [row["point"] for row in back] == [0, 1, 2]
    assert [row[NUMBER_COLUMN] for row in back] == [0.001, 0.002, 0.003]
    assert back[0]["success"] is True and back[0]["error"] is None
    assert [item.name for item in tmp_path.iterdir()] == [CSV_NAME]


def test_resume_takes_the_finished_rows_of_the_same_sweep_only(tmp_path):
    axes = [SimpleNamespace(path="design.beta_deg[0]", values=(10.0, 20.0, 30.0))]
    expected = manifest({"design": {"beta_deg": [1.0]}}, axes, "grid", "optimise", 3)
    assert done_rows(tmp_path, expected, columns(["design.beta_deg[0]"])) == {}
    header = columns(["design.beta_deg[0]"])
    write_rows(
        tmp_path / CSV_NAME,
        header,
        [
            format_row({"point": 0, "status": "ok"}, header),
            format_row({"point": 1, "status": "lost"}, header),
            format_row({"point": 2, "status": "failed"}, header),
        ],
    )
    with pytest.raises(ValueError, match="has no sweep.json beside it"):
        done_rows(tmp_path, expected, header)
    (tmp_path / MANIFEST_NAME).write_text(json.dumps(expected), encoding="utf-8")
    assert sorted(done_rows(tmp_path, expected, header)) == [
        0,
        2,
    ]  # "lost" is run again
    other = manifest({"design": {"beta_deg": [1.0]}}, axes, "grid", "evaluate", 3)
    with pytest.raises(ValueError, match=r"holds a different sweep \(differs in action\)"):
        done_rows(tmp_path, other, header)
    with pytest.raises(ValueError, match="columns of .* are not those of this sweep"):
        done_rows(tmp_path, expected, columns(["design.phase_deg[0]"]))


def test_manifest_is_json_ready():
    axes = [SimpleNamespace(path="option", values=(1, 2))]
    document = manifest({"name": "x"}, axes, "zip", "evaluate", 2)
    assert json.loads(json.dumps(document)) == {
        "schema_version": 1,
        "case": {"name": "x"},
        "axes": [{"path": "option", "values": [1, 2]}],
        "mode": "zip",
        "action": "evaluate",
        "points": 2,
    }


def test_a_sweep_csv_without_the_lm_columns_still_resumes(tmp_path):
    # The layout before "lm" could be swept: the same columns without lm_*.
    axes = [SimpleNamespace(path="option", values=(1, 2))]
    expected = manifest({"design": {"beta_deg": [1.0]}}, axes, "product", "optimise", 2)
    (tmp_path / MANIFEST_NAME).write_text(json.dumps(expected), encoding="utf-8")
    header = columns(["option"])
    earlier = [column for column in header if not column.startswith("lm_")]
    assert len(header) - len(earlier) == len(SOLVER_FIELDS)
    write_rows(tmp_path / CSV_NAME, earlier,
               [format_row({"point": 0, "option": 1, "status": "ok", "slsqp_residual_error": 0.5},
                           earlier)])
    rows = done_rows(tmp_path, expected, header)
    assert list(rows) == [0]
    write_rows(tmp_path / CSV_NAME, header, rows.values())
    (again,) = read_rows(tmp_path / CSV_NAME)
    assert list(again) == header
    assert again["slsqp_residual_error"] == "0.5" and again["lm_residual_error"] == ""
    with pytest.raises(ValueError, match="columns of .* are not those of this sweep"):
        done_rows(tmp_path, expected, columns(["model"]))
