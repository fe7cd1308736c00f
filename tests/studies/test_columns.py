"""Rows as columns: the CSV text a RowTable writes is the text Python's csv module writes
for the same rows (the reference: ``csv.DictWriter`` on ``format_row`` of the row with
each list spread over its elements), and every row reads back as the values it was
made from."""

from __future__ import annotations

import csv
import io
import pickle

import numpy as np
import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from sso._studies.axes import Axis
from sso._studies.columns import RowTable, TableAssembly
from sso._studies.element_columns import flat_row
from sso._studies.table import format_row, sweep_columns, typed_rows

# A sweep of a two-joint design: two operating angles, one phase a row.
HEADER = sweep_columns({"design": {"beta_deg": [10.0, 20.5], "phase_deg": [90.0]}},
                       [Axis("design.beta_deg[0]", (10.0, 20.0, 30.0)), Axis("option", (1, 2, 3))])

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
    writer.writerows(format_row(flat_row(row), HEADER) for row in rows)
    return buffer.getvalue()


def test_csv_text_is_what_the_csv_module_writes():
    table = RowTable.from_rows(HEADER, ROWS)
    assert table.csv_text() == reference_text(ROWS)
    assert table.columns["residual_error"].dtype == float
    assert np.array_equal(table.columns["design_beta_deg[1]"], [20.5, np.nan, 2.0],
                          equal_nan=True)
    assert "design_beta_deg" not in table.header and "design_phase_deg[1]" not in table.header
    assert "ipopt_status" not in table.columns  # empty in every row: not held


def test_rows_read_back_as_the_csv_file_reads_them():
    table = RowTable.from_rows(HEADER, ROWS)
    back = typed_rows(csv.DictReader(io.StringIO(",".join(HEADER) + "\n" + table.csv_text())))
    assert [table.row(index) for index in range(3)] == back
    assert table.row(1)["design_beta_deg[0]"] is None and table.row(1)["success"] is None
    assert table.row(2)["design_phase_deg[0]"] == 45.0


def test_concatenate_take_and_mixed_kinds():
    first = RowTable.from_rows(HEADER, ROWS[:1])
    second = RowTable.from_rows(HEADER, [{**ROWS[1], "option": "3"}])  # text, not a number
    joined = RowTable.concatenate(HEADER, [first, RowTable.empty(HEADER), second])
    assert joined.length == 2 and joined.columns["option"].dtype == object
    assert [row["option"] for row in joined.rows()] == [3, "3"]
    assert list(joined.take(np.array([1, 0])).columns["point"]) == [1, 0]
    assert joined.csv_text() == reference_text([ROWS[0], {**ROWS[1], "option": "3"}])


def test_whole_numbers_beyond_int64_stay_python_ints():
    # A sweep axis of 2**63 rpm (found by tests/test_fuzz_inputs.py): the row is refused
    # later, with its reason, but the table holding it must not overflow first.
    table = RowTable.from_rows(("point", "input_speed_rpm"),
                               [{"point": 0, "input_speed_rpm": 2**63},
                                {"point": 1, "input_speed_rpm": -(2**63) - 1}])
    assert [row["input_speed_rpm"] for row in table.rows()] == [2**63, -(2**63) - 1]
    assert table.csv_text().splitlines() == ["0,9223372036854775808",
                                             "1,-9223372036854775809"]


def test_a_shorter_design_leaves_its_last_cells_empty_and_a_longer_one_is_refused():
    rows = [{"point": 0, "status": "ok", "design_beta_deg": [10.0], "design_phase_deg": []}]
    table = RowTable.from_rows(HEADER, rows)
    assert table.row(0)["design_beta_deg[1]"] is None
    assert table.csv_text() == reference_text(rows)
    assert table.csv_text().startswith("0,,,ok,,,,,,10.0,,,")
    with pytest.raises(ValueError, match=r"row of point 0 holds design_beta_deg\[2\], beyond "):
        RowTable.from_rows(HEADER, [{"point": 0, "design_beta_deg": [1.0, 2.0, 3.0]}])


@given(st.lists(st.one_of(st.none(), st.floats(allow_nan=False), st.text(max_size=8),
                          st.booleans(), st.integers(-5, 5)), min_size=1, max_size=6))
@example([0.0, -0.0, False])  # found by hypothesis: -0.0 was written as 0.0 beside a 0.0
def test_any_cells_write_as_the_csv_module_writes_them(values):
    rows = [{"point": index, "error": None if not isinstance(value, str) else value,
             "residual_error": value if not isinstance(value, str) else None}
            for index, value in enumerate(values)]
    table = RowTable.from_rows(HEADER, rows)
    assert table.csv_text() == reference_text(rows)


def test_a_pickled_table_holds_the_same_cells():
    table = RowTable.from_rows(HEADER, ROWS * 400)
    back = pickle.loads(pickle.dumps(table))
    assert back.header == table.header and back.length == 1200
    assert [back.row(index) for index in range(6)] == [table.row(index) for index in range(6)]
    assert back.csv_text() == table.csv_text()
    # Flags stay flags and empty cells stay empty: True is never read back as 1.
    assert [type(value) for value in back.columns["success"][:3]] == [bool, type(None), bool]


def test_constant_numbers_and_point_ranges_travel_compactly_and_come_back_bit_for_bit():
    columns = {"point": np.arange(7, 5007), "time_s": np.full(5000, -0.0),
               "design_phase_deg[0]": np.full(5000, 90.0),
               "residual_error": np.linspace(0.0, 1.0, 5000)}
    table = RowTable(("point", "time_s", "design_phase_deg[0]", "residual_error"), columns, 5000)
    data = pickle.dumps(table)
    back = pickle.loads(data)
    for name, column in columns.items():
        assert back.columns[name].dtype == column.dtype
        assert back.columns[name].tobytes() == column.tobytes()
    assert len(data) < 5000 * 8 + 2000  # only the residual errors travel in full


def test_a_column_of_mixed_kinds_is_pickled_as_it_is():
    mixed = np.empty(3, dtype=object)
    mixed[:] = [True, 1, "1"]  # True == 1: codes would merge them
    table = RowTable(("point", "option"), {"point": np.arange(3), "option": mixed}, 3)
    assert [type(value) for value in pickle.loads(pickle.dumps(table)).columns["option"]] == [
        bool, int, str]


def test_chunks_placed_in_any_order_give_the_rows_in_order():
    whole = RowTable.from_rows(HEADER, ROWS * 2)
    parts = [whole.sliced(0, 2), whole.sliced(2, 5), whole.sliced(5, 6)]
    assembly = TableAssembly(HEADER, [2, 3, 1])
    for index in (2, 0, 1):
        assembly.place(index, parts[index])
    assert assembly.table().csv_text() == whole.csv_text()


def test_a_chunk_of_other_columns_is_joined_at_the_end():
    first = RowTable.from_rows(HEADER, ROWS[:1])
    other = RowTable.from_rows(HEADER, [{**ROWS[1], "option": "3"}])  # text, not a number
    assembly = TableAssembly(HEADER, [1, 1])
    assembly.place(1, other)
    with pytest.raises(ValueError, match=r"chunks \[0\] were never placed"):
        assembly.table()
    assembly.place(0, first)
    joined = assembly.table()
    assert [row["option"] for row in joined.rows()] == [3, "3"]
    assert joined.csv_text() == reference_text([ROWS[0], {**ROWS[1], "option": "3"}])
    with pytest.raises(ValueError, match="chunk 0 has 2 rows, not 1"):
        assembly.place(0, RowTable.from_rows(HEADER, ROWS[:2]))


def test_a_long_column_of_few_values_writes_each_cell_as_repr_does():
    # 0.0 and -0.0 are equal as numbers but written apart; NaN is an empty cell.
    values = np.tile([0.0, -0.0, 1e-05, 12.5, np.nan, 1.0 / 3.0], 400)
    rows = [{"point": index, "residual_error": None if value != value else float(value),
             "design_beta_deg": [2.0, -0.0 if value != value else float(value)]}
            for index, value in enumerate(values)]
    table = RowTable.from_rows(HEADER, rows)
    assert table.csv_text() == reference_text(rows)
    assert table.csv_text().splitlines()[1].startswith("1,,,,,-0.0,")
