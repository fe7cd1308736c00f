"""First-call cost against the number of joints: 3 and 30 joints, option 3, fresh processes.

``python -m benchmarks.scaling [--joints 3 30] [--repeats 3] [--out DIR]``

Each measurement is a fresh Python process that imports sso (and CasADi and SciPy,
outside the timed part), then times its first :func:`sso.optimise` call on an
option-3 case of the exact model (beta in [5, 35] deg, phase in [0, 180] deg,
default solvers and starts): everything that call builds (NLP graph, solver) is
included. The process reports that time, the RE reached and its peak resident
memory. The summary gives the median over ``--repeats`` processes, the ratio of
the largest to the smallest joint count (target: at most 5x) and whether
the peak memory stays under 500 MB. Also times the first call with each single
solver (``"ipopt"``, ``"slsqp"``, ``"lm"``, one start), so a build that only one
solver pays for shows.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
from pathlib import Path
from typing import Any

TARGET_RATIO = 5.0
TARGET_PEAK_MB = 500.0
METHODS = {"default": {}, "ipopt_1_start": {"solvers": ["ipopt"], "starts": 1},
           "slsqp_1_start": {"solvers": ["slsqp"], "starts": 1},
           "lm_1_start": {"solvers": ["lm"], "starts": 1}}

CHILD = """
import json, resource, sys, time, warnings
import numpy as np
import casadi, scipy.optimize  # imported outside the timed call
import sso
joints, method = int(sys.argv[1]), json.loads(sys.argv[2])
rng = np.random.default_rng(20261123 + joints)
series = sso.ShaftSeries(rng.uniform(5.0, 35.0, joints), rng.uniform(0.0, 180.0, joints - 1))
warnings.simplefilter("ignore")
started = time.perf_counter()
result = sso.optimise(series, 3, beta_bounds_deg=(5.0, 35.0), phase_bounds_deg=(0.0, 180.0),
                      **method)
elapsed = time.perf_counter() - started
peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
print(json.dumps({"time_s": elapsed, "fun": result.fun, "success": result.success,
                  "peak_mb": peak_mb}))
"""


def first_call(joints: int, method: dict[str, Any]) -> dict[str, Any]:
    """Time of the first ``sso.optimise`` call in a fresh process, with its peak memory."""
    output = subprocess.run([sys.executable, "-c", CHILD, str(joints), json.dumps(method)],
                            capture_output=True, text=True, check=True)
    figures: dict[str, Any] = json.loads(output.stdout.strip().splitlines()[-1])
    return figures


def measure(joint_counts: list[int], repeats: int) -> dict[str, Any]:
    """Median first-call time and worst peak memory for each method and joint count."""
    table: dict[str, Any] = {}
    for name, method in METHODS.items():
        rows = {}
        for joints in joint_counts:
            runs = [first_call(joints, method) for _ in range(repeats)]
            rows[joints] = {"time_s": statistics.median(run["time_s"] for run in runs),
                            "peak_mb": max(run["peak_mb"] for run in runs),
                            "fun": max(run["fun"] for run in runs),
                            "success": all(run["success"] for run in runs)}
        smallest, largest = min(joint_counts), max(joint_counts)
        table[name] = {"rows": rows,
                       "ratio": rows[largest]["time_s"] / rows[smallest]["time_s"]}
    return table


def summary(table: dict[str, Any], joint_counts: list[int]) -> str:
    """The figures and the issue's targets met or missed, as Markdown."""
    smallest, largest = min(joint_counts), max(joint_counts)
    met = {True: "met", False: "missed"}
    lines = ["# First call against joints (option 3, fresh process, build included)", "",
             "| method | joints | first call (ms) | peak memory (MB) | RE | success |",
             "|---|---|---|---|---|---|"]
    for name, entry in table.items():
        for joints, row in entry["rows"].items():
            lines.append(f"| {name} | {joints} | {row['time_s'] * 1e3:.1f} | "
                         f"{row['peak_mb']:.0f} | {row['fun']:.2e} | {row['success']} |")
    default = table["default"]
    peak = max(row["peak_mb"] for entry in table.values() for row in entry["rows"].values())
    lines += ["",
              f"- default call, {largest} joints over {smallest}: {default['ratio']:.2f}x, "
              f"target <= {TARGET_RATIO:g}x: {met[default['ratio'] <= TARGET_RATIO]}",
              *[f"- {name}, {largest} over {smallest} joints: {entry['ratio']:.2f}x"
                for name, entry in table.items() if name != "default"],
              f"- peak memory {peak:.0f} MB, target < {TARGET_PEAK_MB:g} MB: "
              f"{met[peak < TARGET_PEAK_MB]}"]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> None:
    """Measure, print the summary and write ``scaling.json`` / ``scaling.md``."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--joints", type=int, nargs="+", default=[3, 30])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--out", type=Path, default=Path("results/benchmarks"))
    arguments = parser.parse_args(argv)
    table = measure(arguments.joints, arguments.repeats)
    text = summary(table, arguments.joints)
    print(text)
    arguments.out.mkdir(parents=True, exist_ok=True)
    (arguments.out / "scaling.json").write_text(json.dumps(table, indent=2) + "\n")
    (arguments.out / "scaling.md").write_text(text)


if __name__ == "__main__":
    main()
