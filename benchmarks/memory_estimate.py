"""Peak memory of sso.optimise, sso.optimise_batch and sso tolerance against the estimate
that guards them.

``python -m benchmarks.memory_estimate`` runs each shape in a fresh process and prints
its peak resident memory (``getrusage``) beside the estimate of
``sso._resources``: for ``sso.optimise`` the whole process's peak (40 deg and
5 deg joints, option 1, so that RE = 0 is out of reach and "lm" screens every start),
for ``sso.optimise_batch`` the peak above the process's own after a warm-up call.
``--large`` adds 64 joints from 1,000 starts (over 1.7 GB, minutes). ``sso tolerance`` of
the paper's option-1 case at its start, one worker: the whole command's peak
(``getrusage`` of the child), as tests/cli/test_tolerance_record.py measures it; with
``--large``, 1,000,000 samples too.

Measured on the 2-core development machine (25 Nov 2026), MB, measured / estimated:
optimise 2 joints 1 start 54.5 / 70.0, 64 joints 1 start (option 3) 64.5 / 80.9,
6 joints 100 starts 124.0 / 71.2, 6 joints 1,000 starts 125.8 / 81.4, 6 joints 10,000
starts 194.7 / 183.9, 16 joints 400 starts 126.8 / 90.5, 32 joints 100 starts
129.2 / 95.9, 32 joints 400 starts 232.4 / 173.7, 64 joints 1,000 starts at least
1,719 / 1,662; optimise_batch above the
process, option 1 (every start on to the Newton steps) after the solver rework of
25 Nov: 20,000 starts of 4 joints 112.4 / 178.1, 2,000 of 10 joints 75.3 / 42.4, 1,000
of 32 joints 389.1 / 259.2. sso tolerance (2 Dec 2026, busy machine): option 1 exact at its
start, 10,000 samples 88.9 / 82.2, 100,000 98.9 / 92.4, 1,000,000 179.3 / 181.6; paper
model, 10,000 samples 156.1 / 209.0.
"""

from __future__ import annotations

import json
import subprocess
import sys

OPTIMISE = """
import json, resource, sys, warnings
warnings.simplefilter("ignore")
import sso
joints, starts, option = (int(value) for value in sys.argv[1:4])
sso.optimise(sso.ShaftSeries([20.0, 25.0], [90.0]), option, starts=1)
series = sso.ShaftSeries([40.0] + [5.0] * (joints - 1), [90.0] * (joints - 1))
sso.optimise(series, option, starts=starts, memory_limit_mb=1e6)
print(json.dumps(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024))
"""

BATCH = """
import json, resource, sys
import numpy as np
import sso
starts, joints = int(sys.argv[1]), int(sys.argv[2])
rng = np.random.default_rng(0)
sso.optimise_batch(rng.uniform(5, 30, (2, joints)), rng.uniform(0, 180, (2, joints - 1)))
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
beta = np.full((starts, joints), 5.0)
beta[:, 0] = 40.0  # RE = 0 out of reach: every start goes on to the batched least squares
sso.optimise_batch(beta, rng.uniform(0, 180, (starts, joints - 1)), option=1,
                   memory_limit_mb=1e6)
print(json.dumps(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024 - before))
"""

TOLERANCE = """
import json, resource, subprocess, sys
subprocess.run([sys.executable, "-m", "sso._cli", *sys.argv[1:]], check=True,
               capture_output=True)
print(json.dumps(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024))
"""
TOLERANCE_CASES = [("paper_option1_exact", 10_000), ("paper_option1_exact", 100_000),
                   ("paper_option1_paper", 10_000)]

OPTIMISE_SHAPES = [(2, 1, 3), (64, 1, 3), (6, 100, 1), (6, 1000, 1), (6, 10_000, 1),
                   (16, 400, 1), (32, 100, 1), (32, 400, 1)]
BATCH_SHAPES = [(20_000, 4), (2_000, 10), (1_000, 32)]


def measured_mb(script: str, *arguments: int) -> float:
    shown = subprocess.run([sys.executable, "-c", script, *map(str, arguments)],
                           capture_output=True, text=True, check=True)
    return float(json.loads(shown.stdout))


def main() -> None:
    from sso._resources import batch_least_squares_mb, multistart_estimate

    shapes = OPTIMISE_SHAPES + ([(64, 1000, 1)] if "--large" in sys.argv else [])
    print("sso.optimise: joints, starts, option: measured / estimated MB (whole process)")
    for joints, starts, option in shapes:
        free = {1: joints - 1, 3: 2 * joints - 1}[option]
        estimate = multistart_estimate(joints, free, 0, starts, 2, screened=True).memory_mb
        print(f"  {joints}, {starts}, {option}: "
              f"{measured_mb(OPTIMISE, joints, starts, option):.1f} / {estimate:.1f}")
    print("sso.optimise_batch, option 1: starts, joints: measured / estimated MB (above "
          "the process)")
    for starts, joints in BATCH_SHAPES:
        estimate = batch_least_squares_mb(starts, joints - 1)
        print(f"  {starts}, {joints}: {measured_mb(BATCH, starts, joints):.1f} / "
              f"{estimate:.1f}")
    tolerance_mb()


def tolerance_mb() -> None:
    """``sso tolerance``'s peak against :func:`sso._studies.tolerance_samples.study_estimate`."""
    import tempfile
    from pathlib import Path

    from sso._cases.schema import load_case
    from sso._studies.tolerance_samples import study_estimate

    root = Path(__file__).resolve().parents[1]
    cases = TOLERANCE_CASES + ([("paper_option1_exact", 1_000_000)] if "--large" in sys.argv
                               else [])
    print("sso tolerance --at start --workers 1: case, samples: measured / estimated MB "
          "(whole process)")
    for name, samples in cases:
        case_path = root / "cases" / f"{name}.toml"
        case = load_case(case_path)
        estimate = study_estimate(case.series(), samples,
                                  (case.quadrature_rtol, case.quadrature_atol)).memory_mb
        with tempfile.TemporaryDirectory() as folder:
            shown = subprocess.run(
                [sys.executable, "-c", TOLERANCE, "tolerance", str(case_path), "--at", "start",
                 "--samples", str(samples), "--workers", "1", "--quiet", "--out", folder,
                 "--memory-limit", "100000"], capture_output=True, text=True, check=True)
        print(f"  {name}, {samples}: {float(json.loads(shown.stdout)):.1f} / {estimate:.1f}")


if __name__ == "__main__":
    main()
