"""Cold wall time of ``sso run`` on the paper's option-3 case, against the bare imports.

Each measurement starts a fresh Python process, so module imports are paid every
time (the operating system's file cache is warm after the first round). The three
commands are interleaved round by round, so a slow spell of the machine hits them
alike; the medians and their ratios are printed.

Usage::

    python benchmarks/cold_start.py [--rounds 7]
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "cases" / "paper_option3_exact.toml"


def commands(out: Path) -> dict[str, list[str]]:
    """The three timed commands: bare imports, run with plots, run without plots."""
    run = [sys.executable, "-m", "sso._cli", "run", str(CASE), "--out", str(out), "--quiet"]
    return {
        "python -c 'import casadi, scipy.optimize'": [sys.executable, "-c",
                                                      "import casadi, scipy.optimize"],
        "sso run paper_option3_exact.toml": run,
        "sso run paper_option3_exact.toml --no-plots": [*run, "--no-plots"],
    }


def wall_time_s(command: list[str]) -> float:
    """Wall time of one run of ``command`` (s); raises if it fails."""
    started = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True)
    return time.perf_counter() - started


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=7, help="timed runs of each command")
    rounds = parser.parse_args().rounds
    with tempfile.TemporaryDirectory() as folder:
        timed = commands(Path(folder))
        for command in timed.values():  # warm the file cache once
            wall_time_s(command)
        times: dict[str, list[float]] = {name: [] for name in timed}
        for _ in range(rounds):
            for name, command in timed.items():
                times[name].append(wall_time_s(command))
    baseline_name = next(iter(timed))
    baseline = statistics.median(times[baseline_name])
    print(f"median of {rounds} cold runs each ({sys.executable})")
    print(f"{'command':48s} {'median (s)':>10s} {'min (s)':>8s} {'ratio':>6s}")
    for name, samples in times.items():
        median = statistics.median(samples)
        print(f"{name:48s} {median:10.3f} {min(samples):8.3f} {median / baseline:6.2f}")


if __name__ == "__main__":
    main()
