"""Long numerical stress run: 30 joints, angles up to 89 deg, thousands of random designs.

``python -m benchmarks.stress [--out DIR]`` writes ``stress.json`` and ``stress.md`` into
``DIR`` (default ``results/benchmarks/``, ignored by git): one line per check with what
was measured and whether it held. The quick versions of these checks are in
``tests/test_stress.py``; this run goes further than a test suite should (minutes, not
seconds).
"""

from __future__ import annotations

import argparse
import json
import math
import time
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

import sso

RANDOM_DESIGNS = 2000
SPEEDS_RPM = (1e-3, 1e-1, 25.0, 1e3, 1e5)
SEED = 20251122


def all_finite(value: Any) -> bool:
    """True when every number in a ``to_dict()`` tree is finite."""
    if isinstance(value, dict):
        return all(all_finite(item) for item in value.values())
    if isinstance(value, (list, tuple)):
        return all(all_finite(item) for item in value)
    return not isinstance(value, float) or math.isfinite(value)


def optimise(series: sso.ShaftSeries, option: int, **options: Any) -> Any:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return sso.optimise(series, option, **options)


def thirty_joints(option: int) -> dict[str, Any]:
    """Thirty joints in [5, 20] deg, both solvers, two starts."""
    rng = np.random.default_rng(SEED + option)
    series = sso.ShaftSeries(rng.uniform(5.0, 20.0, 30), rng.uniform(0.0, 180.0, 29))
    started = time.perf_counter()
    result = optimise(series, option, beta_bounds_deg=(5.0, 20.0), starts=2)
    return {
        "time_s": time.perf_counter() - started,
        "samples": result.samples,
        "initial_re": result.initial.residual_error,
        "best_re": result.best.fun,
        "optimum_quadrature_converged": result.optimum.quadrature_converged,
        "solvers": {name: {"success": solution.success, "fun": solution.fun,
                           "nfev": solution.nfev, "kkt": solution.kkt,
                           "message": solution.message}
                    for name, solution in result.solutions.items()},
        "crosscheck": result.crosscheck.message,
        "held": (all_finite(result.to_dict()) and result.best.success
                 and result.best.fun < result.initial.residual_error),
    }


def random_designs() -> dict[str, Any]:
    """Random chains of 1..30 joints with angles up to 89 deg: invariants and no NaN."""
    rng = np.random.default_rng(SEED)
    theta_deg = np.linspace(0.0, 180.0, 181)
    worst = {"mean_ratio": 0.0, "bound": 0.0}
    failures = []
    refused = 0
    for index in range(RANDOM_DESIGNS):
        joints = int(rng.integers(1, 31))
        beta = rng.uniform(0.0, 89.0, joints) * (rng.random(joints) < 0.8)
        phase = rng.uniform(-360.0, 360.0, joints - 1)
        try:
            series = sso.ShaftSeries(beta, phase)
        except ValueError as error:  # beyond what float64 resolves (docs/model.md)
            if "float64 cannot resolve RE" not in str(error):
                failures.append({"beta_deg": beta.tolist(), "phase_deg": phase.tolist()})
            refused += 1
            continue
        ratio = series.speed_ratio(theta_deg)
        product = float(np.prod(np.cos(np.radians(beta))))
        bound_excess = max(float(np.max(product / ratio - 1.0)),
                           float(np.max(ratio * product - 1.0)), 0.0)
        worst["bound"] = max(worst["bound"], bound_excess)
        if index % 20 == 0:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", sso.QuadratureWarning)
                evaluation = series.evaluate(25.0)
            if evaluation.quadrature_converged:
                worst["mean_ratio"] = max(worst["mean_ratio"],
                                          abs(evaluation.mean_speed_ratio - 1.0))
            if not all_finite(evaluation.to_dict()):
                failures.append({"beta_deg": beta.tolist(), "phase_deg": phase.tolist()})
        if not np.all(np.isfinite(ratio)) or bound_excess > 1e-9:
            failures.append({"beta_deg": beta.tolist(), "phase_deg": phase.tolist()})
    return {"designs": RANDOM_DESIGNS, "refused_beyond_float64": refused,
            "worst_mean_ratio_error": worst["mean_ratio"],
            "worst_relative_bound_excess": worst["bound"], "failures": failures[:5],
            "held": not failures and worst["mean_ratio"] <= 1e-9}


def input_speeds() -> dict[str, Any]:
    """The six-joint design problem at input speeds 1e-3 .. 1e5 rpm: one optimum."""
    series = sso.ShaftSeries([30.0, 10.0, 25.0, 15.0, 20.0, 12.0], [20.0, 45.0, 60.0, 120.0, 150.0])
    designs = {speed: optimise(series, 3, beta_bounds_deg=(5.0, 35.0), starts=2,
                               input_speed_rpm=speed).best.x for speed in SPEEDS_RPM}
    spread = max(float(np.max(np.abs(np.subtract(design, designs[25.0]))))
                 for design in designs.values())
    return {"speeds_rpm": list(SPEEDS_RPM), "largest_design_difference_deg": spread,
            "held": spread <= 1e-9}


def near_ninety_degrees() -> dict[str, Any]:
    """One joint with its angle in [80, 89] deg: the optimum is 80 deg, RE in closed form."""
    cosine = math.cos(math.radians(80.0))
    expected = (1.0 - cosine) ** 2 / (2.0 * cosine)
    result = optimise(sso.ShaftSeries([89.0]), 2, beta_bounds_deg=(80.0, 89.0), starts=2)
    return {"samples": result.samples, "best_beta_deg": result.best.series.beta_deg[0],
            "best_re": result.best.fun, "closed_form_re": expected,
            "crosscheck": result.crosscheck.message,
            "held": (abs(result.best.fun - expected) <= 1e-9 * expected
                     and all_finite(result.to_dict()))}


CHECKS: dict[str, Callable[[], dict[str, Any]]] = {
    "30 joints, option 3": lambda: thirty_joints(3),
    "30 joints, option 1": lambda: thirty_joints(1),
    f"{RANDOM_DESIGNS} random chains of 1..30 joints up to 89 deg": random_designs,
    "input speed 1e-3 .. 1e5 rpm": input_speeds,
    "one joint in [80, 89] deg": near_ninety_degrees,
}


def main(argv: list[str] | None = None) -> None:
    """Command line: ``python -m benchmarks.stress [--out DIR]``."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("results/benchmarks"),
                        help="output folder (default: results/benchmarks)")
    arguments = parser.parse_args(argv)
    arguments.out.mkdir(parents=True, exist_ok=True)
    report = {}
    for name, check in CHECKS.items():
        started = time.perf_counter()
        try:
            outcome = check()
        except Exception as error:  # a crash is a finding of this run, not its end
            outcome = {"held": False, "crash": f"{type(error).__name__}: {error}"}
        outcome["wall_s"] = time.perf_counter() - started
        report[name] = outcome
        print(f"{'held' if outcome['held'] else 'FAILED'}: {name} ({outcome['wall_s']:.1f} s)")
    (arguments.out / "stress.json").write_text(json.dumps(report, indent=2, default=str) + "\n")
    lines = ["# Stress run", ""] + [
        f"- {'held' if outcome['held'] else 'FAILED'}: {name} "
        f"({outcome['wall_s']:.1f} s): "
        + ", ".join(f"{key} = {value}" for key, value in outcome.items()
                    if key not in ("held", "wall_s", "solvers", "failures"))
        for name, outcome in report.items()]
    (arguments.out / "stress.md").write_text("\n".join(lines) + "\n")
    print(f"wrote {arguments.out}/stress.json and stress.md")


if __name__ == "__main__":
    main()
