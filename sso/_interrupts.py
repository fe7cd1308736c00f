"""Ctrl-C and SIGTERM that reach the caller: held over a short critical step, or
carried across native code that would swallow them.

Python runs a signal's handler on the main thread, between bytecodes or when native
code asks (``PyErr_CheckSignals``). CasADi asks at every IPOPT iteration, and when
the handler raises (``KeyboardInterrupt``), it stops IPOPT, reports the solve as
``NonIpopt_Exception_Thrown`` and returns normally: the interruption is lost, and
the interrupted start looks like a failed one. :func:`raised_after_native_call`
keeps what the handler raised and raises it again when the native call returns.
"""

from __future__ import annotations

import os
import signal
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from types import FrameType, TracebackType
from typing import Any

INTERRUPTING_SIGNALS = (signal.SIGINT, signal.SIGTERM)


def _on_main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


class raised_after_native_call:  # a context manager, named for its use: with ...():
    """Raise, after the block, what a SIGINT or SIGTERM handler raised inside it.

    Wrap a call into native code that runs Python's signal handlers and then
    discards their exceptions (CasADi's IPOPT). A signal whose handler raises
    nothing, and signals left to the system (``SIG_DFL``, ``SIG_IGN``), are
    unchanged. Off the main thread (where no handler runs) the block runs as is.

    Raises
    ------
    BaseException
        The first exception a handler raised during the block (``KeyboardInterrupt``
        for Ctrl-C, and for SIGTERM under the ``sso`` command), whether the block
        ended normally or in an error (which the native call may make of the
        interruption).
    """

    __slots__ = ("_previous", "_raised")

    def __enter__(self) -> None:
        self._raised: list[BaseException] = []
        # signal's public functions turn each Python handler into an enum member and
        # back, raising and catching an exception each time: about 30 us per block
        # (4.5 us through signal's C module, which is private), once per IPOPT solve of
        # milliseconds.
        self._previous = ({} if not _on_main_thread() else
                          {number: handler for number in INTERRUPTING_SIGNALS
                           if callable(handler := signal.getsignal(number))})
        for number, handler in self._previous.items():
            signal.signal(number, self._keeping(handler))

    def _keeping(self, handler: Callable[[int, FrameType | None], Any]
                 ) -> Callable[[int, FrameType | None], Any]:
        raised = self._raised

        def handle(number: int, frame: FrameType | None) -> Any:
            try:
                return handler(number, frame)
            except BaseException as error:
                raised.append(error)
                raise

        return handle

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 traceback: TracebackType | None) -> None:
        for number, handler in self._previous.items():
            signal.signal(number, handler)
        # A native call can end in an error of its own once a handler has raised inside
        # it (CasADi's buffered call returns with the exception set: SystemError); the
        # signal is what happened. An error that is not an Exception (a KeyboardInterrupt
        # raised in Python code of the block) goes on as it is.
        if self._raised and error is None:
            raise self._raised[0]
        if self._raised and isinstance(error, Exception):
            raise self._raised[0] from None


@contextmanager
def interrupts_held() -> Iterator[None]:
    """Hold SIGINT and SIGTERM until the block ends, then deliver them to their handlers.

    For steps that must not stop halfway (renaming a finished file into place). On
    the main thread only, where Python runs the handlers; elsewhere, or while a
    signal is left to the system, the block runs as is.
    """
    if not _on_main_thread() or any(signal.getsignal(number) is None
                                    for number in INTERRUPTING_SIGNALS):
        yield
        return
    caught: list[int] = []

    def hold(number: int, frame: FrameType | None) -> None:
        caught.append(number)

    previous = {number: signal.signal(number, hold) for number in INTERRUPTING_SIGNALS}
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)
        for held in caught:
            signal.raise_signal(held)


class Interrupted(KeyboardInterrupt):
    """Ctrl-C or SIGTERM under the ``sso`` command (:func:`interrupt_on_signals`).

    A subclass, so that every ``except KeyboardInterrupt`` catches it, and one the
    interpreter does not take for an unhandled Ctrl-C: CPython marks a
    ``KeyboardInterrupt`` of exactly that class when it leaves code the interpreter
    runs, and then ends the process by SIGINT (exit -2) even where the program caught
    it and returned 130 (``sso run`` got SIGTERM during SLSQP: 6 of 8 runs ended so;
    with this class, 0 of 6).
    """


_RECEIVED: list[int] = []
"""The signals :func:`interrupt_on_signals`' handler took since it was installed: kept,
because a native call that runs Python code (a CasADi graph's build, a compiled
module's import) can discard what the handler raised there, and the program then went
on as if no signal had come (a SIGTERM then went unanswered)."""


def interrupt_on_signals() -> dict[int, Any]:
    """Make SIGINT and SIGTERM interrupt the program as :class:`Interrupted`.

    Each signal is also recorded, for :func:`raise_if_interrupted` to raise again where
    the first was discarded.

    Returns
    -------
    dict
        The previous handler of each signal, to give to :func:`restore_handlers`;
        empty off the main thread (nothing changed).
    """
    if not _on_main_thread():
        return {}
    _RECEIVED.clear()

    def interrupt(signal_number: int, frame: FrameType | None) -> None:
        _RECEIVED.append(signal_number)
        raise Interrupted(f"signal {signal_number}")

    return {number: signal.signal(number, interrupt) for number in INTERRUPTING_SIGNALS}


def raise_if_interrupted() -> None:
    """Raise :class:`Interrupted` if a signal came under :func:`interrupt_on_signals`'
    handler (its exception may have been discarded by native code on the way).

    Raises
    ------
    Interrupted
        If SIGINT or SIGTERM was received since the handler was installed.
    """
    if _RECEIVED:
        raise Interrupted(f"signal {_RECEIVED[0]}")


def exit_on_signals(exit_code: int) -> dict[int, Any]:
    """Make SIGINT and SIGTERM end the program with ``exit_code`` (SystemExit), quietly.

    For the first instructions of the ``sso`` command, before its modules are
    imported: a signal while Python imports them would otherwise end the process
    with a ``KeyboardInterrupt`` traceback (SIGINT) or be killed by the system
    (SIGTERM, exit 143). Nothing is written yet, so there is nothing to finish. The
    handler writes one line on stderr without Python's buffers (a print could
    interrupt a print) and raises :class:`SystemExit`, which Python reports with no
    traceback.

    Returns
    -------
    dict
        The previous handler of each signal (see :func:`restore_handlers`); empty off
        the main thread.
    """
    if not _on_main_thread():
        return {}
    said = f"error: interrupted (signal {{}}); exit {exit_code}\n"

    def leave(signal_number: int, frame: FrameType | None) -> None:
        os.write(2, said.format(signal_number).encode("ascii"))
        raise SystemExit(exit_code)

    return {number: signal.signal(number, leave) for number in INTERRUPTING_SIGNALS}


def restore_handlers(previous: dict[int, Any]) -> None:
    """Put back the handlers :func:`interrupt_on_signals` replaced (and forget the
    signals it recorded)."""
    for number, handler in previous.items():
        signal.signal(number, handler)
    _RECEIVED.clear()
