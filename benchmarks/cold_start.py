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

    python benchmarks/cold_start.py [--rounds 7] [--from-source] [--stages]

``--stages`` also runs ``sso run --no-plots`` in fresh processes that import CasADi and
SciPy first and time each stage after them (reading the case, the solve, the report,
writing it), the wall and CPU time of each stage (median).
"""

from __future__ import annotations

import argparse
import json
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


STAGE_PROBE = """
import json, sys, time
marks = [("start", time.perf_counter(), time.process_time())]


def mark(name):
    marks.append((name, time.perf_counter(), time.process_time()))


import casadi
mark("import casadi (in the baseline)")
import scipy.optimize
mark("import scipy.optimize (in the baseline)")
import sso._cli.app as app
import sso._cases.schema as schema
import sso._files as files
import sso._reports.kinds as kinds
import sso._run.run_case as run_case
mark("import sso's command line")


def timed(module, name, label):
    original = getattr(module, name)

    def wrapper(*arguments, **keywords):
        mark(label + ": before")
        try:
            return original(*arguments, **keywords)
        finally:
            mark(label)

    setattr(module, name, wrapper)


timed(schema, "load_case", "read the case")
timed(run_case, "run_parsed_case", "solve (with the imports of the run, shafts and solvers)")
timed(kinds, "render_report", "render the report")
timed(files, "replace_folder", "write the files")
code = app.main(sys.argv[1:])
mark("the closing summary")
print("STAGES=" + json.dumps(marks))
sys.exit(code)
"""
"""Runs ``sso run`` in a fresh process after importing CasADi and SciPy, and prints the
wall and CPU times at the boundaries of its stages (one JSON list)."""


def stage_times_ms(out: Path, rounds: int, variables: dict[str, str]
                   ) -> dict[str, tuple[float, float]]:
    """Median wall and CPU time (ms) of each stage of ``sso run --no-plots`` over
    ``rounds`` fresh processes; the time between two stages is called "bookkeeping"."""
    command = [sys.executable, "-c", STAGE_PROBE, "run", str(CASE), "--out", str(out),
               "--quiet", "--no-plots"]
    samples: dict[str, list[tuple[float, float]]] = {}
    for _ in range(rounds + 1):  # the first warms the caches
        completed = subprocess.run(command, check=True, capture_output=True, text=True,
                                   env=variables)
        marks = json.loads(completed.stdout.split("STAGES=")[1])
        stages: dict[str, list[float]] = {}
        for before, (name, wall, cpu) in zip(marks[:-1], marks[1:], strict=True):
            _, wall_before, cpu_before = before
            label = "bookkeeping between the stages" if name.endswith(": before") else name
            spent = stages.setdefault(label, [0.0, 0.0])
            spent[0] += 1e3 * (wall - wall_before)
            spent[1] += 1e3 * (cpu - cpu_before)
        for label, (wall, cpu) in stages.items():
            samples.setdefault(label, []).append((wall, cpu))
    return {label: (statistics.median(wall for wall, _ in pairs[1:]),
                    statistics.median(cpu for _, cpu in pairs[1:]))
            for label, pairs in samples.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=7, help="timed runs of each command")
    parser.add_argument("--from-source", action="store_true",
                        help="write no bytecode: sso's modules compile in every run")
    parser.add_argument("--stages", action="store_true",
                        help="also time the stages of sso run --no-plots in fresh processes")
    arguments = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        bytecode = None if arguments.from_source else Path(folder) / "bytecode"
        walls, cpus = interleaved_times_s(commands(Path(folder) / "out"), arguments.rounds,
                                          environment(bytecode))
        stages = (stage_times_ms(Path(folder) / "out", arguments.rounds, environment(bytecode))
                  if arguments.stages else {})
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
    if stages:
        print(f"\nstages of sso run --no-plots, CasADi and SciPy imported first (median of "
              f"{arguments.rounds} processes; a stage includes the imports it triggers)")
        print(f"{'stage':56s} {'wall (ms)':>9s} {'CPU (ms)':>9s}")
        for label, (wall, cpu) in stages.items():
            print(f"{label:56s} {wall:9.1f} {cpu:9.1f}")
        print(f"{'all':56s} {sum(wall for wall, _ in stages.values()):9.1f} "
              f"{sum(cpu for _, cpu in stages.values()):9.1f}")


if __name__ == "__main__":
    main()
