"""The ``sso`` command: parse the arguments, run one subcommand, return its exit code.

Exit codes: 0 every case solved and its solvers agree; 1 a solver failed or the
solvers disagreed (the report says so); 2 bad input (an unreadable or invalid
case or result file, bad arguments); 130 interrupted (Ctrl-C or SIGTERM, at any time:
:func:`sso._cli.main` takes both signals before it imports this module). Bad input
never shows a traceback.

Each subcommand is one :class:`sso._cli.common.Command` in a module of its own
(:mod:`sso._cli.solve`: run and evaluate; :mod:`sso._cli.validate`;
:mod:`sso._cli.report`; :mod:`sso._cli.studies`: sweep and tolerance); adding
one means adding its module and its entry in :data:`COMMANDS`. Heavy modules are
imported inside the handlers, so ``sso --help`` and ``sso validate`` load neither
CasADi nor SciPy.
"""

from __future__ import annotations

import argparse
import gc
from collections.abc import Sequence

from sso._cli import report, solve, studies, validate
from sso._cli.common import EXIT_INTERRUPTED, Command, print_error
from sso._distribution import installed_version
from sso._interrupts import interrupt_on_signals, raise_if_interrupted, restore_handlers

COMMANDS: tuple[Command, ...] = (
    *solve.COMMANDS,
    validate.COMMAND,
    report.COMMAND,
    *studies.COMMANDS,
)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``sso`` command with every subcommand."""
    parser = argparse.ArgumentParser(
        prog="sso",
        description="Shaft Series Optimisation: choose Hooke-joint operating angles and "
                    "phases so the output shaft turns evenly.",
        epilog="Exit codes: 0 all cases solved and cross-checks agree; 1 a solver failed or "
               "the solvers disagreed; 2 bad input; 130 interrupted (Ctrl-C, SIGTERM). "
               "'sso COMMAND --help' describes a command.")
    parser.add_argument("--version", action="version", version=f"sso {installed_version()}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for command in COMMANDS:
        subparser = subparsers.add_parser(command.name, help=command.summary,
                                          description=command.description)
        command.configure(subparser)
        subparser.set_defaults(handle=command.handle)
    return parser


COMMAND_GC_THRESHOLD = 20_000
"""Allocations between two collections of the youngest generation while a command runs
(Python's default: 700). Most of the objects a command creates are those of the
modules it imports (CasADi's and SciPy's bindings, sso's own), which live as long as
the process; each young collection during an import walks the module's growing
namespace again: at the default threshold, collecting took about 6% of the CPU time of
``sso run --no-plots`` on the paper's case (30 ms of 0.49 s; no collection at all saves
no more). Cycles are still collected, and the peak memory of the shipped cases' runs
is the same (within 0.3 MB)."""


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``sso`` command; returns the exit code (argparse exits 2 on bad arguments).

    Its modules imported (:func:`sso._cli.main` is the entry point that takes the
    signals before importing them).
    """
    previous = interrupt_on_signals()
    thresholds = gc.get_threshold()
    gc.set_threshold(COMMAND_GC_THRESHOLD, *thresholds[1:])
    try:
        args = build_parser().parse_args(argv)
        if getattr(args, "quiet", False):
            from sso._progress import silenced

            with silenced():
                quiet_code: int = args.handle(args)
            raise_if_interrupted()
            return quiet_code
        code: int = args.handle(args)
        raise_if_interrupted()  # a signal whose interruption native code discarded
        return code
    except KeyboardInterrupt:
        print_error("interrupted; files already written are complete, none is half-written")
        return EXIT_INTERRUPTED
    finally:
        gc.set_threshold(*thresholds)
        restore_handlers(previous)

