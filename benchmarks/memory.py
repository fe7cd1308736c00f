"""Resident memory of a long session: 20 optimisations with varied bounds and joints.

``python -m benchmarks.memory`` runs the memory target's workload in one process:
20 ``sso.optimise`` calls, 2 to 6 joints, beta bounds from 30 deg up to 89.9 deg,
both models, and prints the resident memory after each call, the peak, and the 20th
call's memory against the 5th's. Built NLPs are cached (least recently used,
``sso._limits.NLP_CACHE_SHAPES`` shapes per thread), so memory must level off.

Measured on the 2-core development machine (23 Nov 2026, when the tenth and twentieth
calls' 6 joints still had bounds up to 89.9 deg, since refused as beyond what float64
resolves): peak resident memory 177.7 MB; call 5 172.2 MB, call 20 177.9 MB (+3.3%);
v0.1 reached 4.7 GB in five
calls with bounds up to 89.99 deg. The target: under 1 GB, the 20th
call within 10% of the 5th.
"""

from __future__ import annotations

import resource
import time
import warnings

import sso

# The tenth call's 6 joints may reach 89.65 deg (docs/model.md, "Numerical limits").
UPPER_BOUNDS_DEG = (30.0, 40.0, 60.0, 75.0, 85.0, 89.0, 89.5, 89.9, 50.0, 89.6)
JOINTS = (2, 3, 4, 5, 6)


def resident_mb() -> float:
    """Current resident set size of this process, MB (from /proc)."""
    with open("/proc/self/statm", encoding="ascii") as handle:
        pages = int(handle.read().split()[1])
    return pages * resource.getpagesize() / 2**20


def main() -> None:
    memory = []
    start = time.perf_counter()
    for call in range(20):
        joints = JOINTS[call % len(JOINTS)]
        upper = UPPER_BOUNDS_DEG[call % len(UPPER_BOUNDS_DEG)]
        model = "exact" if call % 2 == 0 else "paper"
        series = sso.ShaftSeries([min(20.0 + 5 * k, upper) for k in range(joints)],
                                 [90.0] * (joints - 1), model)
        began = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = sso.optimise(series, 3, beta_bounds_deg=(0.0, upper), starts=2)
        memory.append(resident_mb())
        print(f"call {call + 1:2d}: {joints} joints, {model:5s}, beta <= {upper:5.1f} deg, "
              f"{result.samples:5d} angles, {time.perf_counter() - began:6.2f} s, "
              f"RSS {memory[-1]:7.1f} MB")
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"total {time.perf_counter() - start:.1f} s; peak RSS {peak_mb:.1f} MB; "
          f"call 5 {memory[4]:.1f} MB, call 20 {memory[19]:.1f} MB "
          f"({100 * (memory[19] / memory[4] - 1):+.1f}%)")


if __name__ == "__main__":
    main()
