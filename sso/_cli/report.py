"""``sso report``: render the report files again from ``result.json`` files alone."""

from __future__ import annotations

import argparse
import os
from pathlib import Path
from typing import Any

from sso._cli.common import (
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
    from sso._cli.tracked import RENDERING_ERRORS
    from sso._files import check_report_folder
    from sso._reports.kinds import CASE_REPORT, write_report
    from sso._reports.writer import ResultFileError, read_result

    exit_code = EXIT_OK
    for path in args.results:
        if _is_saved_result(path):
            exit_code = max(exit_code, _report_saved_result(args, path))
            continue
        try:
            document = read_result(path)
        except ResultFileError as error:
            print_error(str(error))
            exit_code = EXIT_BAD_INPUT
            continue
        try:
            folder, formats = _report_folder(args, path, document)
            adopt = _rewritten_result(path, folder)
            check_report_folder(folder, CASE_REPORT, adopt)
        except ValueError as error:  # a folder that is not a report's, or a bad case name
            print_error(f"{path}: cannot write the report: {error}")
            exit_code = EXIT_BAD_INPUT
            continue
        except RENDERING_ERRORS as error:
            print_error(_not_a_result(args, path, document, error))
            exit_code = EXIT_BAD_INPUT
            continue
        try:
            # The folder is written afresh, so result.json goes into it again.
            written = write_report(document, folder, ("json", *formats), adopt)
        except RENDERING_ERRORS as error:
            print_error(_not_a_result(args, path, document, error))
            exit_code = EXIT_BAD_INPUT
            continue
        except OSError as error:
            print_error(f"{path}: cannot write the report into {folder}: {error.strerror or error}")
            exit_code = EXIT_BAD_INPUT
            continue
        say(args, f"{path}: wrote {', '.join(item.name for item in written) or 'nothing'} "
            f"in {folder}")
    return exit_code


def _is_saved_result(path: str) -> bool:
    """True unless ``path`` holds a result document (a mechanism's or a column's, with
    ``"schema_version"``); an unreadable file counts as a saved result, whose reading
    then says what is wrong."""
    from sso._record import RecordError, read_json_object

    try:
        return "schema_version" not in read_json_object(path)
    except RecordError:
        return True


def _report_saved_result(args: argparse.Namespace, path: str) -> int:
    """Read a saved result back (``from_dict``) and write its report; the exit code."""
    from sso._cli.saved_results import read_saved_result
    from sso._files import check_report_folder
    from sso._limits import OUTPUT_FORMATS
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
    from sso._reports.writer import RESULT_FILE

    given = Path(path)
    if given.name == RESULT_FILE and os.path.realpath(given.parent) == os.path.realpath(folder):
        return (RESULT_FILE,)
    return ()


def _not_a_result(args: argparse.Namespace, path: str, document: Any,
                  error: BaseException) -> str:
    """Why ``document`` cannot be reported, naming the field at fault where it is found."""
    from sso._cli.tracked import field_at_fault
    from sso._reports.writer import render
    from sso._validation import shown

    field = field_at_fault(
        lambda tracked: render(tracked, _report_folder(args, path, tracked)[1]), document)
    where = f"field {field}" if field else "a field"
    return (f"{path}: not a result document sso can report from: {where} does not hold what "
            f"sso writes there ({type(error).__name__}: {shown(str(error))}); write it again "
            "with sso run or sso evaluate")


def _report_folder(args: argparse.Namespace, path: str,
                   document: Any) -> tuple[Path, tuple[str, ...]]:
    """Where ``sso report`` writes the reports of ``path``, and which formats."""
    from sso._cases.schema import case_name

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
