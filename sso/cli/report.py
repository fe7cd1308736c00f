"""``sso report``: render the report files again from ``result.json`` files alone."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

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
    from sso.cli.tracked import RENDERING_ERRORS, field_at_fault
    from sso.files import write_bytes_atomic
    from sso.reports.writer import ResultFileError, read_result, render
    from sso.validation import shown

    exit_code = EXIT_OK
    for path in args.results:
        try:
            document = read_result(path)
        except ResultFileError as error:
            print_error(str(error))
            exit_code = EXIT_BAD_INPUT
            continue
        try:
            folder, formats = _report_folder(args, path, document)
            files = render(document, formats)
        except RENDERING_ERRORS as error:
            field = field_at_fault(
                lambda tracked, path=path: render(tracked, _report_folder(args, path, tracked)[1]),
                document)
            where = f"field {field}" if field else "a field"
            print_error(f"{path}: not a result document sso can report from: {where} does not "
                        f"hold what sso writes there ({type(error).__name__}: "
                        f"{shown(str(error))}); write it again with sso run or sso evaluate")
            exit_code = EXIT_BAD_INPUT
            continue
        try:
            folder.mkdir(parents=True, exist_ok=True)
            written = [write_bytes_atomic(folder / name, data) for name, data in files.items()]
        except OSError as error:
            print_error(f"{path}: cannot write the report into {folder}: {error.strerror or error}")
            exit_code = EXIT_BAD_INPUT
            continue
        say(args, f"{path}: wrote {', '.join(item.name for item in written) or 'nothing'} "
            f"in {folder}")
    return exit_code


def _report_folder(args: argparse.Namespace, path: str,
                   document: Any) -> tuple[Path, tuple[str, ...]]:
    """Where ``sso report`` writes the reports of ``path``, and which formats."""
    from sso.cases.schema import case_name

    formats = report_formats(args, [name for name in document["case"]["output"]["formats"]
                                    if name != "json"])
    if args.out is None:
        return Path(path).parent, formats
    if len(args.results) > 1:  # the name is checked like a case file's: it names a folder
        return Path(args.out) / case_name("case.name", document["case"]["name"]), formats
    return Path(args.out), formats


COMMAND = Command(
    "report", "render the reports again from result.json files",
    "Render speeds.csv, report.md, report.html and the plots again from each "
    "result.json alone.",
    _configure_report, _report)
