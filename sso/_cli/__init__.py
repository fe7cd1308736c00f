"""The ``sso`` command line: :func:`main` parses the arguments and runs a subcommand.

:mod:`sso._cli.app` holds the parser and the case subcommands (``run``, ``evaluate``,
``validate``, ``report``); :mod:`sso._cli.studies` holds ``sweep`` and
``tolerance``; :mod:`sso._cli.common` the exit codes they share.
"""

from sso._cli.app import main
from sso._cli.common import EXIT_BAD_INPUT, EXIT_FAILED, EXIT_INTERRUPTED, EXIT_OK

__all__ = ["EXIT_BAD_INPUT", "EXIT_FAILED", "EXIT_INTERRUPTED", "EXIT_OK", "main"]
