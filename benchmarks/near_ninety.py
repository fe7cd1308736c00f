"""Random chains near 90 deg: every residual error is right or flagged unconverged.

``python -m benchmarks.near_ninety [--chains N]`` draws chains of 2 to 8 joints
whose largest operating angle lies between 89 deg and 89.99 deg (random phases,
both models), evaluates each, and compares every converged RE with the 60-digit
mpmath reference of ``tests/shafts/test_near_ninety.py``. The target:
no RE off by more than 1e-6 relative while ``quadrature_converged`` is True, and a
``QuadratureWarning`` for every unconverged one. Chains too close to 90 deg for float64
to resolve RE are refused (docs/model.md, "Numerical limits") and counted as such.
Prints the counts.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

import sso

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "shafts"))
from test_near_ninety import reference_residual_error  # the tests' reference, shared


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--chains", type=int, default=200)
    parser.add_argument("--seed", type=int, default=11)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    counts = {"converged and right": 0, "converged and WRONG": 0, "flagged": 0,
              "unflagged unconverged": 0, "refused": 0}
    worst = 0.0
    started = time.perf_counter()
    for index in range(args.chains):
        model = ("exact", "paper")[index % 2]
        joints = int(rng.integers(2, 9))
        top = float(rng.uniform(89.0, 89.99))
        beta = list(rng.uniform(0.0, top, joints))
        beta[int(rng.integers(joints))] = top
        phase = list(rng.uniform(0.0, 180.0, joints - 1))
        try:
            series = sso.ShaftSeries(beta, phase, model)
        except ValueError as error:
            if "float64 cannot resolve RE" not in str(error):
                raise
            counts["refused"] += 1
            continue
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = series.evaluate()
        warned = any(issubclass(item.category, sso.QuadratureWarning) for item in caught)
        if result.quadrature_converged:
            reference = reference_residual_error(beta, phase, model)
            error = abs(result.residual_error - reference) / reference
            worst = max(worst, error)
            counts["converged and right" if error <= 1e-6 else "converged and WRONG"] += 1
        else:
            counts["flagged" if warned else "unflagged unconverged"] += 1
    print(f"{args.chains} chains, largest angle 89-89.99 deg, 2-8 joints: {counts}; "
          f"worst relative error of a converged RE {worst:.2e}; "
          f"{time.perf_counter() - started:.0f} s")


if __name__ == "__main__":
    main()
