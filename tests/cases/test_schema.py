"""Case files: shipped cases load, defaults fill in, bad files fail with clear messages."""

import subprocess
import sys
from pathlib import Path

import pytest

from sso._cases.schema import KIND_MODULES, CaseError, case_kinds, load_case, parse_case, schema
from sso._cases.shaft_series import Case

CASES = Path(__file__).resolve().parents[2] / "cases"
# The shaft-series cases (the column cases are checked in tests/cases/test_column_case.py).
# The shaft-series cases (the column's and the driveline kind's have tests of their own).
SHIPPED = sorted(path for path in CASES.glob("*.toml")
                 if not any(f'kind = "{kind}"' in path.read_text(encoding="utf-8")
                            for kind in ("column", "driveline")))
MINIMAL = '[design]\nbeta_deg = [10.0, 20.0]\n'

# docs/model.md, "The paper's three cases": reported optima.
PAPER_REFERENCES = {
    1: ((15.0, 20.0, 9.0), (57.4233, 73.2749)),
    2: ((7.0, 18.4473, 25.0), (90.0, 90.0)),
    3: ((15.8362, 10.0, 15.8387), (90.0053, 89.9695)),
}


def write(tmp_path: Path, text: str, name: str = "case.toml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def error_of(tmp_path: Path, text: str) -> CaseError:
    with pytest.raises(CaseError) as caught:
        load_case(write(tmp_path, text))
    return caught.value


def test_eight_cases_are_shipped():
    names = {path.stem for path in SHIPPED}
    paper = {f"paper_option{option}_{model}" for option in (1, 2, 3)
             for model in ("exact", "paper")}
    assert paper <= names
    assert {"steering_column", "driveline_four_joint"} <= names


@pytest.mark.parametrize("path", SHIPPED, ids=[path.stem for path in SHIPPED])
def test_shipped_case_loads_and_round_trips(path):
    case = load_case(path)
    assert case.name == path.stem
    assert case.description
    assert case.reference_beta_deg is not None
    assert case.starts <= 4
    assert parse_case(case.to_dict(), str(path)) == case


@pytest.mark.parametrize("option", [1, 2, 3])
@pytest.mark.parametrize("model", ["exact", "paper"])
def test_paper_cases_carry_the_reported_optimum(option, model):
    case = load_case(CASES / f"paper_option{option}_{model}.toml")
    beta_deg, phase_deg = PAPER_REFERENCES[option]
    assert case.option == option
    assert case.model == model
    assert case.input_speed_rpm == pytest.approx(25.0, abs=0)
    assert case.reference_beta_deg == pytest.approx(beta_deg, abs=0)
    assert case.reference_phase_deg == pytest.approx(phase_deg, abs=0)


def test_defaults_are_filled_in(tmp_path):
    case = load_case(write(tmp_path, MINIMAL, "my-case.toml"))
    assert isinstance(case, Case)
    assert case.kind == "shaft_series"
    assert case.name == "my-case"
    assert case.model == "exact"
    assert case.option == 3
    assert case.input_speed_rpm == pytest.approx(25.0, abs=0)
    assert case.phase_deg == pytest.approx((90.0,), abs=0)
    assert case.beta_bounds_deg == pytest.approx((0.0, 40.0), abs=0)
    assert case.phase_bounds_deg == pytest.approx((0.0, 180.0), abs=0)
    assert case.solvers == ("ipopt", "slsqp")
    assert case.formats == ("json", "csv", "md", "html", "png")
    assert case.reference_beta_deg is None
    assert case.warnings == ()


def test_option_by_name_and_per_joint_bounds(tmp_path):
    case = load_case(write(tmp_path, 'option = "phase"\n' + MINIMAL
                           + '[bounds]\nbeta_deg = [[0, 30], [5, 35]]\n'))
    assert case.option == 1
    assert case.beta_bounds_deg == ((0.0, 30.0), (5.0, 35.0))


def test_start_outside_bounds_is_a_warning_not_an_error(tmp_path):
    case = load_case(write(tmp_path, '[design]\nbeta_deg = [10.0, 50.0]\n'))
    assert case.warnings == ("start beta_deg[1] = 50 deg lies outside its bounds [0, 40] deg; "
                             "moved onto 40 deg",)


def test_syntax_error_names_the_line(tmp_path):
    error = error_of(tmp_path, 'name = "x"\n[design]\nbeta_deg = [10, 20]\nmodel = exact\n')
    assert error.line == 4
    assert "TOML syntax error" in str(error)
    assert str(error).startswith(f"{tmp_path / 'case.toml'}, line 4:")


@pytest.mark.parametrize("text, line, message", [
    (MINIMAL + '[solver]\nstrats = 4\n', 4,
     "unknown key solver.strats; did you mean solver.starts?"),
    ('starts = 4\n' + MINIMAL, 1, "unknown key starts; did you mean solver.starts?"),
    ('modle = "exact"\n' + MINIMAL, 1, "unknown key modle; did you mean model?"),
    ('[desing]\nbeta_deg = [10]\n', 1, "unknown table [desing]; did you mean [design]?"),
])
def test_unknown_key_suggests_the_nearest(tmp_path, text, line, message):
    error = error_of(tmp_path, text)
    assert error.line == line
    assert message in error.reason


@pytest.mark.parametrize("text, line, reason", [
    ('input_speed_rpm = -3\n' + MINIMAL, 1,
     "input_speed_rpm = -3 is outside the allowed range (0, 1e+06] rpm"),
    ('input_speed_rpm = "fast"\n' + MINIMAL, 1,
     "input_speed_rpm = 'fast' must be a number in (0, 1e+06] rpm"),
    ('[design]\nbeta_deg = [10, 95]\n', 2,
     "design.beta_deg[1] = 95 is outside the allowed range [0, 90) deg"),
    (MINIMAL + '[solver]\nstarts = 0\n', 4,
     "solver.starts = 0 is outside the allowed range [1, 10000]"),
    (MINIMAL + '[solver]\nstarts = 2.5\n', 4,
     "solver.starts = 2.5 must be a whole number in [1, 10000]"),
    (MINIMAL + '[solver]\nsolvers = ["ipopt", "cobyla"]\n', 4,
     "solver.solvers[1] = 'cobyla' is not one of 'ipopt', 'slsqp'"),
    ('model = "exakt"\n' + MINIMAL, 1, "model = 'exakt' is not one of 'exact', 'paper'"),
    ('option = 4\n' + MINIMAL, 1, "option = 4 is not one of 1, 2, 3, 'phase', 'angle', 'both'"),
    (MINIMAL + '[bounds]\nbeta_deg = [30, 20]\n', 4,
     "bounds.beta_deg = (30, 20) deg is inverted (empty): the lower bound must not exceed "
     "the upper bound"),
    (MINIMAL + '[output]\nformats = ["json", "pdf"]\n', 4,
     "output.formats[1] = 'pdf' is not one of 'json', 'csv', 'md', 'html', 'png'"),
    ('name = "../escape"\n' + MINIMAL, 1, "name = '../escape' must be 1 to 100 letters"),
    ('option = 1\n[design]\nbeta_deg = [10]\n', 1, "option = 1 (phases) needs at least 2 joints"),
    ('[design]\nbeta_deg = [10, 20]\nphase_deg = [1, 2, 3]\n', 3,
     "design.phase_deg has 3 entries; 2 joints need 1"),
    (MINIMAL + '[reference]\nbeta_deg = [1, 2, 3]\n', 4,
     "reference.beta_deg has 3 entries; design.beta_deg has 2 joints"),
    ('kind = "four_bar"\n' + MINIMAL, 1, "kind = 'four_bar' is not one of 'shaft_series'"),
])
def test_bad_value_names_key_value_and_range(tmp_path, text, line, reason):
    error = error_of(tmp_path, text)
    assert error.line == line
    assert reason in error.reason


def test_missing_design_is_named(tmp_path):
    error = error_of(tmp_path, 'name = "x"\n')
    assert error.reason == ("design.beta_deg is missing: give 1-64 entries (one per joint), "
                            "each in [0, 90) deg")


def test_unreadable_files_are_case_errors(tmp_path):
    with pytest.raises(CaseError, match="cannot read the case file"):
        load_case(tmp_path / "absent.toml")
    binary = tmp_path / "binary.toml"
    binary.write_bytes(b"\xff\xfe\x00name")
    with pytest.raises(CaseError, match="not a UTF-8 text file"):
        load_case(binary)


def test_case_strings_are_data_not_code(tmp_path):
    marker = tmp_path / "executed"
    text = (f'description = "__import__(\'pathlib\').Path(\'{marker}\').touch()"\n' + MINIMAL)
    case = load_case(write(tmp_path, text))
    assert case.description.startswith("__import__")
    assert not marker.exists()


def test_every_kind_lists_unique_keys():
    for kind in case_kinds():
        labels = [key.label for key in schema(kind)]
        assert len(labels) == len(set(labels))


def test_one_joint_case_round_trips_with_empty_phase_list():
    # a single joint has no phases; its document writes phase_deg = [] and reads back
    case = parse_case({"name": "one_joint", "option": 2, "design": {"beta_deg": [20.0]},
                       "reference": {"beta_deg": [10.0]}}, "one_joint.toml")
    document = case.to_dict()
    assert document["design"]["phase_deg"] == []
    assert parse_case(document, "one_joint.toml") == case


# The smallest valid cases of the kinds whose [solver] keys keep the cross-checking pair.
PAIR_ONLY_CASES = {
    "fourbar_design": {"kind": "fourbar_design",
                       "start": {"ground": 12.0, "crank": 2.0, "coupler": 12.0, "rocker": 8.0},
                       "bounds": {"crank": [1.0, 6.0], "coupler": [5.0, 20.0],
                                  "rocker": [5.0, 15.0]}},
    "column": {"kind": "column",
               "hardpoints": {"points_mm": [[-950.0, 360.0, 780.0], [-717.9, 296.7, 569.0],
                                            [-614.1, 263.4, 333.0], [-599.9, 285.3, 215.8]]}},
}


def test_lm_alone_or_beside_the_pair_is_a_shaft_series_solver_of_the_exact_model():
    for solvers in (["lm"], ["ipopt", "slsqp", "lm"], ["lm", "slsqp"]):
        case = parse_case({"design": {"beta_deg": [10.0, 20.0]},
                           "solver": {"solvers": solvers}}, "lm.toml")
        assert case.solvers == tuple(solvers)
        assert case.optimise_options()["solvers"] == tuple(solvers)
        assert parse_case(case.to_dict(), "lm.toml") == case


def test_lm_with_the_paper_model_names_the_key_the_value_and_the_model_s_solvers(tmp_path):
    error = error_of(tmp_path,
                     'model = "paper"\n' + MINIMAL + '[solver]\nsolvers = ["slsqp", "lm"]\n')
    assert error.line == 5
    assert error.reason == ("solver.solvers = ['slsqp', 'lm'] includes 'lm', the least-squares "
                            "solver of the exact model's closed form; model = 'paper' allows "
                            "'ipopt', 'slsqp'")


def test_an_lm_override_is_checked_against_the_case_model():
    exact = parse_case({"design": {"beta_deg": [10.0, 20.0]}}, "exact.toml")
    assert exact.with_overrides(solvers=("lm",)).solvers == ("lm",)
    paper = parse_case({"model": "paper", "design": {"beta_deg": [10.0, 20.0]}}, "paper.toml")
    with pytest.raises(ValueError, match=r"^solver.solvers = \['lm'\] includes 'lm'.*"
                                         r"model = 'paper' allows 'ipopt', 'slsqp'$"):
        paper.with_overrides(solvers=("lm",))
    with pytest.raises(ValueError, match=r"solver.solvers\[0\] = 'cobyla' is not one of "
                                         r"'ipopt', 'slsqp', 'lm'"):
        exact.with_overrides(solvers=("cobyla",))


@pytest.mark.parametrize("kind", sorted(PAIR_ONLY_CASES))
def test_kinds_without_a_residual_form_keep_ipopt_and_slsqp(kind):
    document = PAIR_ONLY_CASES[kind]
    case = parse_case({**document, "solver": {"solvers": ["slsqp"]}}, f"{kind}.toml")
    assert case.values["solver.solvers"] == ("slsqp",)
    with pytest.raises(CaseError, match=r"solver.solvers\[0\] = 'lm' is not one of 'ipopt', "
                                        r"'slsqp'$"):
        parse_case({**document, "solver": {"solvers": ["lm"]}}, f"{kind}.toml")
    with pytest.raises(ValueError, match=r"solver.solvers\[0\] = 'lm' is not one of"):
        case.with_overrides(solvers=("lm",))


def test_each_shipped_kind_is_registered_by_the_module_that_reading_it_imports():
    # parse_case imports KIND_MODULES[kind] alone for a case of that kind (a shaft-series
    # run loads no column or linkage module); a kind registered elsewhere would be unknown
    for kind, case_kind in case_kinds().items():
        assert case_kind.build.__module__ == KIND_MODULES[kind], kind
    assert list(case_kinds()) == list(KIND_MODULES)


def test_an_unknown_kind_lists_every_kind_whichever_were_imported_first():
    # a fresh process that reads a mechanism case first registers its kinds before the
    # column's; the message still lists the kinds in the order of KIND_MODULES
    code = ("import sso._cases.mechanism\n"
            "from sso._cases.schema import CaseError, parse_case\n"
            "try:\n"
            "    parse_case({'kind': 'gearbox'})\n"
            "except CaseError as error:\n"
            "    print(error.reason)\n")
    completed = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                               check=True, timeout=120)
    assert completed.stdout.strip() == (
        "kind = 'gearbox' is not one of 'shaft_series', 'column', 'driveline', 'fourbar', "
        "'slider_crank', 'quick_return', 'fourbar_design'")
