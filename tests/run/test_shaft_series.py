"""A shaft-series case run is one result: the optimisation the API returns, the reference,
the curves, the warnings; it reads back from its saved form equal."""

from __future__ import annotations

from pathlib import Path

import pytest

import sso
from sso._cases.schema import load_case
from sso._run.shaft_series import EVALUATED_VERDICT, ShaftSeriesRun, run_shaft_series

CASES = Path(__file__).resolve().parents[2] / "cases"


def test_a_run_holds_what_sso_optimise_returns():
    case = load_case(CASES / "paper_option1_exact.toml")
    run = run_shaft_series(case, optimising=True)
    direct = sso.optimise(case.series(), case.option, **case.optimise_options())
    assert isinstance(run.optimisation, sso.OptimisationResult)
    assert run.optimisation.fun == pytest.approx(direct.fun, rel=1e-9)
    assert [design.role for design in run.designs] == ["initial", "optimum", "reference"]
    assert run.designs[:2] == run.optimisation.compared
    assert run.verdict == run.optimisation.verdict and run.success
    # the paper's reported optimum (cases/paper_option1_exact.toml, [reference])
    reference = run.design("reference")
    assert reference is not None and reference.label == case.reference_label
    assert ShaftSeriesRun.from_dict(run.to_dict()) == run


def test_an_evaluation_builds_no_optimisation():
    case = load_case(CASES / "paper_option2_paper.toml")
    run = run_shaft_series(case, optimising=False)
    assert run.optimisation is None and run.verdict == EVALUATED_VERDICT
    assert [design.role for design in run.designs] == ["initial", "reference"]
    assert run.designs[0].series == case.series()
    assert ShaftSeriesRun.from_dict(run.to_dict()) == run


def test_the_mode_and_the_optimisation_agree():
    run = run_shaft_series(load_case(CASES / "paper_option2_paper.toml"), optimising=False)
    with pytest.raises(ValueError, match="mode = 'guess'"):
        ShaftSeriesRun(run.case, "guess", None, run.compared, warnings=(), versions={},
                       created_utc="")
    with pytest.raises(ValueError, match="an optimise run holds its optimisation"):
        ShaftSeriesRun(run.case, "optimise", None, run.compared, warnings=(), versions={},
                       created_utc="")
    # found by benchmarks/fuzz.py: a saved evaluate run with "compared": [] ended
    # sso report in an IndexError; a run holds at least the design it started from
    with pytest.raises(ValueError, match="compared is empty"):
        ShaftSeriesRun(run.case, "evaluate", None, (), warnings=(), versions={},
                       created_utc="")


def test_evaluation_round_trips_through_result_json(tmp_path):
    import json

    from paper_trials import paper_trial_case

    from sso._reports.kinds import write_report

    run = run_shaft_series(load_case(paper_trial_case(2, "paper", tmp_path)), optimising=False)
    write_report(run, tmp_path / "report", ["json", "csv"])
    saved = json.loads((tmp_path / "report" / "result.json").read_text())
    again = ShaftSeriesRun.from_dict(saved)
    assert again == run
    evaluation = again.designs[0].evaluation
    # docs/model.md: paper model, option 2 trial design at 25 rpm: 22.07 .. 28.31 rpm.
    assert evaluation.speed_min_rpm == pytest.approx(22.07, abs=5e-3)
    assert evaluation.speed_max_rpm == pytest.approx(28.31, abs=5e-3)
    write_report(again, tmp_path / "again", ["csv"])
    assert ((tmp_path / "again" / "speeds.csv").read_bytes()
            == (tmp_path / "report" / "speeds.csv").read_bytes())
