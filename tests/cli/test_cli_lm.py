"""The least-squares solver "lm" in case files and on the command line, run for real."""

import csv
import json
from pathlib import Path

import pytest
from test_cli import sso, write_case

from sso._run.shaft_series import ShaftSeriesRun

ROOT = Path(__file__).resolve().parents[2]
CASES = ROOT / "cases"
# The paper's option 3 (cases/paper_option3_exact.toml) with "lm" alone.
LM_CASE = ('name = "lm_alone"\nmodel = "exact"\noption = 3\n[design]\n'
           'beta_deg = [30.0, 40.0, 40.0]\nphase_deg = [90.0, 90.0]\n[bounds]\n'
           'beta_deg = [10.0, 40.0]\n[solver]\nsolvers = ["lm"]\nstarts = 4\n')
PAPER_LM_CASE = LM_CASE.replace('"exact"', '"paper"').replace("lm_alone", "paper_lm")
PAPER_MESSAGE = ("solver.solvers = ['lm'] includes 'lm', the least-squares solver of the exact "
                 "model's closed form; model = 'paper' allows 'ipopt', 'slsqp'")


def test_a_case_with_lm_alone_is_solved_by_lm(tmp_path):
    case = write_case(tmp_path, LM_CASE)
    completed = sso("run", case, "--out", tmp_path / "out", "--no-plots", cwd=tmp_path)
    assert completed.returncode == 0, completed.stdout + completed.stderr
    run = ShaftSeriesRun.from_dict(
        json.loads((tmp_path / "out" / "lm_alone" / "result.json").read_text()))
    result = run.optimisation
    assert run.case.solvers == ("lm",) and result is not None
    assert list(result.solutions) == ["lm"]
    optimum = run.design("optimum")
    assert optimum is not None and optimum.label == "optimum"
    assert result.found_by == "lm from start 0"
    assert run.success is True and result.crosscheck is None
    # Option 3 of the paper's case cancels: the optimum is at round-off zero.
    assert optimum.evaluation.residual_error < 1e-20
    assert result.solutions["lm"].fun < 1e-20
    assert all(10.0 <= beta <= 40.0 for beta in optimum.series.beta_deg)


def test_lm_on_the_command_line_replaces_the_case_solvers(tmp_path):
    completed = sso("run", CASES / "paper_option1_exact.toml", "--solvers", "lm", "--out",
                    tmp_path / "out", "--formats", "json", cwd=tmp_path)
    assert completed.returncode == 0, completed.stdout + completed.stderr
    run = ShaftSeriesRun.from_dict(
        json.loads((tmp_path / "out" / "paper_option1_exact" / "result.json").read_text()))
    assert run.optimisation is not None and list(run.optimisation.solutions) == ["lm"]
    # docs/guide/python-api.md, the paper's cases: option 1 of the exact model reaches RE
    # 1.15e-4 (the pair's answer).
    assert run.optimisation.solutions["lm"].fun == pytest.approx(1.15e-4, rel=0.01)


@pytest.mark.parametrize("command", ["run", "validate"])
def test_the_paper_model_with_lm_is_bad_input_naming_the_key(tmp_path, command):
    case = write_case(tmp_path, PAPER_LM_CASE)
    arguments = ("--out", tmp_path / "out") if command == "run" else ()
    completed = sso(command, case, *arguments, cwd=tmp_path)
    assert completed.returncode == 2
    assert f"error: {case}, line 10: {PAPER_MESSAGE}" in completed.stderr
    assert "Traceback" not in completed.stderr
    assert not (tmp_path / "out").exists()


def test_lm_on_the_command_line_for_the_paper_model_exits_2(tmp_path):
    case = CASES / "paper_option1_paper.toml"
    completed = sso("run", case, "--solvers", "ipopt,lm", "--out", tmp_path / "out", cwd=tmp_path)
    assert completed.returncode == 2
    assert (f"error: {case}: --solvers: "
            + PAPER_MESSAGE.replace("['lm']", "['ipopt', 'lm']")) in completed.stderr
    assert "Traceback" not in completed.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("case", ["mechanisms/fourbar_swing_design.toml",
                                  "column_car_intermediate_shaft.toml"])
def test_lm_is_refused_where_the_problem_has_no_residual_form(tmp_path, case):
    path = CASES / case
    completed = sso("run", path, "--solvers", "lm", "--out", tmp_path / "out", cwd=tmp_path)
    assert completed.returncode == 2
    assert (f"error: {path}: --solvers: solver.solvers[0] = 'lm' is not one of 'ipopt', 'slsqp'"
            in completed.stderr)
    assert "Traceback" not in completed.stderr



def test_sso_sweep_of_an_lm_case_solves_its_points_with_lm(tmp_path):
    write_case(tmp_path, LM_CASE)
    (tmp_path / "map.toml").write_text('case = "case.toml"\n[axes]\n'
                                       '"design.beta_deg[0]" = [15.0, 25.0, 35.0]\n'
                                       'option = [2, 3]\n')
    completed = sso("sweep", "map.toml", "--workers", "1", "--no-plots", "--quiet",
                    cwd=tmp_path)
    assert completed.returncode == 0, completed.stdout + completed.stderr
    with open(tmp_path / "results" / "map" / "sweep.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert [row["point"] for row in rows] == [str(index) for index in range(6)]
    for row in rows:
        assert row["status"] == "ok" and row["best_solver"] == "lm"
        assert row["success"] == "true" and row["lm_success"] == "true"
        assert float(row["residual_error"]) < 1e-20  # options 2 and 3 cancel in [10, 40] deg
        assert row["ipopt_residual_error"] == "" and row["slsqp_residual_error"] == ""
