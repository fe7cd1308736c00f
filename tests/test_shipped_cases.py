"""Every shipped case runs clean: no warning on stderr, none raised, exit code 0.

A warning that fires on the shipped examples teaches users to ignore warnings, so
each one must fire only when the input deserves it; the paper's own starts, which do
deserve one, are checked in tests/test_cli.py (``paper_trials.paper_trial_case``).
"""

import warnings
from pathlib import Path

import pytest
from paper_trials import PAPER_BETA_BOUNDS_DEG, PAPER_TRIAL_BETA_DEG

from sso._cases.schema import load_case
from sso._cli import main

ROOT = Path(__file__).resolve().parents[1]
SHIPPED = sorted([*ROOT.glob("cases/*.toml"), *ROOT.glob("cases/mechanisms/*.toml")])


# Shipped to fail: issue 35's car column is not shown to reach its required yield of 90 %
# of built columns, so sso run says why on stderr and exits 1
# (tests/cli/test_cli_column_yield.py).
BELOW_REQUIRED_YIELD = {"column_car_limits"}


def test_every_case_folder_is_covered():
    assert len(SHIPPED) == 26


@pytest.mark.parametrize("command", ["run", "evaluate", "validate"])
@pytest.mark.parametrize("case", SHIPPED, ids=[path.stem for path in SHIPPED])
def test_shipped_case_emits_no_warning(case, command, tmp_path, capsys):
    arguments = [command, str(case)]
    if command != "validate":
        arguments += ["--out", str(tmp_path), "--no-plots", "--quiet"]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        code = main(arguments)
    captured = capsys.readouterr()
    if command == "run" and case.stem in BELOW_REQUIRED_YIELD:
        assert code == 1
        assert captured.err == (f"error: {case.stem}: the recommended assembly's built columns "
                                "([tolerances] sample): FAILS the required yield 90.0 %: yield "
                                "of all limits together 51.5 % (95 % CI 44.6 % to 58.3 %, width "
                                "13.7 %, 200 samples), its upper bound below it\n")
    elif command == "evaluate" and case.stem in BELOW_REQUIRED_YIELD:
        assert code == 1  # as built, none of the 200 built columns meets every limit
        assert captured.err == (f"error: {case.stem}: the built columns of the assembly as "
                                "built ([tolerances] sample): FAILS the required yield 90.0 %: "
                                "yield of all limits together 0.0 % (95 % CI 0.0 % to 1.9 %, "
                                "width 1.9 %, 200 samples), its upper bound below it\n")
    else:
        assert code == 0, captured.err
        assert captured.err == ""
    assert [str(warning.message) for warning in caught] == []


@pytest.mark.parametrize("option", [2, 3])
@pytest.mark.parametrize("model", ["exact", "paper"])
def test_shipped_paper_start_is_the_papers_start_clipped_onto_its_bounds(option, model):
    case = load_case(ROOT / "cases" / f"paper_option{option}_{model}.toml")
    low, high = PAPER_BETA_BOUNDS_DEG[option]
    assert case.beta_deg == tuple(min(max(beta, low), high)
                                  for beta in PAPER_TRIAL_BETA_DEG[option])
    assert case.beta_deg != PAPER_TRIAL_BETA_DEG[option]
    assert case.beta_bounds_deg == (low, high)
