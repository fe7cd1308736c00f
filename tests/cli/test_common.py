"""The exit codes every subcommand shares, seen from a real ``sso`` process.

References: the codes documented in sso/_cli/app.py (0 solved and agreed, 1 a solver
failed or disagreed, 2 bad input) and the shell's convention 128 + signal number for
a process stopped by Ctrl-C (SIGINT = 2).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

from sso._cli.common import (
    DEFAULT_OUT,
    EXIT_BAD_INPUT,
    EXIT_FAILED,
    EXIT_INTERRUPTED,
    EXIT_OK,
)

ROOT = Path(__file__).resolve().parents[2]


def sso_command(*arguments: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    environment = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run(
        [sys.executable, "-m", "sso", *arguments],
        cwd=cwd,
        env=environment,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )


def test_codes_follow_their_conventions():
    assert (EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT) == (0, 1, 2)
    assert EXIT_INTERRUPTED == 128 + signal.SIGINT
    assert DEFAULT_OUT == "results"
    assert DEFAULT_OUT + "/" in (ROOT / ".gitignore").read_text(encoding="utf-8").splitlines()


def test_valid_case_exits_ok_and_bad_input_exits_2_without_traceback(tmp_path):
    good = sso_command("validate", str(ROOT / "cases" / "paper_option1_exact.toml"), cwd=tmp_path)
    assert good.returncode == EXIT_OK, good.stderr
    broken = tmp_path / "broken.toml"
    broken.write_text(
        "[design]\nbeta_deg = [30.0, 40.0]\n\n[solver]\nstrats = 4\n", encoding="utf-8"
    )
    bad = sso_command("validate", str(broken), cwd=tmp_path)
    assert bad.returncode == EXIT_BAD_INPUT
    assert "line 5" in bad.stderr and "did you mean solver.starts?" in bad.stderr
    assert "Traceback" not in bad.stderr
    assert not (tmp_path / DEFAULT_OUT).exists()  # validating writes nothing
