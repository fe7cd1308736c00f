"""Every public result reads well (a short repr, summary(), _repr_html_), and
sso.write_report writes its report."""

import json
from pathlib import Path

import numpy as np
import pytest

import sso
from sso._display import format_number

DATA = Path(__file__).resolve().parents[1] / "data"


@pytest.fixture(scope="module")
def two_joint_result():
    # Two equal joints phased 90 deg cancel exactly (docs/model.md, "Two joints"):
    # the optimum's RE is zero to round-off.
    return sso.optimise(sso.ShaftSeries([20.0, 20.0], [40.0], "exact"), 1, starts=1)


def test_optimisation_result_reads_well(two_joint_result):
    result = two_joint_result
    text = repr(result)
    assert len(text) <= 400 and text.count("\n") <= 2
    assert text.startswith("OptimisationResult(option 1 (phase), exact model, success")
    summary = result.summary()
    assert "found by: " in summary
    assert "cross-check of the solvers' own answers: solvers agree" in summary
    # The optimum phase is 90 deg to the solver's tolerance; its RE is round-off.
    optimum_line = next(line for line in summary.splitlines() if line.startswith("optimum"))
    assert optimum_line.split()[-2:] == ["<", "1e-15"]
    assert "ipopt" in summary and "slsqp" in summary
    assert "<table>" in result._repr_html_()


def test_evaluation_solution_and_crosscheck_read_well(two_joint_result):
    evaluation = sso.ShaftSeries([20.0, 20.0], [0.0], "exact").evaluate(25.0)
    for item in (evaluation, two_joint_result.best, two_joint_result.crosscheck):
        assert len(repr(item)) <= 400 and "\n" not in repr(item)
        assert item.summary() and "<" in item._repr_html_()
    assert format_number(evaluation.speed_min_rpm) in evaluation.summary()


def test_write_report_of_an_optimisation_is_the_report_sso_run_writes(two_joint_result,
                                                                      tmp_path):
    written = sso.write_report(two_joint_result, tmp_path / "report", formats=("json", "md"))
    assert sorted(path.name for path in written) == ["report.md", "result.json"]
    saved = json.loads((tmp_path / "report" / "result.json").read_text())
    assert saved["type"] == "OptimisationResult"
    assert sso.OptimisationResult.from_dict(saved) == two_joint_result
    assert saved["best"]["series"]["phase_deg"] == [pytest.approx(90.0, abs=1e-4)]
    assert "# SSO report: optimisation" in (tmp_path / "report" / "report.md").read_text()


def test_write_report_refuses_what_is_not_a_result(tmp_path):
    with pytest.raises(TypeError, match="result must be an sso result"):
        sso.write_report(42, tmp_path / "report")
    # a dict is no result: result.json is read back with from_dict, never reported as a dict
    with pytest.raises(TypeError, match="result must be an sso result .* not dict"):
        sso.write_report({"schema_version": 1, "kind": "column"}, tmp_path / "report")
    with pytest.raises(ValueError, match="formats = \\['pdf'\\]"):
        sso.write_report(sso.can_cancel([10.0, 20.0]), tmp_path / "report", formats=["pdf"])
    assert not (tmp_path / "report").exists()


def test_batch_phasing_and_spline_results_read_well():
    batch = sso.optimise_batch(np.array([[20.0, 20.0], [20.0, 20.0]]), np.array([[40.0], [80.0]]),
                               option=1)
    column = json.loads((DATA / "columns" / "truck_three_joints.json").read_text())
    geometry = sso.ColumnGeometry(np.asarray(column["points_mm"]))
    phasing = sso.optimise(geometry)
    splines = sso.optimise(geometry, teeth=12)
    for item in (batch, phasing, splines):
        assert len(repr(item)) <= 400 and "\n" not in repr(item), repr(item)
        assert "<table>" in item._repr_html_()
    # Two equal joints: option 1 puts the phase at 90 deg and cancels (docs/model.md).
    assert "lowest RE < 1e-15" in repr(batch)
    assert phasing.summary().startswith("Phasing: ")
    assert "tooth offset" in splines.summary()


def test_every_public_result_type_reads_well():
    from sso._display import Readable

    results = [name for name in sso.__all__ if name.endswith("Result")]
    assert {"OptimisationResult", "FourBarDesignResult", "SweepResult", "ToleranceResult",
            "BatchResult", "PhasingResult", "SplineResult"} <= set(results)
    for name in [*results, "Evaluation", "Solution", "CrossCheck", "MechanismTable"]:
        assert issubclass(getattr(sso, name), Readable), name
