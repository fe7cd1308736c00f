"""The array engine against the point-by-point path it replaces.

Reference: each point read as a case and solved by ``sso.optimise(..., solvers=("lm",))``
or evaluated by ``sso.ShaftSeries.evaluate`` on its own (``sso._studies.worker.run_point``, the
path every sweep took before): the engine's rows must give the same RE within 1e-12 and
the same success flags, whichever way the sweep runs (one process, the pool).
"""

from __future__ import annotations

import mmap
import sys

import numpy as np
import pytest

import sso
from sso._studies.array_engine import array_plan, number_columns
from sso._studies.axes import base_case, parse_axes
from sso._studies.element_columns import gathered
from sso._studies.table import TIME_COLUMNS
from sso._studies.worker import SweepChunk, run_point, run_sweep_chunk

RE_ATOL = 1e-12


def lm_document(option, starts, joints=3):
    return base_case({"design": {"beta_deg": [30.0, 40.0, 40.0, 25.0][:joints],
                                 "phase_deg": [90.0, 90.0, 90.0][:joints - 1]},
                      "bounds": {"beta_deg": [10.0, 40.0], "phase_deg": [0.0, 180.0]},
                      "option": option, "model": "exact",
                      "solver": {"solvers": ["lm"], "starts": starts}}).to_dict()


def reference_rows(document, axes, action, rows):
    return [run_point(row["point"], document, {path: row[path] for path in axes}, action)
            for row in rows]


def assert_same_results(fast, slow):
    assert len(fast) == len(slow)
    for mine, theirs in zip(fast, slow, strict=True):
        assert mine["status"] == theirs["status"] == "ok"
        assert mine["residual_error"] == pytest.approx(theirs["residual_error"], rel=0,
                                                       abs=RE_ATOL)
        assert mine.get("success") is theirs.get("success")


@pytest.mark.parametrize("option, starts", [(1, 1), (2, 1), (3, 1), (3, 4), (1, 3)])
def test_optimised_points_match_sso_optimise_point_by_point(option, starts):
    document = lm_document(option, starts)
    axes = {"design.beta_deg[0]": {"start": 10.0, "stop": 40.0, "num": 4},
            "design.phase_deg[1]": [30.0, 90.0, 150.0],
            "design.beta_deg[2]": [12.0, 33.0]}
    assert array_plan(base_case(document), parse_axes(axes, document), "optimise") is not None
    result = sso.sweep(document, axes, workers=1, progress=False)
    assert [row["point"] for row in result.rows] == list(range(24))
    assert_same_results(list(result.rows),
                        reference_rows(document, axes, "optimise", result.rows))


def test_evaluated_points_match_evaluate_and_carry_the_same_columns():
    document = lm_document(3, 1, joints=4)
    axes = {"design.beta_deg[1]": {"start": 0.0, "stop": 60.0, "num": 7},
            "design.phase_deg[2]": [0.0, 45.0], "input_speed_rpm": [10, 2500.5]}
    result = sso.sweep(document, axes, action="evaluate", workers=1, progress=False)
    slow = reference_rows(document, axes, "evaluate", result.rows)
    for mine, theirs in zip(result.rows, slow, strict=True):
        assert mine.keys() - {"sweep_hash"} == theirs.keys() | {
            key for key, value in mine.items() if value is None}
        for key in ("residual_error", "residual_error_rpm2", "fluctuation",
                    "max_output_accel_rad_s2"):
            assert mine[key] == pytest.approx(theirs[key], rel=1e-12, abs=1e-30)
        assert gathered(mine, "design_beta_deg") == gathered(theirs, "design_beta_deg")
        assert gathered(mine, "design_phase_deg") == gathered(theirs, "design_phase_deg")
        assert mine["input_speed_rpm"] == theirs["input_speed_rpm"]
        assert type(mine["input_speed_rpm"]) is type(theirs["input_speed_rpm"])


def test_a_value_the_case_refuses_is_an_error_row_and_moved_starts_are_warned():
    document = lm_document(3, 2)
    axes = {"design.beta_deg[2]": [25.0, 50.0, 95.0]}
    result = sso.sweep(document, axes, workers=1, progress=False)
    slow = reference_rows(document, axes, "optimise", result.rows)
    assert [row["status"] for row in result.rows] == ["ok", "ok", "failed"]
    assert result.rows[2]["error"] == slow[2]["error"]
    assert "point 2: design.beta_deg[2] = 95 is outside" in result.rows[2]["error"]
    assert result.rows[1]["warnings"] == slow[1]["warnings"]
    assert "start beta_deg[2] = 50 deg lies outside its bounds" in result.rows[1]["warnings"]
    assert_same_results(list(result.rows[:2]), slow[:2])


def strip(rows):
    return [{key: value for key, value in row.items() if key not in TIME_COLUMNS}
            for row in rows]


def mapped_memory(column):
    """The object at the end of an array's chain of bases (an mmap: shared memory)."""
    while isinstance(column, (np.ndarray, memoryview)):
        column = column.base if isinstance(column, np.ndarray) else column.obj
    return column


@pytest.mark.parametrize("action", ["optimise", "evaluate"])
def test_the_pool_gives_the_rows_of_one_process(action):
    document = lm_document(3, 1)
    axes = {"design.beta_deg[0]": {"start": 10.0, "stop": 40.0, "num": 30},
            "design.beta_deg[1]": {"start": 10.0, "stop": 40.0, "num": 20}}
    one = sso.sweep(document, axes, action=action, workers=1, progress=False)
    pool = sso.sweep(document, axes, action=action, workers=2, chunk_size=150,
                     progress=False)
    assert strip(pool.rows) == strip(one.rows)
    if sys.platform.startswith("linux"):  # the workers wrote the numbers in place
        columns = pool.rows.table.columns
        assert isinstance(mapped_memory(columns["residual_error"]), mmap.mmap)
        assert isinstance(mapped_memory(columns["design_beta_deg[2]"]), mmap.mmap)
        assert columns["status"].dtype == object  # text travelled


def test_the_pool_gives_the_rows_of_one_process_where_values_are_refused():
    document = lm_document(3, 2)
    axes = {"design.beta_deg[2]": [25.0, 50.0, 95.0, 30.0], "design.beta_deg[0]": [20.0, 35.0]}
    one = sso.sweep(document, axes, workers=1, progress=False)
    pool = sso.sweep(document, axes, workers=2, chunk_size=3, progress=False)
    assert [row["status"] for row in one.rows] == ["ok"] * 4 + ["failed"] * 2 + ["ok"] * 2
    assert strip(pool.rows) == strip(one.rows)


@pytest.mark.parametrize("action", ["optimise", "evaluate"])
def test_the_number_columns_are_those_the_engine_makes(action):
    document = lm_document(2, 3, joints=4)
    axes = parse_axes({"design.beta_deg[1]": [10.0, 20.0], "input_speed_rpm": [10, 20.5],
                       "design.phase_deg[0]": [45.0, 90.0]}, document)
    plan = array_plan(base_case(document), axes, action)
    chunk = SweepChunk.listed(document, action, tuple(
        (index, {axis.path: axis.values[index] for axis in axes}) for index in range(2)),
        plan=plan)
    table = run_sweep_chunk(chunk)
    made = {name: (column.dtype, column.shape[1:]) for name, column in table.columns.items()
            if column.dtype != object}
    assert number_columns(plan, axes) == made
    assert "input_speed_rpm" not in made  # whole numbers among its values: text


def test_a_sweep_that_varies_the_problem_takes_the_point_path():
    document = lm_document(3, 2)
    assert array_plan(base_case(document), parse_axes({"option": [2, 3]}, document),
                      "optimise") is None
    crosschecked = base_case("cases/paper_option3_exact.toml")
    axes = parse_axes({"design.beta_deg[0]": [20.0]}, crosschecked.to_dict())
    assert array_plan(crosschecked, axes, "optimise") is None
    assert array_plan(crosschecked, axes, "evaluate") is not None
    paper = base_case("cases/paper_option3_paper.toml")
    assert array_plan(paper, parse_axes({"design.beta_deg[0]": [20.0]}, paper.to_dict()),
                      "evaluate") is None


def test_rows_hold_columns_and_give_a_frame():
    pandas = pytest.importorskip("pandas")
    document = lm_document(3, 1)
    result = sso.sweep(document, {"design.beta_deg[0]": [10.0, 20.0, 30.0]},
                       action="evaluate", workers=1, progress=False)
    frame = result.frame()
    assert isinstance(frame, pandas.DataFrame)
    assert list(frame["point"]) == [0, 1, 2]
    np.testing.assert_array_equal(frame["residual_error"].to_numpy(),
                                  [row["residual_error"] for row in result.rows])
    assert list(frame.columns) == list(result.rows[0])
