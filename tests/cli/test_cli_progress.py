"""Long work shows its progress (done, rate, time left) on a real terminal, and none
under ``--quiet`` or when stderr is not a terminal (issue 35, item 7).

The terminal is a pseudo-terminal from the standard library's ``pty`` module: the
command runs with stdin, stdout and stderr on its slave end, as in an interactive
shell, and the test reads what the master end receives.
"""

from __future__ import annotations

import fcntl
import os
import pty
import re
import select
import struct
import subprocess
import sys
import termios
import time
from pathlib import Path

import sso
from sso import _progress as progress
from sso._progress import ProgressBar

ROOT = Path(__file__).resolve().parents[2]
POSITIONS = ROOT / "cases" / "column_truck_three_positions.toml"
SAMPLES = 20000
BAR = re.compile(r"\[[^\]]{30}\] (\d+)/(\d+) (\w+)(?:, \d+ failed)?, +[\d.?]+ ?\w*/s, "
                 r"[\d:]+ elapsed, [\d:?]+ left")


def terminal_pair() -> tuple[int, int]:
    """A pseudo-terminal's master and slave ends, 200 columns by 50 lines (a new one
    reports 0 by 0)."""
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 50, 200, 0, 0))
    return master, slave


def on_a_terminal(*arguments: object, cwd: Path) -> tuple[int, str]:
    """Exit status and everything the terminal showed of ``sso ARGUMENTS``."""
    master, slave = terminal_pair()
    environment = {name: value for name, value in os.environ.items() if name != "CI"}
    process = subprocess.Popen([sys.executable, "-m", "sso", *map(str, arguments)], cwd=cwd,
                               stdin=slave, stdout=slave, stderr=slave, env=environment)
    os.close(slave)
    shown = b""
    while True:
        ready, _, _ = select.select([master], [], [], 1.0)
        if ready:
            try:
                chunk = os.read(master, 65536)
            except OSError:  # the slave end closed: the process is gone
                break
            if not chunk:
                break
            shown += chunk
        elif process.poll() is not None:
            break
    os.close(master)
    return process.wait(timeout=600), shown.decode("utf-8", errors="replace")


def test_a_tolerance_study_shows_samples_done_rate_and_time_left(tmp_path):
    code, shown = on_a_terminal("tolerance", POSITIONS, "--samples", SAMPLES, "--out", tmp_path,
                                "--no-plots", "--workers", "1", cwd=ROOT)
    assert code == 0, shown
    bars = [(int(done), int(total), unit) for done, total, unit in BAR.findall(shown)]
    assert bars and bars[-1] == (SAMPLES, SAMPLES, "samples"), shown
    assert "\r" in shown  # redrawn in place, one line


def test_quiet_shows_no_progress_on_a_terminal(tmp_path):
    code, shown = on_a_terminal("tolerance", POSITIONS, "--samples", SAMPLES, "--out", tmp_path,
                                "--no-plots", "--workers", "1", "--quiet", cwd=ROOT)
    assert code == 0, shown
    assert not BAR.search(shown) and " left" not in shown, shown


def test_no_progress_when_stderr_is_not_a_terminal(tmp_path):
    done = subprocess.run([sys.executable, "-m", "sso", "tolerance", str(POSITIONS), "--samples",
                           str(SAMPLES), "--out", str(tmp_path), "--no-plots", "--workers", "1"],
                          cwd=ROOT, capture_output=True, text=True, timeout=600,
                          env={name: value for name, value in os.environ.items() if name != "CI"})
    assert done.returncode == 0, done.stderr
    assert " left" not in done.stderr and not BAR.search(done.stderr)


def test_a_case_run_names_each_step_on_a_terminal(monkeypatch):
    # A run draws its bar once it has taken RUN_DELAY_S (2 s); at no delay this short
    # run draws it too, on a real terminal as stderr.
    monkeypatch.setattr(progress, "RUN_DELAY_S", 0.0)
    monkeypatch.delenv("CI", raising=False)
    master, slave = terminal_pair()
    shown = b""
    with os.fdopen(slave, "w", encoding="utf-8") as terminal:
        monkeypatch.setattr(sys, "stderr", terminal)
        sso.run_case(POSITIONS)  # a few hundred bytes: within the terminal's buffer
        while select.select([master], [], [], 0.2)[0]:
            shown += os.read(master, 65536)
    os.close(master)
    text = shown.decode("utf-8", errors="replace")
    # phasing, positions/tolerances/feel, spline teeth, excitation, steering figures
    assert [match[:3] for match in BAR.findall(text)][-1] == ("5", "5", "steps"), text
    for step in ("phasing", "positions, tolerances and feel", "spline teeth", "excitation",
                 "steering figures"):
        assert f"column_truck_three_positions: {step} [" in text


def test_a_long_step_shows_the_time_going_by_before_it_ends():
    # A bar with a delay is drawn once the delay has passed, though no step has ended
    # (a tolerance step of 48 s on a busy machine, issue 35): here 0.1 s, then 1.5 s.
    master, slave = terminal_pair()
    shown = b""
    with os.fdopen(slave, "w", encoding="utf-8") as terminal:
        bar = ProgressBar(3, "steps", True, stream=terminal, delay_s=0.1,
                          description="truck: tolerances ")
        time.sleep(1.5)  # a step under way, no update
        drawn_before_any_update = b""
        while select.select([master], [], [], 0.2)[0]:
            drawn_before_any_update += os.read(master, 65536)
        bar.advance(3)
        bar.close()
        while select.select([master], [], [], 0.2)[0]:
            shown += os.read(master, 65536)
    os.close(master)
    early = drawn_before_any_update.decode("utf-8", errors="replace")
    assert BAR.findall(early)[0][:3] == ("0", "3", "steps"), early
    assert "truck: tolerances [" in early
    assert BAR.findall(shown.decode("utf-8", errors="replace"))[-1][:3] == ("3", "3", "steps")
    assert shown.endswith(b"\r\n")  # the line ended


def test_a_shaft_series_and_a_mechanism_run_name_their_steps(monkeypatch):
    monkeypatch.setattr(progress, "RUN_DELAY_S", 0.0)
    monkeypatch.delenv("CI", raising=False)
    for case, steps in (("paper_option3_exact.toml", ("optimisation", "reference")),
                        ("mechanisms/fourbar_swing_design.toml", ("design", "tables"))):
        master, slave = terminal_pair()
        shown = b""
        with os.fdopen(slave, "w", encoding="utf-8") as terminal:
            monkeypatch.setattr(sys, "stderr", terminal)
            run = sso.run_case(ROOT / "cases" / case)
            while select.select([master], [], [], 0.2)[0]:
                shown += os.read(master, 65536)
        os.close(master)
        text = shown.decode("utf-8", errors="replace")
        assert BAR.findall(text)[-1][:3] == ("2", "2", "steps"), text
        for step in steps:
            assert f"{run.case.name}: {step} [" in text
