"""The exit codes of the ``sso`` command (a module of constants only, so that the
command's entry point reads them before it imports anything heavy)."""

EXIT_OK = 0
EXIT_FAILED = 1
EXIT_BAD_INPUT = 2
EXIT_INTERRUPTED = 130
"""Ctrl-C (SIGINT) or SIGTERM, at any time after the command starts (128 + SIGINT's
number, as a shell reports a program Ctrl-C ended)."""
