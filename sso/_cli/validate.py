"""``sso validate``: check case files only (loads neither CasADi nor SciPy)."""

from __future__ import annotations

import argparse

from sso._cli.common import EXIT_BAD_INPUT, EXIT_OK, Command, print_error, print_warnings


def _configure_validate(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("cases", nargs="+", metavar="CASE.toml", help="case files to check")


def _validate(args: argparse.Namespace) -> int:
    from sso._cases.schema import CaseError, load_case

    exit_code = EXIT_OK
    for path in args.cases:
        try:
            case = load_case(path)
        except CaseError as error:
            print_error(str(error))
            exit_code = EXIT_BAD_INPUT
            continue
        print_warnings(case.name, case.warnings)
        if case.kind == "shaft_series":
            print(f"ok: {path}: {case.name}, {len(case.beta_deg)} joints, {case.model} model, "
                  f"option {case.option}", flush=True)
        else:
            print(f"ok: {path}: {case.name}, {case.summary()}", flush=True)
    return exit_code


COMMAND = Command(
    "validate", "check case files only",
    "Read and check each case file; print what is wrong (key, value, allowed range, "
    "line) and exit 2 if any file is invalid.",
    _configure_validate, _validate)
