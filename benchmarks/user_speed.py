"""Speed as a user meets it: fresh processes, first solves of a shape, stalls.

Three measurements, each figure a ratio or a time measured in one run:

1. **Fresh process.** A Python process that imports sso and solves the README
   example (option 3, beta bounds 10-40 deg), from its start to its answer, against
   one that imports numpy and scipy and solves it with the skilled baseline
   (:mod:`benchmarks.skilled_baseline`): ``"lm"`` alone (one start) and the default
   cross-checked call. Warm-up: each program runs once untimed (it compiles every
   module it imports to bytecode, as an installed package has it). Then the three
   commands take turns, ``repeats`` times each; the median wall time of each is
   compared.
2. **First solve of a new shape.** In a running process (sso imported, one 2-joint
   solve done), the first ``sso.optimise(..., solvers=("lm",), starts=1)`` of 3 to 8
   and of 30 joints (option 3), the shape's build included.
3. **No stalls.** ``CALLS`` calls of ``"lm"`` (one start) on random designs of each of
   a few shapes in one process, from the shape's first call: the largest call after
   the first against the median of all, in CPU time.

Usage::

    python -m benchmarks.user_speed [--repeats 5]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

import sso
from sso._solvers.nlp import cached_shapes

CALLS = 200
STALL_SHAPES = ((3, 1), (4, 3), (6, 1), (6, 3))
FIRST_SOLVE_JOINTS = (3, 4, 5, 6, 7, 8, 30)
TARGET_LM_PROCESS = 0.3
TARGET_DEFAULT_PROCESS = 1.0
TARGET_FIRST_SOLVE_S = 0.020
TARGET_FIRST_SOLVE_30_S = 0.1
TARGET_STALL = 10.0

BETA_DEG, PHASE_DEG = [30.0, 40.0, 40.0], [90.0, 90.0]
"""The README example's design (option 3, beta bounds 10-40 deg, phases 0-180 deg)."""
BOUNDS = "beta_bounds_deg=(10.0, 40.0), phase_bounds_deg=(0.0, 180.0)"
PROCESSES = {
    "skilled": ("import numpy as np\nfrom benchmarks.skilled_baseline import solve\n"
                f"solve(np.array({BETA_DEG}), np.array({PHASE_DEG}), 3, (10.0, 40.0), "
                "(0.0, 180.0))\n"),
    "sso_lm": (f"import sso\nsso.optimise(sso.ShaftSeries({BETA_DEG}, {PHASE_DEG}), 3, "
               f"{BOUNDS}, solvers=('lm',), starts=1)\n"),
    "sso_default": (f"import sso\nsso.optimise(sso.ShaftSeries({BETA_DEG}, {PHASE_DEG}), 3, "
                    f"{BOUNDS})\n"),
}
"""Each side's whole program, from its imports to its answer."""


def fresh_process_figures(repeats: int) -> dict[str, Any]:
    """Median wall time of each program of :data:`PROCESSES` in a fresh process (taking
    turns), and sso's over the skilled script's.

    Each program runs once untimed first (the warm-up, the same on both sides): it writes
    the bytecode of every module it imports, as an installed package has it, into a
    folder of this run (``PYTHONPYCACHEPREFIX``), whatever ``PYTHONDONTWRITEBYTECODE``
    says; without it sso's own modules, not yet compiled in an editable checkout, were
    compiled from source in every timed process (about 60 ms of a 0.2 s process)."""
    times: dict[str, list[float]] = {name: [] for name in PROCESSES}
    with tempfile.TemporaryDirectory() as bytecode:
        environment = {name: value for name, value in os.environ.items()
                       if name != "PYTHONDONTWRITEBYTECODE"}
        environment["PYTHONPYCACHEPREFIX"] = bytecode
        for round_number in range(repeats + 1):
            for name, program in PROCESSES.items():
                started = time.perf_counter()
                subprocess.run([sys.executable, "-c", program], check=True,
                               capture_output=True, env=environment,
                               cwd=Path(__file__).resolve().parents[1])
                if round_number:
                    times[name].append(time.perf_counter() - started)
    medians = {name: statistics.median(values) for name, values in times.items()}
    return {"median_s": medians,
            "lm_over_skilled": medians["sso_lm"] / medians["skilled"],
            "default_over_skilled": medians["sso_default"] / medians["skilled"]}


def _solve_lm(joints: int, option: int, rng: np.random.Generator,
              clock: Any = time.perf_counter) -> float:
    """Seconds of one ``"lm"`` call on a random design of the shape, by ``clock``."""
    series = sso.ShaftSeries(rng.uniform(5.0, 35.0, joints), rng.uniform(0.0, 180.0, joints - 1))
    started = clock()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sso.optimise(series, option, solvers=("lm",), starts=1, beta_bounds_deg=(5.0, 35.0))
    return float(clock() - started)


def first_solve_figures() -> dict[str, float]:
    """Seconds of the first ``"lm"`` solve of each shape of :data:`FIRST_SOLVE_JOINTS` joints
    (option 3) in this process, after one 2-joint solve (imports and CasADi loaded), the
    process's built shapes dropped before each."""
    rng = np.random.default_rng(33)
    _solve_lm(2, 3, rng)
    figures = {}
    for joints in FIRST_SOLVE_JOINTS:
        cached_shapes().clear()  # a shape solved earlier in this run is new again
        figures[str(joints)] = _solve_lm(joints, 3, rng)
    return figures


def stall_figures() -> dict[str, dict[str, float]]:
    """For each shape of :data:`STALL_SHAPES`: the median of its first :data:`CALLS` calls,
    the largest after the first, and their ratio, in this process's CPU time (a call of
    0.1 ms that waits for a core on a shared machine waits a scheduler slice, many times
    its work; the work is what a stall is)."""
    rng = np.random.default_rng(34)
    figures = {}
    for joints, option in STALL_SHAPES:
        times = [_solve_lm(joints, option, rng, time.process_time) for _ in range(CALLS)]
        median = statistics.median(times)
        figures[f"{joints} joints, option {option}"] = {
            "first_s": times[0], "median_s": median, "largest_after_first_s": max(times[1:]),
            "ratio": max(times[1:]) / median}
    return figures


def targets(fresh: dict[str, Any], first: dict[str, float],
            stalls: dict[str, dict[str, float]]) -> dict[str, dict[str, Any]]:
    """The issue's targets of this module, met or missed, with what was measured."""
    small = {joints: seconds for joints, seconds in first.items() if joints != "30"}
    worst_stall = max(stalls, key=lambda name: stalls[name]["ratio"])
    return {
        f"fresh process to the README answer, \"lm\" <= {TARGET_LM_PROCESS}x the skilled "
        "script's": {
            "met": fresh["lm_over_skilled"] <= TARGET_LM_PROCESS,
            "measured": f"{fresh['lm_over_skilled']:.2f}x ({fresh['median_s']['sso_lm']:.2f} s "
                        f"against {fresh['median_s']['skilled']:.2f} s)"},
        f"fresh process to the README answer, default call <= {TARGET_DEFAULT_PROCESS}x the "
        "skilled script's": {
            "met": fresh["default_over_skilled"] <= TARGET_DEFAULT_PROCESS,
            "measured": f"{fresh['default_over_skilled']:.2f}x "
                        f"({fresh['median_s']['sso_default']:.2f} s)"},
        "first solve of a new shape <= 20 ms (3 to 8 joints), <= 0.1 s (30 joints)": {
            "met": (max(small.values()) <= TARGET_FIRST_SOLVE_S
                    and first["30"] <= TARGET_FIRST_SOLVE_30_S),
            "measured": ", ".join(f"{joints}: {seconds * 1e3:.0f} ms"
                                  for joints, seconds in first.items())},
        f"no call of a shape > {TARGET_STALL:g}x the median of its first {CALLS}": {
            "met": stalls[worst_stall]["ratio"] <= TARGET_STALL,
            "measured": f"worst {stalls[worst_stall]['ratio']:.1f}x ({worst_stall}; median "
                        f"{stalls[worst_stall]['median_s'] * 1e3:.2f} ms)"},
    }


def measure(repeats: int) -> dict[str, Any]:
    """Every figure of this module and its targets."""
    fresh = fresh_process_figures(repeats)
    first = first_solve_figures()
    stalls = stall_figures()
    return {"fresh_process": fresh, "first_solve_s": first, "stalls": stalls,
            "targets": targets(fresh, first, stalls)}


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    figures = measure(parser.parse_args(argv).repeats)
    print(json.dumps(figures, indent=1))


if __name__ == "__main__":
    main()
