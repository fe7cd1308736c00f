"""The ``sso`` command line: :func:`main` parses the arguments and runs a subcommand.

:mod:`sso._cli.app` holds the parser and the case subcommands (``run``, ``evaluate``,
``validate``, ``report``); :mod:`sso._cli.studies` holds ``sweep`` and
``tolerance``; :mod:`sso._cli.exit_codes` the exit codes they share. This module
imports nothing heavy: :func:`main` takes SIGINT and SIGTERM first, then imports
the command.
"""

from __future__ import annotations

from collections.abc import Sequence

from sso._cli.exit_codes import EXIT_BAD_INPUT, EXIT_FAILED, EXIT_INTERRUPTED, EXIT_OK
from sso._interrupts import exit_on_signals, restore_handlers

__all__ = ["EXIT_BAD_INPUT", "EXIT_FAILED", "EXIT_INTERRUPTED", "EXIT_OK", "main"]


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``sso`` command; returns the exit code (argparse exits 2 on bad arguments).

    Ctrl-C (SIGINT) and SIGTERM end it with exit 130 and no traceback from its first
    instruction: while its modules are imported, and after it has finished. With
    ``argv`` None (the process's own command line: the ``sso`` script, ``python -m
    sso``) those handlers stay until the process ends; with ``argv`` given (a call
    from Python), the caller's handlers are put back.
    """
    previous = exit_on_signals(EXIT_INTERRUPTED)
    try:
        from sso._cli import app  # the heavy imports, once the signals are ours

        return app.main(argv)
    except KeyboardInterrupt:  # a signal in the instant app.main puts our handlers back
        return EXIT_INTERRUPTED
    finally:
        if argv is not None:
            restore_handlers(previous)
