"""``sso report``: render the report files again from ``result.json`` files alone."""

from __future__ import annotations

import argparse
from pathlib import Path

from sso.cli.common import (
    EXIT_BAD_INPUT,
    EXIT_OK,
    Command,
    add_report_arguments,
    print_error,
    report_formats,
    say,
)


def _configure_report(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("results", nargs="+", metavar="RESULT.json",
                        help="result files written by sso run or sso evaluate")
    add_report_arguments(parser, "write the reports into DIR (default: the folder of each "
                          "RESULT.json; with several results, DIR/<case name>/)")


def _report(args: argparse.Namespace) -> int:
    from sso.reports.writer import ResultFileError, read_result, write_report

    exit_code = EXIT_OK
    for path in args.results:
        try:
            document = read_result(path)
        except ResultFileError as error:
            print_error(str(error))
            exit_code = EXIT_BAD_INPUT
            continue
        formats = report_formats(args, [name for name in document["case"]["output"]["formats"]
                                        if name != "json"])
        if args.out is None:
            folder = Path(path).parent
        elif len(args.results) > 1:
            folder = Path(args.out) / document["case"]["name"]
        else:
            folder = Path(args.out)
        try:
            written = write_report(document, folder, formats)
        except OSError as error:
            print_error(f"{path}: cannot write the report into {folder}: {error.strerror or error}")
            exit_code = EXIT_BAD_INPUT
            continue
        say(args, f"{path}: wrote {', '.join(item.name for item in written) or 'nothing'} "
            f"in {folder}")
    return exit_code


COMMAND = Command(
    "report", "render the reports again from result.json files",
    "Render speeds.csv, report.md, report.html and the plots again from each "
    "result.json alone.",
    _configure_report, _report)
