"""Cost of the robust phasing NLP against the sample size, per solver.

``optimise_robust`` with a percentile objective (CVaR, one variable and one
constraint per sample) on the tilt_down position of the shipped three-position truck
column, 1 mm / 1 deg normal tolerances. For each sample size it prints the median
wall time of one solver run (over every start of one call, the NLP graph already
built by a warm-up call) and the ratio SLSQP / IPOPT, so the docs' statement that
SLSQP's dense subproblem dominates at a few hundred samples can be checked.

Usage::

    python benchmarks/robust_samples.py [--samples 50 100 200 400]
"""

from __future__ import annotations

import argparse
import json
import statistics
from pathlib import Path

from sso._column.geometry import ColumnGeometry
from sso._column.robust_phasing import optimise_robust
from sso._column.tolerances import Tolerances

CASE = (Path(__file__).resolve().parents[1] / "tests" / "data" / "columns"
        / "truck_three_positions.json")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, nargs="+", default=[50, 100, 200, 400])
    sizes = parser.parse_args().samples
    points = json.loads(CASE.read_text())["positions"]["tilt_down"]["points_mm"]
    geometry = ColumnGeometry(points)
    print(f"{'samples':>7s} {'ipopt run (s)':>14s} {'slsqp run (s)':>14s} {'ratio':>7s} agree")
    for size in sizes:
        tolerances = Tolerances(hardpoint_mm=1.0, yoke_phase_deg=1.0, samples=size, seed=1)
        optimise_robust(geometry, tolerances)  # builds and caches the NLP graph
        result = optimise_robust(geometry, tolerances)
        times = {name: statistics.median(run.time_s for run in result.runs if run.solver == name)
                 for name in ("ipopt", "slsqp")}
        agree = result.crosscheck is not None and result.crosscheck.agree
        print(f"{size:7d} {times['ipopt']:14.4f} {times['slsqp']:14.4f} "
              f"{times['slsqp'] / times['ipopt']:7.1f} {agree}")


if __name__ == "__main__":
    main()
