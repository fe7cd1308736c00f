"""A sweep's lists as one column per element (issue 35: "CSV cells hold Python lists,
which a spreadsheet cannot use: one column per element").

Each test runs a real sweep and reads its ``sweep.csv`` with the standard library's
:mod:`csv` module (the reference reader): no cell holds a list, every cell is a number
or a known text field, and the CSV, the Parquet parts and the :class:`sso.SweepResult`
hold the same columns and the same values. Reference values: the axis values as given;
the design of each point is the one the row reports (its RE computed again on resume).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path

import pytest

import sso
from sso._studies.element_columns import element_names, flat_row, gathered, value_shape
from sso._studies.table import TEXT_COLUMNS, typed_rows

ROOT = Path(__file__).resolve().parents[2]
CAR = ROOT / "cases" / "column_car_limits.toml"
FLAGS = ("success", "crosscheck_agree", "can_cancel", "joint_centres_success",
         "ipopt_success", "slsqp_success", "lm_success")
# Listed points of two and three joints: the two-joint rows leave their third angle
# and second phase empty.
SERIES_BASE = {"design": {"beta_deg": [20.0, 30.0], "phase_deg": [60.0]},
               "bounds": {"beta_deg": [5.0, 40.0]}, "option": 3,
               "solver": {"solvers": ["lm"], "starts": 1}}
SERIES_AXES = {"design.beta_deg": [[20.0, 30.0], [25.0, 10.0, 30.0]],
               "design.phase_deg": [[60.0], [30.0, 120.0]]}
# The car column's upper joint moved up by 6 mm: a list-valued axis, and every list a
# column row holds (angles, phasings, tooth offsets, the tolerance-aware phasing).
COLUMN_AXES = {"hardpoints.points_mm[1]": [[-717.9, 296.7, 569.0], [-717.9, 296.7, 575.0]]}


def read_csv(path: Path) -> tuple[list[str], list[list[str]]]:
    with open(path, newline="", encoding="utf-8") as handle:
        header, *rows = list(csv.reader(handle))
    return header, rows


def plain(value):
    """A cell as Python holds it: None for an empty cell or NaN, numpy scalars as Python's."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return None
    return value.item() if hasattr(value, "item") else value


@pytest.fixture(scope="module", params=["series", "column"])
def swept(request, tmp_path_factory):
    pytest.importorskip("pyarrow")
    folder = tmp_path_factory.mktemp(request.param)
    if request.param == "series":
        result = sso.sweep(SERIES_BASE, SERIES_AXES, mode="listed", action="optimise",
                           out_dir=folder, workers=1, plots=False, progress=False, parquet=True)
    else:
        result = sso.sweep(CAR, COLUMN_AXES, action="optimise", out_dir=folder, workers=1,
                           plots=False, progress=False, parquet=True)
    return result, folder


def test_no_cell_holds_a_list_and_every_cell_is_a_number_or_known_text(swept):
    result, folder = swept
    header, rows = read_csv(folder / "sweep.csv")
    assert all(row[header.index("status")] == "ok" for row in rows)
    for row in rows:
        for column, cell in zip(header, row, strict=True):
            assert not cell.startswith("["), (column, cell)
            if cell == "" or column in TEXT_COLUMNS:
                continue
            if column in FLAGS:
                assert cell in ("true", "false"), (column, cell)
            else:
                assert math.isfinite(float(cell)), (column, cell)


def test_csv_parquet_and_result_agree_column_for_column_and_value_for_value(swept):
    result, folder = swept
    header, _ = read_csv(folder / "sweep.csv")
    with open(folder / "sweep.csv", newline="", encoding="utf-8") as handle:
        from_csv = typed_rows(csv.DictReader(handle))
    frame = result.frame()  # read from sweep.parquet
    assert list(frame.columns) == header == list(result.rows[0])
    assert len(from_csv) == len(frame) == len(result.rows) == 2
    for position, row in enumerate(result.rows):
        for column in header:
            expected = plain(row[column])
            assert plain(from_csv[position][column]) == expected, column
            assert plain(frame[column][position]) == expected, column


def test_the_lists_read_back_from_their_element_columns(swept):
    result, _ = swept
    if result.axes[0].path == "design.beta_deg":
        # the two-joint point: its third angle and second phase empty
        assert result.rows[0]["design_beta_deg[2]"] is None
        assert result.rows[0]["design_phase_deg[1]"] is None
        for row, beta_deg in zip(result.rows, SERIES_AXES["design.beta_deg"], strict=True):
            assert gathered(row, "design.beta_deg") == beta_deg
            assert len(gathered(row, "design_beta_deg")) == len(beta_deg)
            series = sso.ShaftSeries(gathered(row, "design_beta_deg"),
                                     gathered(row, "design_phase_deg"))
            assert row["residual_error"] == pytest.approx(series.evaluate().residual_error,
                                                          rel=1e-12, abs=1e-30)
    else:
        for row, point in zip(result.rows, COLUMN_AXES["hardpoints.points_mm[1]"], strict=True):
            assert gathered(row, "hardpoints.points_mm[1]") == point
            assert all(type(row[f"tooth_offset[{k}]"]) is int for k in range(2))
        # the same yokes on 36-tooth splines as sso run recommends for the car (-80, -60)
        assert gathered(result.rows[0], "yoke_phase_deg") == [-80.0, -60.0]


def test_a_finished_sweep_resumes_and_keeps_its_rows(swept):
    result, folder = swept
    again = (sso.sweep(SERIES_BASE, SERIES_AXES, mode="listed", out_dir=folder, workers=1,
                       plots=False, progress=False, resume=True)
             if result.axes[0].path == "design.beta_deg" else
             sso.sweep(CAR, COLUMN_AXES, out_dir=folder, workers=1, plots=False,
                       progress=False, resume=True))
    assert again.resumed == 2 and again.computed == 0
    assert [dict(row) for row in again.rows] == [dict(row) for row in result.rows]


def test_element_names_shapes_and_flat_rows():
    assert element_names("a", (2, 3))[:4] == ["a[0][0]", "a[0][1]", "a[0][2]", "a[1][0]"]
    assert element_names("a", ()) == ["a"]
    assert value_shape([[1.0, 2.0], [3.0]], "axis") == (2,)
    assert value_shape([[[1.0, 2.0, 3.0]], [[4.0, 5.0, 6.0], [7.0, 8.0, 9.0]]], "axis") == (2, 3)
    with pytest.raises(ValueError, match="axis 'x' mixes lists and single values"):
        value_shape([[1.0, 2.0], 3.0], "axis 'x'")
    flat = flat_row({"a": [[1.0, 2.0], [3.0]], "b": "text"})
    assert flat == {"a[0][0]": 1.0, "a[0][1]": 2.0, "a[1][0]": 3.0, "b": "text"}
    assert gathered({**flat, "a[1][1]": None}, "a") == [[1.0, 2.0], [3.0]]
    assert gathered(flat, "c") is None


def test_an_axis_mixing_lists_and_single_values_is_refused_before_any_point():
    with pytest.raises(ValueError, match=r"axis 'bounds.beta_deg' mixes lists and single "):
        sso.sweep(SERIES_BASE, {"bounds.beta_deg": [[5.0, 40.0], [[5.0, 40.0], [5.0, 40.0]]]},
                  workers=1, progress=False)
