"""The ``sso`` command: parse arguments, call the API and the case, run and report modules, set the exit code.

Exit codes: 0 every case solved and its solvers agree; 1 a solver failed or the
solvers disagreed (the report says so); 2 bad input (an unreadable or invalid
case or result file, bad arguments). Bad input never shows a traceback.

Each subcommand is one :class:`Command` in :data:`COMMANDS`; adding one (``sso
sweep``, say) means adding an entry. Heavy modules are imported inside the
handlers, so ``sso --help`` and ``sso validate`` load neither CasADi nor SciPy.
"""

from __future__ import annotations

import argparse
import sys
import time
import traceback
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

import sso
from sso.cli.batch_commands import (
    configure_sweep,
    configure_tolerance,
    run_sweep,
    run_tolerance,
)
from sso.cli.common import (
    DEFAULT_OUT,
    EXIT_BAD_INPUT,
    EXIT_FAILED,
    EXIT_INTERRUPTED,
    EXIT_OK,
)
from sso.distribution import installed_version
from sso.limits import OUTPUT_FORMATS


@dataclass(frozen=True)
class Command:
    """One subcommand.

    Attributes
    ----------
    name : str
        What the user types after ``sso``.
    summary : str
        One line for ``sso --help``.
    description : str
        Text of ``sso <name> --help``.
    configure : callable
        Adds the subcommand's arguments to its parser.
    handle : callable
        Runs it on the parsed arguments and returns the exit code.
    """

    name: str
    summary: str
    description: str
    configure: Callable[[argparse.ArgumentParser], None]
    handle: Callable[[argparse.Namespace], int]


@dataclass
class Outcome:
    """What happened to one case, for the closing summary table."""

    case: str
    status: str
    exit_code: int
    residual_errors: tuple[str, str, str] = ("", "", "")
    seconds: float = 0.0
    folder: str = ""


# ---------------------------------------------------------------- argument helpers

def _list_argument(allowed: tuple[str, ...], what: str) -> Callable[[str], tuple[str, ...]]:
    def parse(text: str) -> tuple[str, ...]:
        items = tuple(item.strip() for item in text.split(",") if item.strip())
        unknown = [item for item in items if item not in allowed]
        if not items or unknown:
            raise argparse.ArgumentTypeError(
                f"{text!r}: give a comma-separated list of {', '.join(allowed)} ({what})")
        return tuple(dict.fromkeys(items))

    return parse


def _add_report_arguments(parser: argparse.ArgumentParser, out_help: str) -> None:
    parser.add_argument("--out", metavar="DIR", help=out_help)
    parser.add_argument("--formats", type=_list_argument(OUTPUT_FORMATS, "report files"),
                        metavar="LIST", help="report files to write, comma-separated from "
                        f"{','.join(OUTPUT_FORMATS)} (default: the case's [output] formats)")
    parser.add_argument("--no-plots", action="store_true",
                        help="write no PNG plots (matplotlib is not even imported)")
    parser.add_argument("--quiet", action="store_true",
                        help="print only errors, warnings and the closing summary")


def _configure_run(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("cases", nargs="+", metavar="CASE.toml", help="case files to solve")
    parser.add_argument("--solvers", type=_list_argument(("ipopt", "slsqp"), "solvers"),
                        metavar="LIST", help="solvers to run, comma-separated from ipopt,slsqp "
                        "(default: the case's [solver] solvers)")
    _add_report_arguments(parser, f"write each report into DIR/<case name>/ (default: {DEFAULT_OUT})")


def _configure_evaluate(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("cases", nargs="+", metavar="CASE.toml", help="case files to evaluate")
    _add_report_arguments(parser, f"write each report into DIR/<case name>/ (default: {DEFAULT_OUT})")


def _configure_validate(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("cases", nargs="+", metavar="CASE.toml", help="case files to check")


def _configure_report(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("results", nargs="+", metavar="RESULT.json",
                        help="result files written by sso run or sso evaluate")
    _add_report_arguments(parser, "write the reports into DIR (default: the folder of each "
                          "RESULT.json; with several results, DIR/<case name>/)")


# ---------------------------------------------------------------- handlers

def _formats(args: argparse.Namespace, case_formats: Sequence[str]) -> tuple[str, ...]:
    formats = args.formats if args.formats is not None else tuple(case_formats)
    return tuple(name for name in formats if not (args.no_plots and name == "png"))


def _say(args: argparse.Namespace, text: str) -> None:
    if not args.quiet:
        print(text, flush=True)


def _warn(case: str, texts: Sequence[str]) -> None:
    for text in texts:
        print(f"warning: {case}: {text}", file=sys.stderr, flush=True)


def _error(text: str) -> None:
    print(f"error: {text}", file=sys.stderr, flush=True)


def _solve_cases(args: argparse.Namespace, optimising: bool) -> int:
    from sso.cases.schema import CaseError, load_case

    outcomes: list[Outcome] = []
    folders: dict[str, str] = {}
    for path in args.cases:
        started = time.perf_counter()
        try:
            case = load_case(path)
        except CaseError as error:
            _error(str(error))
            outcomes.append(Outcome(path, "bad input", EXIT_BAD_INPUT))
            continue
        if case.name in folders:
            _error(f"{path}: name = {case.name!r} is already used by {folders[case.name]} in "
                   "this run; its report would overwrite that one")
            outcomes.append(Outcome(path, "bad input", EXIT_BAD_INPUT))
            continue
        folders[case.name] = path
        case = case.with_overrides(solvers=getattr(args, "solvers", None),
                                   formats=_formats(args, case.formats))
        folder = Path(args.out or DEFAULT_OUT) / case.name
        outcomes.append(_solve_one(args, case, folder, optimising, started))
    _print_summary(outcomes, optimising)
    return max(outcome.exit_code for outcome in outcomes)


def _solve_one(args: argparse.Namespace, case: Any, folder: Path, optimising: bool,
               started: float) -> Outcome:
    from sso.cases.mechanism import MECHANISM_KINDS
    from sso.reports.kinds import write_report
    from sso.run.document import evaluate_case, optimise_case
    from sso.run.mechanism_document import mechanism_document

    _say(args, f"{case.name}: {'solving' if optimising else 'evaluating'} {case.source}")
    try:
        if case.kind in MECHANISM_KINDS:
            document = mechanism_document(case, optimising)
        else:
            document = optimise_case(case) if optimising else evaluate_case(case)
    except ValueError as error:
        _error(f"{case.source}: {error}")
        return Outcome(case.name, "bad input", EXIT_BAD_INPUT)
    except Exception:
        _error(f"{case.source}: internal error while solving; please report it:\n"
               + traceback.format_exc())
        return Outcome(case.name, "internal error", EXIT_FAILED)
    _warn(case.name, document["warnings"])
    try:
        written = write_report(document, folder, case.formats)
    except (OSError, ValueError) as error:
        reason = error.strerror if isinstance(error, OSError) and error.strerror else error
        _error(f"{case.name}: cannot write the report into {folder}: {reason}")
        return Outcome(case.name, "cannot write", EXIT_BAD_INPUT)
    status, code = _status(document)
    if not document["success"]:
        _error(f"{case.name}: {document['verdict']}")
    _say(args, f"{case.name}: {status}; wrote {', '.join(path.name for path in written)} "
         f"in {folder}")
    designs = document.get("designs", {})
    errors = tuple(f"{designs[role]['evaluation']['residual_error']:.3g}" if role in designs else "-"
                   for role in ("initial", "optimum", "reference"))
    return Outcome(case.name, status, code, errors, time.perf_counter() - started, str(folder))


def _status(document: dict[str, Any]) -> tuple[str, int]:
    if document["mode"] == "evaluate":
        return "evaluated", EXIT_OK
    if document["mode"] == "analyse":
        return "analysed", EXIT_OK
    if document["success"]:
        return "solved", EXIT_OK
    if document["verdict"].startswith("solver failed"):
        return "solver failed", EXIT_FAILED
    return "solvers disagree", EXIT_FAILED


def _print_summary(outcomes: list[Outcome], optimising: bool) -> None:
    header = ("case", "status", "RE initial", "RE optimum" if optimising else "-",
              "RE reference", "time (s)", "report")
    rows = [header] + [(outcome.case, outcome.status, *outcome.residual_errors,
                        f"{outcome.seconds:.2f}" if outcome.folder else "", outcome.folder)
                       for outcome in outcomes]
    if not optimising:
        rows = [row[:3] + row[4:] for row in rows]
    widths = [max(len(row[column]) for row in rows) for column in range(len(rows[0]))]
    lines = ["  ".join(cell.ljust(width) for cell, width in zip(row, widths)).rstrip()
             for row in rows]
    lines.insert(1, "  ".join("-" * width for width in widths))
    print("\n" + "\n".join(lines), flush=True)


def _run(args: argparse.Namespace) -> int:
    return _solve_cases(args, optimising=True)


def _evaluate(args: argparse.Namespace) -> int:
    return _solve_cases(args, optimising=False)


def _validate(args: argparse.Namespace) -> int:
    from sso.cases.schema import CaseError, load_case

    exit_code = EXIT_OK
    for path in args.cases:
        try:
            case = load_case(path)
        except CaseError as error:
            _error(str(error))
            exit_code = EXIT_BAD_INPUT
            continue
        _warn(case.name, case.warnings)
        if case.kind == "shaft_series":
            print(f"ok: {path}: {case.name}, {len(case.beta_deg)} joints, {case.model} model, "
                  f"option {case.option}", flush=True)
        else:
            print(f"ok: {path}: {case.name}, {case.summary()}", flush=True)
    return exit_code


def _report(args: argparse.Namespace) -> int:
    from sso.reports.kinds import write_report
    from sso.reports.writer import ResultFileError, read_result

    exit_code = EXIT_OK
    for path in args.results:
        try:
            document = read_result(path)
        except ResultFileError as error:
            _error(str(error))
            exit_code = EXIT_BAD_INPUT
            continue
        # The folder is written afresh, so result.json goes into it again.
        formats = ("json", *_formats(args, [name for name in document["case"]["output"]["formats"]
                                            if name != "json"]))
        if args.out is None:
            folder = Path(path).parent
        elif len(args.results) > 1:
            folder = Path(args.out) / document["case"]["name"]
        else:
            folder = Path(args.out)
        try:
            written = write_report(document, folder, formats)
        except (OSError, ValueError) as error:
            reason = error.strerror if isinstance(error, OSError) and error.strerror else error
            _error(f"{path}: cannot write the report into {folder}: {reason}")
            exit_code = EXIT_BAD_INPUT
            continue
        _say(args, f"{path}: wrote {', '.join(item.name for item in written) or 'nothing'} "
             f"in {folder}")
    return exit_code


COMMANDS: tuple[Command, ...] = (
    Command("run", "solve case files and write their reports",
            "Solve each case (IPOPT and SLSQP, several starts, cross-checked) and write its "
            "report into DIR/<case name>/. One failing case does not stop the others; a "
            "summary table closes the run. Exit 0: all solved and the solvers agree; 1: a "
            "solver failed or the solvers disagreed; 2: bad input.",
            _configure_run, _run),
    Command("evaluate", "evaluate the designs as given, without optimising",
            "Evaluate each case's design as given (and its reference design), with no "
            "optimisation and no NLP, and write the same report without the optimum.",
            _configure_evaluate, _evaluate),
    Command("validate", "check case files only",
            "Read and check each case file; print what is wrong (key, value, allowed range, "
            "line) and exit 2 if any file is invalid.",
            _configure_validate, _validate),
    Command("report", "render the reports again from result.json files",
            "Render speeds.csv, report.md, report.html and the plots again from each "
            "result.json alone.",
            _configure_report, _report),
    Command("sweep", "optimise or evaluate a base case over a grid of key values",
            "Run a sweep file: a base case, the [axes] to vary (any case key, e.g. "
            "design.beta_deg[1], option, model, input_speed_rpm) and the action. Writes "
            "sweep.csv as chunks finish, report.md and a plot into DIR/<name>/; --resume "
            "computes only the missing points. Exit 0: every point finished (and converged); "
            "1: some did not; 2: bad input.",
            configure_sweep, run_sweep),
    Command("tolerance", "Monte Carlo tolerance study of a case's optimum",
            "Optimise the case (or read its optimum from --result RESULT.json), perturb the "
            "optimum's angles and phases as the case's [tolerance] table says (normal or "
            "uniform, deg), evaluate every sample, and write percentiles of RE, fluctuation "
            "and output acceleration with a histogram into DIR/<case name>/. --at start "
            "studies the case's design as given instead.",
            configure_tolerance, run_tolerance),
)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``sso`` command with every subcommand."""
    parser = argparse.ArgumentParser(
        prog="sso",
        description="Shaft Series Optimisation: choose Hooke-joint operating angles and "
                    "phases so the output shaft turns evenly.",
        epilog="Exit codes: 0 all cases solved and cross-checks agree; 1 a solver failed or "
               "the solvers disagreed; 2 bad input. 'sso COMMAND --help' describes a command.")
    parser.add_argument("--version", action="version", version=f"sso {installed_version()}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for command in COMMANDS:
        subparser = subparsers.add_parser(command.name, help=command.summary,
                                          description=command.description)
        command.configure(subparser)
        subparser.set_defaults(handle=command.handle)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``sso`` command; returns the exit code (argparse exits 2 on bad arguments)."""
    args = build_parser().parse_args(argv)
    try:
        return args.handle(args)
    except KeyboardInterrupt:
        _error("interrupted; files already written are complete, none is half-written")
        return EXIT_INTERRUPTED

