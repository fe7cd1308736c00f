"""Progress of long work on stderr for interactive runs, drawn by tqdm.

A bar shows the units done, the rate and the time left, on one line redrawn in
place. It is drawn only when stderr is a terminal, no CI system runs us and the
caller has not silenced progress (:func:`silenced`, which ``--quiet`` wraps every
command in); piped or redirected output never holds a bar.
"""

from __future__ import annotations

import os
import sys
import threading
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from contextvars import ContextVar
from typing import TYPE_CHECKING, TextIO

from sso._interrupts import raise_if_interrupted

if TYPE_CHECKING:
    from tqdm import tqdm

BAR_WIDTH = 30
BAR_FORMAT = ("{desc}[{bar:" + str(BAR_WIDTH) + "}] {n_fmt}/{total_fmt}{unit}{postfix}, "
              "{rate_fmt}, {elapsed} elapsed, {remaining} left")
"""Done out of total, the rate, the time so far and the time left (tqdm's fields)."""
TICK_S = 1.0
"""A bar shown after a delay is redrawn this often between its updates, s: a step that
takes minutes (a tolerance study on a busy machine) still shows the time going by."""

DEFAULT_SIZE = (100, 24)
EVERY_STEP_DRAWN = 100
"""Up to this many units every one is drawn (a run's steps); more are drawn at most
five times a second."""

_SILENCED: ContextVar[bool] = ContextVar("sso_progress_silenced", default=False)


@contextmanager
def silenced() -> Iterator[None]:
    """No bar is drawn inside this block (``--quiet``)."""
    token = _SILENCED.set(True)
    try:
        yield
    finally:
        _SILENCED.reset(token)


def interactive(stream: TextIO | None = None) -> bool:
    """True when ``stream`` (stderr) is a terminal, no CI system is running us and
    progress is not :func:`silenced`."""
    stream = sys.stderr if stream is None else stream
    return (bool(getattr(stream, "isatty", lambda: False)()) and not os.environ.get("CI")
            and not _SILENCED.get())


def _size(stream: TextIO) -> tuple[int, int]:
    """The terminal's columns and lines, each :data:`DEFAULT_SIZE`'s where it reports
    none (a new pseudo-terminal reports 0 by 0, on which tqdm would draw nothing)."""
    try:
        columns, lines = os.get_terminal_size(stream.fileno())
    except (AttributeError, OSError, ValueError):  # no file descriptor, or not a terminal
        columns = lines = 0
    return (columns if columns > 0 else DEFAULT_SIZE[0], lines if lines > 0 else DEFAULT_SIZE[1])


class ProgressBar:
    """Done, total, rate and time left, redrawn in place; silent when disabled.

    Parameters
    ----------
    total : int
        Units of work (points, samples, runs or steps) to do in this run.
    unit : str
        What a unit is called ("points", "samples").
    enabled : bool
        Draw the bar at all (:func:`silenced` overrides it).
    stream : file, optional
        Where to draw (default stderr).
    delay_s : float, optional
        Draw nothing until this much time has passed (work that may finish quickly,
        such as a case run, shows a bar only when it is long), s.
    description : str, optional
        The work under way, shown before the bar (:meth:`describe` changes it).
    """

    def __init__(self, total: int, unit: str, enabled: bool, stream: TextIO | None = None,
                 delay_s: float = 0.0, description: str = ""):
        self.total = total
        self.unit = unit
        self.enabled = enabled and total > 0 and not _SILENCED.get()
        self.done = 0
        self.failed = 0
        self._bar: tqdm[None] | None = None
        if self.enabled:
            from tqdm import tqdm  # only where a bar is drawn: a run's cold start skips it

            stream = sys.stderr if stream is None else stream
            columns, lines = _size(stream)
            self._bar = tqdm(total=total, desc=description, unit=f" {unit}", file=stream,
                             delay=delay_s,
                             bar_format=BAR_FORMAT, ncols=columns, nrows=lines,
                             mininterval=0.0 if total <= EVERY_STEP_DRAWN else 0.2)
        self._stop = threading.Event()
        self._ticker: threading.Thread | None = None
        if self._bar is not None and delay_s > 0.0:
            # work of few, long steps: without updates tqdm would draw nothing until a
            # step ends, so a daemon thread draws the bar once the delay has passed
            self._ticker = threading.Thread(target=self._tick, args=(delay_s,), daemon=True,
                                            name="sso-progress")
            self._ticker.start()

    def _tick(self, delay_s: float) -> None:
        if self._stop.wait(delay_s):
            return
        while self._bar is not None and not self._stop.is_set():
            self._bar.update(0)  # as an update draws it: the bar then ends its line on close
            self._stop.wait(TICK_S)

    def advance(self, count: int, failed: int = 0) -> None:
        """Record ``count`` more units done, ``failed`` of which failed.

        Raises
        ------
        sso._interrupts.Interrupted
            If Ctrl-C or SIGTERM came under the ``sso`` command and native code
            discarded its interruption: the work stops here, between two units.
        """
        raise_if_interrupted()
        self.done += count
        self.failed += failed
        if self._bar is not None:
            if failed:
                self._bar.set_postfix_str(f"{self.failed} failed", refresh=False)
            self._bar.update(count)

    def describe(self, text: str) -> None:
        """Name the work under way (``"phasing "``), shown before the bar."""
        if self._bar is not None:
            self._bar.set_description_str(text, refresh=False)

    def close(self) -> None:
        """End the bar's line (a bar never drawn leaves nothing)."""
        self._stop.set()
        if self._ticker is not None:
            self._ticker.join()
        if self._bar is not None:
            self._bar.close()


RUN_DELAY_S = 2.0
"""A case run shows its steps' bar once it has taken this long (short runs draw nothing), s."""


class Steps:
    """The named steps of one case run, as a bar shown once the run has taken
    :data:`RUN_DELAY_S`: the step under way, steps done, rate, time so far and left.

    Use it as a context manager (the bar's line ends on leaving) and call
    :meth:`finished` after each step.

    Parameters
    ----------
    case_name : str
        The case, named before the step.
    names : sequence of str
        The steps, in order (at least one).
    """

    def __init__(self, case_name: str, names: Sequence[str]) -> None:
        self.case_name = case_name
        self.names = tuple(names)
        self.bar = ProgressBar(len(self.names), "steps", interactive(), delay_s=RUN_DELAY_S,
                               description=self._label(0))

    def _label(self, index: int) -> str:
        return f"{self.case_name}: {self.names[index]} "

    def finished(self) -> None:
        """The step under way is done; the next one, if any, is named."""
        self.bar.advance(1)
        if self.bar.done < len(self.names):
            self.bar.describe(self._label(self.bar.done))

    def __enter__(self) -> Steps:
        return self

    def __exit__(self, *exception: object) -> None:
        self.bar.close()
