"""A mechanism case run is one result: the linkages, their tables, the curves the plots
draw, the extremes, the design the API returns; it reads back from its saved form equal,
and its report renders from it alone."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import sso
import sso._cases.schema
from sso._cases.schema import load_case
from sso._reports.kinds import render_report
from sso._run.mechanism_run import CURVE_STEP_DEG, MechanismRun, run_mechanism

CASES = Path(__file__).resolve().parents[2] / "cases" / "mechanisms"


def test_an_analysis_holds_its_curves_and_reads_back_equal(tmp_path):
    case = load_case(CASES / "fourbar_crank5.toml")
    run = run_mechanism(case, optimising=False)
    assert run.mode == "analyse" and run.success and run.design is None
    (given,) = run.linkages
    assert given.mechanism == case.mechanism()
    # the table is what the public API returns at the case's crank angles
    direct = case.mechanism().analyse(case.crank_angles_deg(),
                                      crank_speed=case.crank_speed_rad_s)
    for column in direct.columns:
        np.testing.assert_allclose(given.table[column], direct[column], rtol=0, atol=1e-12)
    # the curve the plots draw: every 1 deg over a revolution, and each of its points
    # closes the loop (|AB| = coupler, |O_B B| = rocker; the geometry, not the solver)
    angles = given.curve["crank_angle_deg"]
    assert np.allclose(np.diff(angles), CURVE_STEP_DEG) and angles[-1] - angles[0] == 360.0
    joint_a = given.curve["joint_a_x"] + 1j * given.curve["joint_a_y"]
    joint_b = given.curve["joint_b_x"] + 1j * given.curve["joint_b_y"]
    linkage = case.mechanism()
    np.testing.assert_allclose(np.abs(joint_b - joint_a), linkage.coupler, rtol=1e-12)
    np.testing.assert_allclose(np.abs(joint_b - linkage.ground), linkage.rocker, rtol=1e-12)
    assert len(given.positions) == len(case.values["plots.crank_angles_deg"])
    sso.write_report(run, tmp_path / "report", formats=("json", "md"))
    saved = json.loads((tmp_path / "report" / "result.json").read_text())
    assert saved["type"] == "MechanismRun"
    assert MechanismRun.from_dict(saved) == run


def test_the_report_of_a_reloaded_run_parses_no_case_and_is_the_same(tmp_path, monkeypatch):
    case = load_case(CASES / "quickreturn.toml")
    run = run_mechanism(case, optimising=False)
    files = render_report(run, ("json", "csv", "md", "png"))
    reloaded = MechanismRun.from_dict(json.loads(files["result.json"]))

    def refused(*arguments: object) -> None:
        raise AssertionError("a report parsed a case")

    monkeypatch.setattr(sso._cases.schema, "parse_case", refused)
    again = render_report(reloaded, ("json", "csv", "md", "png"))
    assert set(again) == set(files) >= {"linkage.png", "slider_motion.png", "table.csv"}
    for name in ("result.json", "table.csv", "report.md"):
        assert again[name] == files[name], name


def test_a_design_case_evaluated_holds_no_design():
    run = run_mechanism(load_case(CASES / "fourbar_swing_design.toml"), optimising=False)
    assert run.mode == "evaluate" and run.design is None
    assert [linkage.role for linkage in run.linkages] == ["initial"]
    with pytest.raises(ValueError, match="an optimise run holds its design"):
        MechanismRun(case=run.case, mode="optimise", design=None, linkages=run.linkages,
                     method_difference=None, verdict="", warnings=(), versions={},
                     created_utc=run.created_utc)


@pytest.mark.parametrize(("edit", "message"), [
    (lambda data: data["case"]["case"]["linkage"].update(crank=-2.0),
     r"case \(MechanismCase\): .*linkage\.crank = -2 is outside the allowed range"),
    (lambda data: data["case"]["case"].update(kind="bogus"), "kind = 'bogus' is not one of"),
    (lambda data: data["linkages"][0]["extremes"][0].update(min="low"),
     r"linkages\[0\]\.extremes\[0\]\.min = 'low'; allowed: a number"),
    (lambda data: data.update(mode="guess"), "mode = 'guess'"),
])
def test_a_saved_run_is_read_as_strictly_as_its_case_file(tmp_path, edit, message):
    from sso._cli.saved_results import read_saved_result
    from sso._record import RecordError

    run = run_mechanism(load_case(CASES / "fourbar_crank2.toml"), optimising=False)
    saved = json.loads(json.dumps(run.to_dict()))
    edit(saved)
    path = tmp_path / "result.json"
    path.write_text(json.dumps(saved))
    with pytest.raises(RecordError, match=message):
        read_saved_result(path)
