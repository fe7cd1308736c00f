"""Best residual error known for each benchmark case, computed once by a long multi-start run.

``python -m benchmarks.best_known`` recomputes ``benchmarks/best_known.json``: for every
case, both solvers from ``STARTS`` starts (the case's start plus scrambled Halton
points) at tolerance ``TOLERANCE``; every run's design is re-evaluated with the
accurate adaptive quadrature and the lowest RE is kept, with the design that gives it.
The work-precision benchmark measures each method's error against these values.
"""

from __future__ import annotations

import json
import platform
import time
import warnings
from pathlib import Path
from typing import Any

import sso
from benchmarks.cases import CASES, accurate_residual_error
from sso._limits import DEFAULT_SEED

BEST_KNOWN_PATH = Path(__file__).with_name("best_known.json")
STARTS = 128
TOLERANCE = 1e-14
MAX_ITERATIONS = 3000


def load_best_known(path: Path = BEST_KNOWN_PATH) -> dict[str, Any]:
    """The stored best RE per case key (``name/model``) and how it was computed."""
    return json.loads(path.read_text())


def compute_best_known() -> dict[str, Any]:
    """Run the long multi-start search of every case (minutes)."""
    cases: dict[str, Any] = {}
    for case in CASES:
        started = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            result = sso.optimise(sso.ShaftSeries(case.beta_deg, case.phase_deg, case.model),
                                  starts=STARTS, solver_tol=TOLERANCE,
                                  max_iterations=MAX_ITERATIONS, **case.optimise_arguments())
        scored = [(accurate_residual_error(run.series.beta_deg, run.series.phase_deg,
                                           case.model), run) for run in result.runs]
        residual_error, run = min(scored, key=lambda pair: pair[0])
        cases[case.key] = {
            "residual_error": residual_error,
            "beta_deg": list(run.series.beta_deg),
            "phase_deg": list(run.series.phase_deg),
            "solver": run.solver,
            "start_index": run.start_index,
            "search_time_s": round(time.perf_counter() - started, 2),
        }
        print(f"{case.key}: RE = {residual_error:.6g} ({run.solver}, start {run.start_index})")
    return {
        "how": (f"sso.optimise with solvers ipopt and slsqp, starts = {STARTS} (the case's "
                f"start plus scrambled Halton points, seed {DEFAULT_SEED}), "
                f"tolerance = {TOLERANCE:g}, max_iterations = {MAX_ITERATIONS}; every run's "
                "design re-evaluated by the adaptive quadrature (rtol 1e-13, absolute floor "
                "at the round-off of RE); "
                "the lowest RE kept"),
        "computed_with": {"sso": sso.__version__, "python": platform.python_version()},
        "cases": cases,
    }


def main() -> None:
    """Recompute and store ``best_known.json``."""
    BEST_KNOWN_PATH.write_text(json.dumps(compute_best_known(), indent=2) + "\n")
    print(f"wrote {BEST_KNOWN_PATH}")


if __name__ == "__main__":
    main()
