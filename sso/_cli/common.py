"""What every subcommand shares: exit codes, the default output folder, the
:class:`Command` record, and the argument and message helpers."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from sso._cli.exit_codes import EXIT_BAD_INPUT, EXIT_FAILED, EXIT_INTERRUPTED, EXIT_OK
from sso._limits import OUTPUT_FORMATS

__all__ = ["EXIT_BAD_INPUT", "EXIT_FAILED", "EXIT_INTERRUPTED", "EXIT_OK", "Command",
           "add_report_arguments", "list_argument", "print_error", "print_warnings",
           "report_formats", "say", "DEFAULT_OUT", "REPORT_FOLDER_HELP"]

DEFAULT_OUT = "results"
REPORT_FOLDER_HELP = f"write each report into DIR/<case name>/ (default: {DEFAULT_OUT})"


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


def list_argument(allowed: tuple[str, ...], what: str) -> Callable[[str], tuple[str, ...]]:
    """An argparse type: a comma-separated list, each item one of ``allowed``."""
    def parse(text: str) -> tuple[str, ...]:
        items = tuple(item.strip() for item in text.split(",") if item.strip())
        unknown = [item for item in items if item not in allowed]
        if not items or unknown:
            raise argparse.ArgumentTypeError(
                f"{text!r}: give a comma-separated list of {', '.join(allowed)} ({what})")
        return tuple(dict.fromkeys(items))

    return parse


def add_report_arguments(parser: argparse.ArgumentParser, out_help: str) -> None:
    """``--out``, ``--formats``, ``--no-plots`` and ``--quiet``."""
    parser.add_argument("--out", metavar="DIR", help=out_help)
    parser.add_argument("--formats", type=list_argument(OUTPUT_FORMATS, "report files"),
                        metavar="LIST", help="report files to write, comma-separated from "
                        f"{','.join(OUTPUT_FORMATS)} (default: the case's [output] formats)")
    parser.add_argument("--no-plots", action="store_true",
                        help="write no PNG plots (matplotlib is not even imported)")
    parser.add_argument("--quiet", action="store_true",
                        help="print only errors, warnings and the closing summary")


def report_formats(args: argparse.Namespace, case_formats: Sequence[str]) -> tuple[str, ...]:
    """``--formats`` or the case's formats, without PNG under ``--no-plots``."""
    formats = args.formats if args.formats is not None else tuple(case_formats)
    return tuple(name for name in formats if not (args.no_plots and name == "png"))


def say(args: argparse.Namespace, text: str) -> None:
    """Print ``text`` unless ``--quiet``."""
    if not args.quiet:
        print(text, flush=True)


def print_warnings(case: str, texts: Sequence[str]) -> None:
    """Print each of a case's warnings on stderr."""
    for text in texts:
        print(f"warning: {case}: {text}", file=sys.stderr, flush=True)


def print_error(text: str) -> None:
    """Print an error on stderr (never a traceback)."""
    print(f"error: {text}", file=sys.stderr, flush=True)
