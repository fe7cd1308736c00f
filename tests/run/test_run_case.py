"""sso.run_case: a case file into the result ``sso run`` (or ``sso evaluate``) reports,
the kind of result its case calls for, and bad files refused naming the file."""

from __future__ import annotations

from pathlib import Path

import pytest

import sso

CASES = Path(__file__).resolve().parents[2] / "cases"


def test_a_shaft_series_case_is_solved_as_sso_run_solves_it():
    run = sso.run_case(CASES / "paper_option3_exact.toml")
    assert isinstance(run, sso.ShaftSeriesRun) and run.mode == "optimise"
    assert run.optimisation is not None and run.success
    # Option 3 of the exact model cancels (docs/model.md, "Checks with known answers"):
    # RE at round-off zero, against the paper's reported optimum's 1.93e-3.
    assert run.optimisation.fun <= 1e-15
    reference = run.design("reference")
    assert reference is not None
    assert reference.evaluation.residual_error == pytest.approx(1.928e-3, rel=1e-3)


def test_solve_false_evaluates_the_design_as_given():
    run = sso.run_case(CASES / "paper_option2_paper.toml", solve=False)
    assert isinstance(run, sso.ShaftSeriesRun) and run.mode == "evaluate"
    assert run.optimisation is None
    given = run.designs[0]
    assert given.evaluation.residual_error == pytest.approx(
        given.series.evaluate().residual_error, rel=1e-12)


@pytest.mark.parametrize(("file", "kind"), [
    ("column_car_intermediate_shaft.toml", sso.ColumnRun),
    ("mechanisms/quickreturn.toml", sso.MechanismRun),
])
def test_each_kind_of_case_gives_its_kind_of_result(file, kind):
    assert isinstance(sso.run_case(CASES / file, solve=False), kind)


def test_a_missing_file_is_refused_naming_it(tmp_path):
    with pytest.raises(ValueError, match="no_such_case.toml"):
        sso.run_case(tmp_path / "no_such_case.toml")


def test_an_unknown_keyword_fails():
    with pytest.raises(TypeError):
        sso.run_case(CASES / "paper_option1_exact.toml", optimise=True)  # type: ignore[call-arg]
