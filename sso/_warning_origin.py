"""Where a warning raised on the user's behalf should point: the user's own line."""

from __future__ import annotations

import sys


def user_stacklevel() -> int:
    """The ``stacklevel`` that makes the caller's ``warnings.warn`` name the nearest frame
    outside the ``sso`` package.

    ``warnings.warn(..., stacklevel=user_stacklevel())`` called anywhere inside the
    package blames the line of the user's code that called into it, however many
    package frames lie between (Python 3.12's ``skip_file_prefixes`` does this;
    3.11 does not have it). Cheaper than catching the warnings at the entry point
    and raising them again, which a single solve would pay for on every call.
    """
    frame = sys._getframe(1)
    level = 1
    while frame is not None and frame.f_globals.get("__name__", "").split(".")[0] == "sso":
        frame = frame.f_back  # type: ignore[assignment]
        level += 1
    return level
