"""sso._interrupts: a real SIGINT during a real IPOPT solve (CasADi) is not lost, and
SIGINT and SIGTERM held over a critical step reach their handlers after it.

The signals are real (``os.kill`` of this process from a timer thread); the solve is a
real CasADi IPOPT run of a problem large enough to be mid-iteration when the signal
comes (the extended Rosenbrock function of 2,000 variables, from its standard start).
"""

from __future__ import annotations

import os
import signal
import threading

import numpy as np
import pytest

from sso._interrupts import (
    Interrupted,
    interrupt_on_signals,
    interrupts_held,
    raised_after_native_call,
    restore_handlers,
)

VARIABLES = 2000
SIGNAL_AFTER_S = 0.3


def slow_ipopt() -> object:
    """An IPOPT solver that takes seconds from ``x0``: extended Rosenbrock, tolerance
    far below reach, many iterations."""
    import casadi

    x = casadi.SX.sym("x", VARIABLES)
    objective = casadi.sum1(100 * (x[1::2] - x[::2] ** 2) ** 2 + (1 - x[::2]) ** 2)
    return casadi.nlpsol("slow", "ipopt", {"x": x, "f": objective},
                         {"ipopt.print_level": 0, "print_time": False, "ipopt.tol": 1e-300,
                          "ipopt.max_iter": 100_000, "ipopt.hessian_approximation":
                          "limited-memory"})


def signalled_in(seconds: float, number: int = signal.SIGINT) -> threading.Timer:
    timer = threading.Timer(seconds, os.kill, (os.getpid(), number))
    timer.start()
    return timer


def start() -> np.ndarray:
    return np.tile([-1.2, 1.0], VARIABLES // 2)


def test_ipopt_alone_swallows_ctrl_c():
    # Why the module exists: CasADi runs the handler, stops IPOPT and returns normally.
    solver = slow_ipopt()
    timer = signalled_in(SIGNAL_AFTER_S)
    solver(x0=start())  # type: ignore[operator]
    timer.join()
    assert solver.stats()["return_status"] == "NonIpopt_Exception_Thrown"  # type: ignore[attr-defined]


def test_ctrl_c_during_ipopt_is_raised_when_the_solve_returns():
    solver = slow_ipopt()
    timer = signalled_in(SIGNAL_AFTER_S)
    with pytest.raises(KeyboardInterrupt), raised_after_native_call():
        solver(x0=start())  # type: ignore[operator]
    timer.join()
    assert solver.stats()["return_status"] == "NonIpopt_Exception_Thrown"  # type: ignore[attr-defined]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # restored


def test_ctrl_c_during_ipopt_through_its_buffers_is_raised_when_the_solve_returns():
    # sso calls IPOPT through numpy buffers (BufferedSolver): there CasADi returns with the
    # handler's exception set, which Python turns into a SystemError; the Ctrl-C wins.
    from sso._solvers.nlp import BufferedSolver

    solver = BufferedSolver(slow_ipopt())
    timer = signalled_in(SIGNAL_AFTER_S)
    with pytest.raises(KeyboardInterrupt) as caught, raised_after_native_call():
        solver(x0=start())
    timer.join()
    assert caught.type is KeyboardInterrupt
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # restored
    other = np.array([1.0, 1.0] * (VARIABLES // 2)) + 0.5  # the solver still works
    assert solver(x0=other, lbx=other, ubx=other)["x"] == pytest.approx(other)


def test_an_error_of_the_block_without_a_signal_is_raised_as_it_is():
    with pytest.raises(ZeroDivisionError), raised_after_native_call():
        1 / 0  # noqa: B018


@pytest.mark.parametrize("number", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_during_ipopt_under_the_sso_command_s_handler_is_raised(number):
    previous = interrupt_on_signals()
    try:
        solver = slow_ipopt()
        timer = signalled_in(SIGNAL_AFTER_S, number)
        with pytest.raises(Interrupted, match=f"signal {int(number)}"), \
                raised_after_native_call():
            solver(x0=start())  # type: ignore[operator]
        timer.join()
    finally:
        restore_handlers(previous)
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # restored
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL


def test_a_handler_that_raises_nothing_changes_nothing():
    seen: list[int] = []
    previous = signal.signal(signal.SIGINT, lambda number, frame: seen.append(number))
    try:
        solver = slow_ipopt()
        timer = signalled_in(SIGNAL_AFTER_S)
        with raised_after_native_call():
            solver(x0=start())  # type: ignore[operator]
        timer.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    assert seen == [signal.SIGINT]


def test_signals_held_over_a_step_reach_their_handlers_after_it():
    seen: list[int] = []
    previous = {number: signal.signal(number, lambda number, frame: seen.append(number))
                for number in (signal.SIGINT, signal.SIGTERM)}
    try:
        with interrupts_held():
            os.kill(os.getpid(), signal.SIGINT)
            os.kill(os.getpid(), signal.SIGTERM)
            for _ in range(1000):  # the handlers run between bytecodes: give them the chance
                pass
            assert seen == []
        assert seen == [signal.SIGINT, signal.SIGTERM]
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)


def test_signals_are_handled_through_the_public_signal_module_only():
    # Issue 33, item 3: sso._interrupts read and set handlers through CPython's private
    # _signal module (to save about 25 us a block). No module of sso imports it now.
    import ast
    from pathlib import Path

    package = Path(__file__).resolve().parents[1] / "sso"
    private = []
    for path in package.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = ([alias.name for alias in node.names] if isinstance(node, ast.Import)
                     else [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            private += [f"{path.name}: {name}" for name in names if name == "_signal"]
    assert private == []
    assert len(list(package.rglob("*.py"))) > 100  # the walk saw the package
