"""``sso report``: render the report files again from ``result.json`` files alone."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from sso._cli.common import (
    EXIT_BAD_INPUT,
    EXIT_OK,
    Command,
    add_report_arguments,
    print_error,
    report_formats,
    say,
)
from sso._limits import OUTPUT_FORMATS


def _configure_report(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("results", nargs="+", metavar="RESULT.json",
                        help="result files written by sso run or sso evaluate")
    add_report_arguments(parser, "write the reports into DIR (default: the folder of each "
                          "RESULT.json; with several results, DIR/<case name>/)")


def _report(args: argparse.Namespace) -> int:
    return max(_report_one(args, path) for path in args.results)


def _report_one(args: argparse.Namespace, path: str) -> int:
    """Read a saved result back (``from_dict``) and write its report; the exit code."""
    from sso._cli.saved_results import read_saved_result
    from sso._files import check_report_folder
    from sso._record import RecordError
    from sso._reports.kinds import report_kind_of, write_report

    try:
        result = read_saved_result(path)
    except RecordError as error:
        print_error(str(error))
        return EXIT_BAD_INPUT
    case = getattr(result, "case", None)  # a case run's result holds its case
    case_formats = OUTPUT_FORMATS if case is None else case.formats
    formats = report_formats(args, [name for name in case_formats if name != "json"])
    folder = Path(path).parent if args.out is None else Path(args.out)
    if args.out is not None and len(args.results) > 1:
        folder = folder / (Path(path).resolve().parent.name if case is None else case.name)
    try:
        adopt = _rewritten_result(path, folder)
        check_report_folder(folder, report_kind_of(result).folder, adopt)
        written = write_report(result, folder, ("json", *formats), adopt)
    except ValueError as error:
        print_error(f"{path}: cannot write the report: {error}")
        return EXIT_BAD_INPUT
    except OSError as error:
        print_error(f"{path}: cannot write the report into {folder}: {error.strerror or error}")
        return EXIT_BAD_INPUT
    say(args, f"{path}: wrote {', '.join(item.name for item in written) or 'nothing'} "
        f"in {folder}")
    return EXIT_OK


def _rewritten_result(path: str, folder: Path) -> tuple[str, ...]:
    """``("result.json",)`` if ``path`` is the ``result.json`` of ``folder``: the report
    writes it again (its contents are sso's, if not its listing in the manifest)."""
    from sso._reports.kinds import RESULT_FILE

    given = Path(path)
    if given.name == RESULT_FILE and os.path.realpath(given.parent) == os.path.realpath(folder):
        return (RESULT_FILE,)
    return ()


COMMAND = Command(
    "report", "render the reports again from result.json files",
    "Render speeds.csv, report.md, report.html and the plots again from each "
    "result.json alone.",
    _configure_report, _report)
