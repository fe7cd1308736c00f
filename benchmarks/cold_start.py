"""Cold wall time of ``sso run`` on the paper's option-3 case, against the bare imports.

Each measurement starts a fresh Python process, so module imports are paid every
time (the operating system's file cache is warm after the first round). The three
commands are interleaved round by round, so a slow spell of the machine hits them
alike; the medians of the wall times and of the CPU times, and their ratios, are
printed.

Every process runs from compiled bytecode, as an installed package does (pip compiles
it at install time): the timed processes cache it in a temporary folder
(``PYTHONPYCACHEPREFIX``) even where ``PYTHONDONTWRITEBYTECODE`` is set, and the untimed
first round writes it. ``--from-source`` measures the other case, sso's modules
compiled from source in every run (``PYTHONDONTWRITEBYTECODE`` set, no cache folder).

Usage::

    python benchmarks/cold_start.py [--rounds 7] [--from-source]
"""

from __future__ import annotations

import argparse
import os
import resource
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


def environment(bytecode_folder: Path | None) -> dict[str, str]:
    """The timed processes' environment: bytecode cached in ``bytecode_folder``, or
    (None) never written, so that modules without a cached copy compile every run."""
    variables = dict(os.environ)
    variables.pop("PYTHONPYCACHEPREFIX", None)
    if bytecode_folder is None:
        variables["PYTHONDONTWRITEBYTECODE"] = "1"
    else:
        variables.pop("PYTHONDONTWRITEBYTECODE", None)
        variables["PYTHONPYCACHEPREFIX"] = str(bytecode_folder)
    return variables


def timed_s(command: list[str], variables: dict[str, str] | None = None
            ) -> tuple[float, float]:
    """Wall time and CPU time (user + system) of one run of ``command`` (s) in the
    environment ``variables`` (None: this process's); raises if it fails.

    On a shared machine the CPU time is the steadier figure: it leaves out the time the
    process waited for a core.
    """
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True, env=variables)
    wall = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def interleaved_times_s(timed: dict[str, list[str]], rounds: int, variables: dict[str, str]
                        ) -> tuple[dict[str, list[float]], dict[str, list[float]]]:
    """Wall and CPU times (s) of each command over ``rounds`` rounds, the commands taking
    turns within each round, after one untimed round that warms the file and bytecode
    caches."""
    for command in timed.values():
        timed_s(command, variables)
    walls: dict[str, list[float]] = {name: [] for name in timed}
    cpus: dict[str, list[float]] = {name: [] for name in timed}
    for _ in range(rounds):
        for name, command in timed.items():
            wall, cpu = timed_s(command, variables)
            walls[name].append(wall)
            cpus[name].append(cpu)
    return walls, cpus


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=7, help="timed runs of each command")
    parser.add_argument("--from-source", action="store_true",
                        help="write no bytecode: sso's modules compile in every run")
    arguments = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        bytecode = None if arguments.from_source else Path(folder) / "bytecode"
        walls, cpus = interleaved_times_s(commands(Path(folder) / "out"), arguments.rounds,
                                          environment(bytecode))
    wall_baseline = statistics.median(next(iter(walls.values())))
    cpu_baseline = statistics.median(next(iter(cpus.values())))
    print(f"median of {arguments.rounds} cold runs each ({sys.executable}; "
          f"{'compiled from source' if arguments.from_source else 'cached bytecode'})")
    print(f"{'command':48s} {'wall (s)':>8s} {'min (s)':>8s} {'ratio':>6s} {'CPU (s)':>8s} "
          f"{'ratio':>6s}")
    for name, samples in walls.items():
        wall = statistics.median(samples)
        cpu = statistics.median(cpus[name])
        print(f"{name:48s} {wall:8.3f} {min(samples):8.3f} {wall / wall_baseline:6.2f} "
              f"{cpu:8.3f} {cpu / cpu_baseline:6.2f}")


if __name__ == "__main__":
    main()
