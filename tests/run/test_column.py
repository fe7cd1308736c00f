"""A column case run is one result, ``sso.ColumnRun``, whose parts are what the API returns.

Reference values: the truck column of tests/data/columns/truck_three_joints.json (best
RE 2.268e-4, the closed-form least RE of ``sso.can_cancel``, checked against the
independent 3D simulation in tests/column/test_column_phasing.py); every part is
compared with the public function that computes it on its own.
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import pytest

import sso
from sso._cases.schema import parse_case
from sso._record import RecordError
from sso._reports.kinds import record_json, render_report
from sso._run.column import MOVED_LABEL, ColumnRun, run_column

TRUCK = json.loads((Path(__file__).resolve().parents[1] / "data" / "columns"
                    / "truck_three_joints.json").read_text())["points_mm"]
SOLVER = {"starts": 2, "seed": 0}


def truck_case(**tables: dict[str, object]) -> object:
    return parse_case({"kind": "column", "name": "truck", "hardpoints": {"points_mm": TRUCK},
                       "solver": SOLVER, **tables}, "truck.toml")


@pytest.fixture(scope="module")
def optimised() -> ColumnRun:
    return run_column(truck_case(splines={"teeth": [36, 36]}), optimising=True)


def test_the_parts_are_what_the_public_api_returns(optimised):
    geometry = sso.ColumnGeometry(TRUCK)
    assert optimised.geometry == geometry
    assert optimised.cancel == sso.can_cancel(geometry.beta_deg)
    phasing = sso.optimise(geometry, **SOLVER)
    assert optimised.phasing.x == pytest.approx(phasing.x, abs=1e-9)
    assert optimised.phasing.fun == pytest.approx(2.268e-4, rel=1e-3)
    assert optimised.phasing.fun == pytest.approx(optimised.cancel.minimum_residual_error,
                                                  rel=1e-9)
    assert optimised.splines == sso.optimise(geometry, teeth=[36, 36])
    recommended = optimised.assembly("splines")
    assert recommended.yoke_phase_deg == optimised.splines.yoke_phase_deg
    speeds = [20.0 + 100.0 * index / 11 for index in range(12)]  # 12 rows, 20 to 120 rpm
    assert optimised.excitation["splines"] == sso.excitation_table(
        geometry.series(recommended.yoke_phase_deg), speeds, "car", "steering")
    assert list(optimised.excitation) == ["as_built", "splines"]
    designs = [(item.role, item.label, item.yoke_phase_deg) for item in optimised.assemblies]
    assert optimised.steering == sso.assess_steering(geometry, designs, lock_deg=540.0)
    assert [item.role for item in optimised.assemblies] == [
        "as_built", "in_phase", "textbook", "best", "splines"]


def test_the_closing_figures_are_the_as_built_and_the_recommended_assembly(optimised):
    assert optimised.initial.residual_error == optimised.assembly("as_built").residual_error
    optimum = optimised.optimum
    assert optimum.label == "best on the splines (whole teeth)" and optimum.objective is None
    assert optimum.residual_error == optimised.splines.residual_error
    assert optimised.success and optimised.verdict.startswith("phasing: ")


def test_a_saved_run_reads_back_equal_and_reports_the_same(optimised, tmp_path):
    saved = json.loads(json.dumps(optimised.to_dict(), allow_nan=False))
    again = ColumnRun.from_dict(saved)
    assert again == optimised
    # saved again, byte for byte (the case's tables in the schema's order, not the file's)
    assert record_json(again) == record_json(optimised)
    assert again.case == optimised.case
    assert (render_report(again, ("md", "csv")) == render_report(optimised, ("md", "csv")))
    written = sso.write_report(again, tmp_path / "report", formats=("json", "md"))
    assert {path.name for path in written} >= {"result.json", "report.md"}
    assert ColumnRun.from_dict(json.loads((tmp_path / "report" / "result.json").read_text())) \
        == optimised


@pytest.mark.parametrize(("edit", "message"), [
    (lambda data: data["assemblies"][0].update(residual_error=-5.0),
     r"assemblies\[0\]\.residual_error = -5\.0; allowed: a finite number >= 0"),
    (lambda data: data["phasing"].update(in_phase_re=-1),
     r"phasing\.in_phase_re = -1\.0; allowed: a finite number >= 0"),
    (lambda data: data.update(recommended="nowhere"),
     r"recommended = 'nowhere' names no assembly"),
    (lambda data: data["case"]["case"]["hardpoints"].update(points_mm=[[0, 0, 0]]),
     r"case \(ColumnCase\): .*hardpoints"),
    (lambda data: data.pop("steering"), r"steering is missing \(a field of ColumnRun\)"),
])
def test_a_saved_run_out_of_range_is_refused_naming_the_field(optimised, edit, message):
    saved = json.loads(json.dumps(optimised.to_dict()))
    edit(saved)
    with pytest.raises(RecordError, match=message):
        ColumnRun.from_dict(saved)


def test_an_analysis_holds_no_optimisation():
    run = run_column(truck_case(), optimising=False)
    assert run.mode == "evaluate" and run.phasing is None and run.joint_centres is None
    assert run.recommended == "as_built" and run.optimum is None
    assert [item.role for item in run.assemblies] == ["as_built", "in_phase", "textbook"]
    assert run.verdict == "assembly as built analysed; no optimisation"
    with pytest.raises(ValueError, match="an optimise run holds its phasing"):
        replace(run, mode="optimise")


def test_joints_moved_to_a_lower_re_are_the_optimum():
    # Boxes of +-20 mm about each joint: the least RE of the given points is 2.27e-4
    # (sso.can_cancel), so the moved joints go lower and the closing table names them.
    boxes = {"min_mm": [[c - 20.0 for c in point] for point in TRUCK[1:-1]],
             "max_mm": [[c + 20.0 for c in point] for point in TRUCK[1:-1]]}
    run = run_column(truck_case(joint_boxes=boxes), optimising=True)
    moved = run.joint_centres
    assert moved is not None and moved.fun < run.phasing.fun
    assert run.optimum.label == MOVED_LABEL and run.optimum.residual_error == moved.fun
