"""Exit 130 (EXIT_INTERRUPTED, sso/_cli/exit_codes.py) for SIGINT or SIGTERM at any time
after the ``sso`` command starts, the first 0.3 s included (while it imports its
modules), and no traceback (issue 34, item 8): before, a signal then printed a
``KeyboardInterrupt`` traceback (exit 1 or -2), or SIGTERM killed it (exit 143, -15
here).

Real processes, real signals. "Starts" is the first instruction of sso's entry point
``sso._cli:main`` (which ``python -m sso`` calls too), which takes both signals before
anything else: the test watches the child's caught signals in ``/proc/PID/status``
(``SigCgt``) and counts the delays from the moment SIGTERM is among them (Python
itself never catches SIGTERM). A signal before that falls in Python's own start-up
(the interpreter, ``site``) and sso's two small package modules, where the signal's
default action still applies (about 8 ms of imports of sso's own; the interpreter's
start-up is not sso's to change).
"""

from __future__ import annotations

import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
CASE = ROOT / "cases" / "paper_option1_exact.toml"
SWEEP = f"""\
name = "s"
case = "{CASE}"
action = "optimise"

[axes]
"design.beta_deg[0]" = {{ start = 10, stop = 30, num = 20000 }}
"""
DELAYS_S = (0.0, 0.01, 0.05, 0.1, 0.2, 0.3)
CONSOLE_SCRIPT = Path(sys.executable).parent / "sso"


def catches_sigterm(pid: int) -> bool:
    """Whether process ``pid`` has a handler of SIGTERM (its ``SigCgt`` mask)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False
    caught = int(re.search(r"^SigCgt:\s*([0-9a-f]+)$", status, re.MULTILINE)[1], 16)
    return bool(caught >> (signal.SIGTERM - 1) & 1)


def signalled(command: list[str], delay_s: float, signal_number: int,
              cwd: Path) -> subprocess.CompletedProcess[str]:
    """Run ``command``; ``delay_s`` after it has taken SIGTERM, send ``signal_number``;
    the finished process."""
    child = subprocess.Popen(command, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True)
    deadline = time.monotonic() + 60
    while not catches_sigterm(child.pid):
        assert child.poll() is None and time.monotonic() < deadline, child.communicate()
    time.sleep(delay_s)
    # the work must outlast the delay, or the signal tests nothing (a quiet machine ran
    # a 40-point sweep within 0.3 s): fail rather than pass on a finished process
    assert child.poll() is None, f"finished within {delay_s} s: {child.communicate()}"
    child.send_signal(signal_number)
    stdout, stderr = child.communicate(timeout=120)
    return subprocess.CompletedProcess(command, child.returncode, stdout, stderr)


@pytest.mark.parametrize("signal_number", [signal.SIGINT, signal.SIGTERM],
                         ids=["SIGINT", "SIGTERM"])
@pytest.mark.parametrize("entry", ["sso script", "python -m sso"])
def test_a_signal_in_the_first_instants_of_sso_run_ends_it_with_exit_130(tmp_path, entry,
                                                                         signal_number):
    program = [str(CONSOLE_SCRIPT)] if entry == "sso script" else [sys.executable, "-m", "sso"]
    for delay_s in DELAYS_S:
        done = signalled([*program, "run", str(CASE), "--out", "out", "--no-plots",
                          "--quiet"], delay_s, signal_number, tmp_path)
        assert (done.returncode, "Traceback" in done.stderr) == (130, False), (
            f"delay {delay_s} s: exit {done.returncode}\n{done.stderr}")
        assert "interrupted" in done.stderr


@pytest.mark.parametrize("signal_number", [signal.SIGINT, signal.SIGTERM],
                         ids=["SIGINT", "SIGTERM"])
def test_a_signal_in_the_first_instants_of_sso_sweep_ends_it_with_exit_130(tmp_path,
                                                                           signal_number):
    (tmp_path / "s.toml").write_text(SWEEP)
    for delay_s in DELAYS_S:
        done = signalled([str(CONSOLE_SCRIPT), "sweep", "s.toml", "--out", f"out{delay_s}",
                          "--workers", "1", "--no-plots", "--quiet"], delay_s, signal_number,
                         tmp_path)
        assert (done.returncode, "Traceback" in done.stderr) == (130, False), (
            f"delay {delay_s} s: exit {done.returncode}\n{done.stderr}")


TAKEN_FIRST = """
import signal, sys
before = set(sys.modules)
import sso._cli
loaded = sorted(set(sys.modules) - before)
print(" ".join(loaded))
"""


def test_the_entry_point_takes_the_signals_before_any_heavy_import():
    # The window no handler of sso's covers: sso's modules imported before main()'s
    # first instruction. The command's modules (argparse, the subcommands, numpy,
    # CasADi) are imported after it: they used to be imported first (sso._cli imported
    # sso._cli.app), and a signal then ended in a traceback or exit 143.
    done = subprocess.run([sys.executable, "-c", TAKEN_FIRST], capture_output=True, text=True,
                          timeout=60, check=True)
    loaded = done.stdout.split()
    ours = {name for name in loaded if name.split(".")[0] == "sso"}
    assert {"sso._cli", "sso._interrupts"} <= ours <= {
        "sso", "sso._cli", "sso._cli.exit_codes", "sso._distribution", "sso._interrupts"}
    assert not {"argparse", "numpy", "casadi", "sso._cli.app"} & set(loaded)
