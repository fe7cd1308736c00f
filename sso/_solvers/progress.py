"""A one-line progress bar on stderr for interactive runs."""

from __future__ import annotations

import os
import sys
import time
from typing import TextIO

BAR_WIDTH = 30


def interactive(stream: TextIO | None = None) -> bool:
    """True when ``stream`` (stderr) is a terminal and no CI system is running us."""
    stream = sys.stderr if stream is None else stream
    return bool(getattr(stream, "isatty", lambda: False)()) and not os.environ.get("CI")


class ProgressBar:
    """Done, total, rate and time left, redrawn in place; silent when disabled.

    Parameters
    ----------
    total : int
        Units of work (points or samples) to do in this run.
    unit : str
        What a unit is called ("points", "samples").
    enabled : bool
        Draw the bar at all.
    stream : file, optional
        Where to draw (default stderr).
    """

    def __init__(self, total: int, unit: str, enabled: bool, stream: TextIO | None = None):
        self.total = total
        self.unit = unit
        self.enabled = enabled and total > 0
        self.stream = sys.stderr if stream is None else stream
        self.done = 0
        self.failed = 0
        self.started = time.perf_counter()
        self._draw()

    def advance(self, count: int, failed: int = 0) -> None:
        """Record ``count`` more units done, ``failed`` of which failed."""
        self.done += count
        self.failed += failed
        self._draw()

    def close(self) -> None:
        """End the bar's line."""
        if self.enabled:
            self.stream.write("\n")
            self.stream.flush()

    def _draw(self) -> None:
        if not self.enabled:
            return
        elapsed_s = time.perf_counter() - self.started
        fraction = self.done / self.total
        filled = int(BAR_WIDTH * fraction)
        rate = self.done / elapsed_s if elapsed_s > 0 else 0.0
        left = f"{(self.total - self.done) / rate:.0f} s left" if rate > 0 else "starting"
        failed = f", {self.failed} failed" if self.failed else ""
        self.stream.write(f"\r[{'#' * filled}{'.' * (BAR_WIDTH - filled)}] {self.done}/"
                          f"{self.total} {self.unit}{failed}, {rate:.1f}/s, {left}   ")
        self.stream.flush()
