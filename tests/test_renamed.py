"""Names changed in v0.2 still work for one release, with a DeprecationWarning.

The solvers' stopping tolerance is ``solver_tol`` (keyword and case key
``solver.solver_tol``); v0.1 called it ``tolerance``, the word that also names the
Monte Carlo study.
"""

import json

import pytest

import sso
from sso.cases.schema import CaseError, load_case
from sso.limits import DEFAULT_SHAFT_SOLVER_TOL
from sso.reports.writer import read_result, result_json
from sso.run.document import evaluate_case

SERIES = sso.ShaftSeries([10.0, 20.0], [90.0])


def test_optimise_reads_the_old_keyword_with_a_warning():
    # Both spellings must give the very same run (same start, solver and tolerance).
    with pytest.warns(DeprecationWarning, match=r"optimise\(tolerance=...\) is deprecated.*"
                                                r"use solver_tol="):
        old = sso.optimise(SERIES, 1, starts=1, solvers="slsqp", tolerance=1e-9)
    new = sso.optimise(SERIES, 1, starts=1, solvers="slsqp", solver_tol=1e-9)
    assert old.fun == new.fun
    assert old.x == new.x


def test_the_old_keyword_is_checked_under_the_new_name():
    with pytest.warns(DeprecationWarning), \
            pytest.raises(ValueError, match=r"solver_tol = 0 is outside the allowed range"):
        sso.optimise(SERIES, 1, tolerance=0)


def test_both_names_at_once_are_refused():
    with pytest.raises(TypeError, match=r"got both tolerance= and solver_tol="):
        sso.optimise(SERIES, 1, tolerance=1e-9, solver_tol=1e-9)
    with pytest.raises(TypeError, match=r"design_fourbar\(\) got both tolerance="):
        sso.design_fourbar(sso.FourBar(ground=12, crank=2, coupler=15, rocker=9),
                           crank_bounds=(1, 6), coupler_bounds=(5, 20), rocker_bounds=(5, 15),
                           tolerance=1e-9, solver_tol=1e-9)


def test_an_unknown_keyword_still_fails():
    with pytest.raises(TypeError, match="tolerence"):
        sso.optimise(SERIES, 1, tolerence=1e-9)


def test_a_case_file_with_the_old_key_loads_with_a_note(tmp_path):
    path = tmp_path / "old.toml"
    path.write_text("[design]\nbeta_deg = [10.0, 20.0]\n[solver]\ntolerance = 1e-9\n")
    with pytest.warns(DeprecationWarning, match="solver.tolerance is deprecated"):
        case = load_case(path)
    assert case.solver_tol == 1e-9
    assert case.optimise_options()["solver_tol"] == 1e-9
    assert case.warnings[0].startswith("solver.tolerance is deprecated")
    assert "name it solver.solver_tol" in case.warnings[0]


def test_a_case_file_with_both_keys_is_refused_at_the_old_ones_line(tmp_path):
    path = tmp_path / "both.toml"
    path.write_text("[design]\nbeta_deg = [10.0, 20.0]\n[solver]\nsolver_tol = 1e-9\n"
                    "tolerance = 1e-9\n")
    with pytest.raises(CaseError, match="solver.tolerance and solver.solver_tol are both given") \
            as caught:
        load_case(path)
    assert caught.value.line == 5


def test_a_v01_result_file_still_reads(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text("[design]\nbeta_deg = [10.0, 20.0]\n")
    document = json.loads(result_json(evaluate_case(load_case(path))))
    assert document["case"]["solver"]["solver_tol"] == DEFAULT_SHAFT_SOLVER_TOL
    document["case"]["solver"]["tolerance"] = document["case"]["solver"].pop("solver_tol")
    saved = tmp_path / "result.json"
    saved.write_text(json.dumps(document))
    assert read_result(saved)["case"]["solver"]["solver_tol"] == DEFAULT_SHAFT_SOLVER_TOL
