"""Rows as columns: the CSV text a RowTable writes is the text Python's csv module writes
for the same rows (the reference: ``csv.DictWriter`` on ``format_row``), and every row
reads back as the values it was made from."""

from __future__ import annotations

import csv
import io

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from sso.batch.columns import RowTable
from sso.batch.table import columns, format_row, typed_rows

HEADER = columns(["design.beta_deg[0]", "option"])

ROWS = [
    {"point": 0, "design.beta_deg[0]": 10.0, "option": 3, "status": "ok",
     "residual_error": 1e-30, "design_beta_deg": [10.0, 20.5], "design_phase_deg": [90.0],
     "success": True, "warnings": 'a "quoted", comma | b', "time_s": 0.25},
    {"point": 1, "design.beta_deg[0]": 20.0, "option": 2, "status": "failed",
     "error": "CaseError: point 1: x, y", "time_s": 0.5},
    {"point": 2, "design.beta_deg[0]": 30.0, "option": 1, "status": "ok",
     "residual_error": 0.125, "design_beta_deg": [1.0, 2.0], "design_phase_deg": [45.0],
     "success": False, "warnings": "", "time_s": 1e-5},
]


def reference_text(rows):
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=HEADER, lineterminator="\n")
    writer.writerows(format_row(row, HEADER) for row in rows)
    return buffer.getvalue()


def test_csv_text_is_what_the_csv_module_writes():
    table = RowTable.from_rows(HEADER, ROWS)
    assert table.csv_text() == reference_text(ROWS)
    assert table.columns["residual_error"].dtype == float
    assert table.columns["design_beta_deg"].shape == (3, 2)
    assert "ipopt_status" not in table.columns  # empty in every row: not held


def test_rows_read_back_as_the_csv_file_reads_them():
    table = RowTable.from_rows(HEADER, ROWS)
    back = typed_rows(csv.DictReader(io.StringIO(",".join(HEADER) + "\n" + table.csv_text())))
    assert [table.row(index) for index in range(3)] == back
    assert table.row(1)["design_beta_deg"] is None and table.row(1)["success"] is None


def test_concatenate_take_and_mixed_kinds():
    first = RowTable.from_rows(HEADER, ROWS[:1])
    second = RowTable.from_rows(HEADER, [{**ROWS[1], "option": "3"}])  # text, not a number
    joined = RowTable.concatenate(HEADER, [first, RowTable.empty(HEADER), second])
    assert joined.length == 2 and joined.columns["option"].dtype == object
    assert [row["option"] for row in joined.rows()] == [3, "3"]
    assert list(joined.take(np.array([1, 0])).columns["point"]) == [1, 0]
    assert joined.csv_text() == reference_text([ROWS[0], {**ROWS[1], "option": "3"}])


def test_a_design_of_one_joint_has_an_empty_phase_list():
    rows = [{"point": 0, "status": "ok", "design_beta_deg": [10.0], "design_phase_deg": []}]
    table = RowTable.from_rows(HEADER, rows)
    table.columns["design_phase_deg"] = np.zeros((1, 0))  # as the array engine holds it
    assert table.row(0)["design_phase_deg"] == []
    assert table.csv_text() == reference_text(rows)


@given(st.lists(st.one_of(st.none(), st.floats(allow_nan=False), st.text(max_size=8),
                          st.booleans(), st.integers(-5, 5)), min_size=1, max_size=6))
def test_any_cells_write_as_the_csv_module_writes_them(values):
    rows = [{"point": index, "error": None if not isinstance(value, str) else value,
             "residual_error": value if not isinstance(value, str) else None}
            for index, value in enumerate(values)]
    table = RowTable.from_rows(HEADER, rows)
    assert table.csv_text() == reference_text(rows)
