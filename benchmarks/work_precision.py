"""Work-precision benchmark: wall time against error for sso and a plain scipy baseline.

``python -m benchmarks.work_precision [--quick] [--out DIR]`` writes into ``DIR``
(default ``results/benchmarks/``, ignored by git):

* ``work_precision.csv``: one row per case, model, method and tolerance with the
  median wall time of repeated solves (after a warm-up), objective evaluations,
  iterations and the error, i.e. the achieved RE (accurate adaptive quadrature)
  minus the best RE known for the case (``best_known.json``);
* ``work_precision.png``: log-log error against time, one panel per case;
* ``summary.md`` / ``summary.json``: ratios measured in this run, the batch of solves,
  the cold start of ``sso run``, and the performance targets met or missed.

Methods: ``sso-ipopt`` and ``sso-slsqp`` call :func:`sso.optimise` with one start
(the case's start) and one solver; its NLP is built by the warm-up and reused, as
in a batch. ``baseline`` is scipy SLSQP on a numpy objective sampled at 361 angles
with finite-difference gradients (:func:`benchmarks.cases.baseline_solve`).
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import warnings
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

import sso
from benchmarks.best_known import load_best_known
from benchmarks.cases import (
    CASES,
    BenchmarkCase,
    accurate_residual_error,
    baseline_solve,
)

METHODS = ("sso-ipopt", "sso-slsqp", "baseline")
FULL_TOLERANCES = (1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14)
QUICK_TOLERANCES = (1e-4, 1e-8, 1e-12)
FULL_REPEATS = 7
QUICK_REPEATS = 3
FULL_BATCH_SOLVES = 1000
QUICK_BATCH_SOLVES = 100
BATCH_TOLERANCE = 1e-10
BATCH_CASE = "paper-option3/exact"
COLD_START_REPEATS = 3
COLD_START_CASE_FILE = Path("cases/paper_option3_exact.toml")
# Performance targets (README.md, "Performance").
TARGET_ERROR = 1e-10
TARGET_SPEEDUP = 3.0
TARGET_NFEV_FRACTION = 0.25
DEFAULT_TOLERANCE = 1e-12  # sso.optimise's default; the nfev target is read there
# Errors this far below the best known RE are round-off (of the solvers' arithmetic
# and of the accurate quadrature), so a run that gets within it has reached any
# smaller error too.
ERROR_RESOLUTION_RTOL = 1e-12
PLOT_ERROR_FLOOR = 1e-32


@dataclass(frozen=True)
class Measurement:
    """One row of ``work_precision.csv``."""

    case: str
    model: str
    method: str
    tol: float
    time_s: float
    nfev: int
    nit: int
    error: float
    residual_error: float
    solver_time_s: float


def median_time(solve: Callable[[], Any], repeats: int) -> tuple[float, list[Any]]:
    """Median wall time (s) of ``repeats`` calls after one warm-up call, and their answers."""
    solve()
    times, answers = [], []
    for _ in range(repeats):
        started = time.perf_counter()
        answers.append(solve())
        times.append(time.perf_counter() - started)
    return statistics.median(times), answers


def sso_solver(case: BenchmarkCase, solver: str, tolerance: float,
               beta_deg: Any = None, phase_deg: Any = None) -> Callable[[], Any]:
    """A call of :func:`sso.optimise` with one start and one solver."""
    series = sso.ShaftSeries(case.beta_deg if beta_deg is None else beta_deg,
                             case.phase_deg if phase_deg is None else phase_deg, case.model)
    arguments = case.optimise_arguments()

    def solve() -> Any:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return sso.optimise(series, solvers=solver, starts=1, solver_tol=tolerance,
                                **arguments)

    return solve


def measure(case: BenchmarkCase, method: str, tolerance: float, repeats: int,
            best_residual_error: float) -> Measurement:
    """Time one method on one case at one tolerance and measure its error."""
    if method == "baseline":
        time_s, runs = median_time(lambda: baseline_solve(case, tolerance), repeats)
        solver_times = [run.time_s for run in runs]
        run = runs[-1]
        beta_deg, phase_deg, nfev, nit = run.beta_deg, run.phase_deg, run.nfev, run.nit
    else:
        time_s, results = median_time(sso_solver(case, method.removeprefix("sso-"), tolerance),
                                      repeats)
        solver_times = [result.best.time_s for result in results]
        best = results[-1].best
        beta_deg, phase_deg = best.series.beta_deg, best.series.phase_deg
        nfev, nit = best.nfev, best.nit
    residual_error = accurate_residual_error(beta_deg, phase_deg, case.model)
    return Measurement(case.name, case.model, method, tolerance, time_s, nfev, nit,
                       residual_error - best_residual_error, residual_error,
                       statistics.median(solver_times))


def speedup_at_baseline_error(rows: list[Measurement]) -> dict[str, Any]:
    """Ratios for one case: baseline time over each sso method's time at the baseline's best error.

    The baseline's best error is the lowest it reaches over the tolerance sweep (no
    lower than ``ERROR_RESOLUTION_RTOL`` times the best known RE), and its time
    there the fastest of its runs that reach it; each sso method's time is
    the fastest of its runs whose error is no larger. Two timings: the whole call
    (``sso.optimise``, with its input checks, quadrature choice and the evaluations
    of the start and the optimum, against ``scipy.optimize.minimize`` plus the
    porter's set-up) and the solver path alone (sso's solver runs with their
    second-order checks, against the baseline's ``minimize`` call).
    """
    baseline = [row for row in rows if row.method == "baseline"]
    resolution = ERROR_RESOLUTION_RTOL * min(row.residual_error - row.error for row in rows)
    baseline_error = max(min(row.error for row in baseline), resolution)
    reached = [row for row in baseline if row.error <= baseline_error]
    baseline_time = min(row.time_s for row in reached)
    baseline_solver_time = min(row.solver_time_s for row in reached)
    summary: dict[str, Any] = {"baseline_best_error": baseline_error,
                               "baseline_time_s": baseline_time,
                               "baseline_solver_time_s": baseline_solver_time, "methods": {}}
    for method in METHODS[:-1]:
        own = [row for row in rows if row.method == method]
        reaching = [row for row in own if row.error <= baseline_error]
        fastest = min(reaching, key=lambda row: row.time_s) if reaching else None
        fastest_solver = min(reaching, key=lambda row: row.solver_time_s) if reaching else None
        at_default = [row for row in own if row.tol == DEFAULT_TOLERANCE]
        summary["methods"][method] = {
            "best_error": min(row.error for row in own),
            "time_s_at_baseline_error": None if fastest is None else fastest.time_s,
            "tol_at_baseline_error": None if fastest is None else fastest.tol,
            "speedup": None if fastest is None else baseline_time / fastest.time_s,
            "solver_speedup": (None if fastest_solver is None
                               else baseline_solver_time / fastest_solver.solver_time_s),
            "nfev_at_default_tol": at_default[0].nfev if at_default else None,
        }
    return summary


def batch_of_solves(count: int, best_known: dict[str, Any]) -> dict[str, Any]:
    """``count`` solves of the paper's option-3 shape from space-filling starts, in one process.

    Every method solves the same designs at ``BATCH_TOLERANCE``; sso's NLP is built by a
    warm-up solve and reused. Returns total and per-solve time, and the share of solves
    within ``TARGET_ERROR`` of the best known RE.
    """
    from sso.solvers.starts import start_points

    case = next(case for case in CASES if case.key == BATCH_CASE)
    problem = case.problem()
    starts = start_points(problem.start_rad, problem.lower_rad, problem.upper_rad, count + 1)[1:]
    best = best_known["cases"][case.key]["residual_error"]
    outcome: dict[str, Any] = {"case": case.key, "solves": count, "tolerance": BATCH_TOLERANCE,
                               "methods": {}}
    for method in METHODS:
        calls = []
        for start in starts:
            if method == "baseline":
                calls.append(lambda start=start: baseline_solve(case, BATCH_TOLERANCE,
                                                                start_rad=start))
            else:
                beta_rad, phase_rad = problem.split(start, problem.parameters_rad)
                calls.append(sso_solver(case, method.removeprefix("sso-"), BATCH_TOLERANCE,
                                        np.degrees(beta_rad), np.degrees(phase_rad)))
        calls[0]()
        started = time.perf_counter()
        answers = [call() for call in calls]
        elapsed = time.perf_counter() - started
        designs_found = [(answer.beta_deg, answer.phase_deg) if method == "baseline"
                         else (answer.best.series.beta_deg, answer.best.series.phase_deg)
                         for answer in answers]
        errors = [accurate_residual_error(beta, phase, case.model) - best
                  for beta, phase in designs_found]
        outcome["methods"][method] = {
            "total_s": elapsed,
            "per_solve_s": elapsed / count,
            "share_within_target_error": float(np.mean(np.array(errors) <= TARGET_ERROR)),
        }
    baseline_total = outcome["methods"]["baseline"]["total_s"]
    for method in METHODS[:-1]:
        method_total = outcome["methods"][method]["total_s"]
        outcome["methods"][method]["speedup"] = baseline_total / method_total
    return outcome


def cold_start() -> dict[str, Any]:
    """Wall time of a fresh ``sso run`` on the paper's option-3 case, if the CLI exists.

    Compared with a fresh Python process that imports scipy and runs the baseline once
    on the same case (what the porter's script costs from a cold start).
    """
    executable = Path(sys.executable).with_name("sso")
    if not executable.exists():
        executable = Path(shutil.which("sso") or "")
    case_file = COLD_START_CASE_FILE.resolve()
    has_cli = executable.is_file() and _module_exists("sso.cli")
    if not (has_cli and case_file.exists()):
        return {"measured": False,
                "note": ("not measured: the `sso run` command or cases/paper_option3_exact.toml "
                         "does not exist in this checkout; rerun "
                         "this benchmark when they do")}
    baseline_script = ("from benchmarks.cases import CASES, baseline_solve; "
                       f"baseline_solve(next(c for c in CASES if c.key == {BATCH_CASE!r}), 1e-10)")
    timings: dict[str, list[float]] = {"sso run": [], "baseline": []}
    for _ in range(COLD_START_REPEATS):
        with tempfile.TemporaryDirectory() as scratch:
            timings["sso run"].append(_timed([str(executable), "run", str(case_file)], scratch))
        timings["baseline"].append(_timed([sys.executable, "-c", baseline_script], os.getcwd()))
    sso_s = statistics.median(timings["sso run"])
    baseline_s = statistics.median(timings["baseline"])
    return {"measured": True, "sso_run_s": sso_s, "baseline_script_s": baseline_s,
            "ratio_sso_over_baseline": sso_s / baseline_s, "repeats": COLD_START_REPEATS}


def _module_exists(name: str) -> bool:
    from importlib.util import find_spec

    return find_spec(name) is not None


def _timed(command: list[str], working_directory: str) -> float:
    started = time.perf_counter()
    subprocess.run(command, cwd=working_directory, check=True, capture_output=True)
    return time.perf_counter() - started


def targets(rows: list[Measurement], ratios: dict[str, Any]) -> dict[str, Any]:
    """The three performance targets, each case and method, met or missed."""
    paper_fmincon = {case.key: case.fmincon_nfev for case in CASES if case.fmincon_nfev}
    error_misses, speed_misses, nfev_misses = [], [], []
    for key, summary in ratios.items():
        for method, figures in summary["methods"].items():
            if figures["best_error"] > TARGET_ERROR:
                error_misses.append(f"{key} {method}: best error {figures['best_error']:.3g}")
            if figures["speedup"] is None or figures["speedup"] < TARGET_SPEEDUP:
                speed_misses.append(f"{key} {method}: speedup {_format(figures['speedup'])} "
                                    f"(solver path {_format(figures['solver_speedup'])})")
            fmincon = paper_fmincon.get(key)
            nfev = figures["nfev_at_default_tol"]
            if fmincon and (nfev is None or nfev > TARGET_NFEV_FRACTION * fmincon):
                nfev_misses.append(f"{key} {method}: nfev {nfev} > {fmincon}/4")
    return {
        "error_at_most_1e-10": {"met": not error_misses, "misses": error_misses},
        "speedup_at_least_3": {"met": not speed_misses, "misses": speed_misses},
        "nfev_at_most_quarter_of_fmincon": {"met": not nfev_misses, "misses": nfev_misses},
    }


def _format(value: Any, spec: str = ".3g") -> str:
    return "n/a" if value is None else format(value, spec)


def write_summary(out: Path, ratios: dict[str, Any], batch: dict[str, Any],
                  cold: dict[str, Any], verdict: dict[str, Any], settings: dict[str, Any]) -> None:
    """``summary.json`` and a Markdown table ``summary.md``."""
    (out / "summary.json").write_text(json.dumps(
        {"settings": settings, "cases": ratios, "batch": batch, "cold_start": cold,
         "targets": verdict}, indent=2) + "\n")
    lines = ["# Work-precision summary", "",
             f"Settings: {json.dumps(settings)}", "",
             "Speedup = baseline time / sso time, each at the baseline's best error "
             "(fastest run that reaches it). Whole call: `sso.optimise` (input checks, "
             "quadrature choice, solve, evaluations of start and optimum) against the "
             "baseline's set-up and `scipy.optimize.minimize`. Solver path: sso's solver "
             "runs with their second-order checks against the baseline's `minimize` call. "
             "Errors are RE - best known RE (benchmarks/best_known.json).", "",
             "| case | baseline best error | baseline time (ms) | method | best error "
             "| time at baseline error (ms) | speedup | solver-path speedup | nfev at tol 1e-12 |",
             "|---|---|---|---|---|---|---|---|---|"]
    for key, summary in ratios.items():
        for method, figures in summary["methods"].items():
            time_ms = (None if figures["time_s_at_baseline_error"] is None
                       else 1e3 * figures["time_s_at_baseline_error"])
            lines.append(
                f"| {key} | {summary['baseline_best_error']:.3g} "
                f"| {1e3 * summary['baseline_time_s']:.2f} | {method} "
                f"| {figures['best_error']:.3g} | {_format(time_ms, '.2f')} "
                f"| {_format(figures['speedup'], '.2f')} "
                f"| {_format(figures['solver_speedup'], '.2f')} "
                f"| {figures['nfev_at_default_tol']} |")
    lines += ["", f"## Batch: {batch['solves']} solves of {batch['case']} in one process "
              f"(tolerance {batch['tolerance']:g})", "",
              "| method | total (s) | per solve (ms) | within 1e-10 of best | speedup |",
              "|---|---|---|---|---|"]
    for method, figures in batch["methods"].items():
        lines.append(f"| {method} | {figures['total_s']:.2f} | {1e3 * figures['per_solve_s']:.2f} "
                     f"| {figures['share_within_target_error']:.1%} "
                     f"| {_format(figures.get('speedup'), '.2f')} |")
    lines += ["", "## Cold start of `sso run` on the paper's option-3 case", ""]
    if cold["measured"]:
        lines.append(f"`sso run`: {cold['sso_run_s']:.2f} s; a fresh Python running the "
                     f"baseline once: {cold['baseline_script_s']:.2f} s "
                     f"(median of {cold['repeats']}).")
    else:
        lines.append(cold["note"])
    lines += ["", "## Targets", ""]
    for name, target in verdict.items():
        lines.append(f"- {name}: {'met' if target['met'] else 'MISSED'}")
        lines.extend(f"  - {miss}" for miss in target["misses"])
    (out / "summary.md").write_text("\n".join(lines) + "\n")


def plot(out: Path, rows: list[Measurement]) -> None:
    """Log-log error against time, one panel per case."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    keys = list(dict.fromkeys((row.case, row.model) for row in rows))
    columns = 3
    rows = (len(keys) + columns - 1) // columns
    figure, axes = plt.subplots(rows, columns, figsize=(4.2 * columns, 3.2 * rows),
                                squeeze=False)
    for axis, (case, model) in zip(axes.flat, keys, strict=False):
        for method in METHODS:
            own = sorted((row for row in rows if (row.case, row.model, row.method)
                          == (case, model, method)), key=lambda row: row.tol, reverse=True)
            axis.loglog([row.time_s for row in own],
                        [max(row.error, PLOT_ERROR_FLOOR) for row in own], "o-", label=method)
        axis.set_title(f"{case} ({model})", fontsize=9)
        axis.set_xlabel("wall time (s)")
        axis.set_ylabel(f"RE - best RE (floor {PLOT_ERROR_FLOOR:g})")
    for axis in list(axes.flat)[len(keys):]:
        axis.set_visible(False)
    axes.flat[0].legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(out / "work_precision.png", dpi=110)
    plt.close(figure)


def run(out: Path, quick: bool) -> dict[str, Any]:
    """Run the whole benchmark and write its files into ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    tolerances = QUICK_TOLERANCES if quick else FULL_TOLERANCES
    repeats = QUICK_REPEATS if quick else FULL_REPEATS
    best_known = load_best_known()
    rows = [measure(case, method, tolerance, repeats,
                    best_known["cases"][case.key]["residual_error"])
            for case in CASES for method in METHODS for tolerance in tolerances]
    with (out / "work_precision.csv").open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(asdict(rows[0])))
        writer.writeheader()
        writer.writerows(asdict(row) for row in rows)
    ratios = {case.key: speedup_at_baseline_error(
        [row for row in rows if (row.case, row.model) == (case.name, case.model)])
        for case in CASES}
    batch = batch_of_solves(QUICK_BATCH_SOLVES if quick else FULL_BATCH_SOLVES, best_known)
    cold = cold_start()
    verdict = targets(rows, ratios)
    settings = {"quick": quick, "tolerances": list(tolerances), "repeats": repeats,
                "cpu_count": os.cpu_count(), "sso": sso.__version__}
    write_summary(out, ratios, batch, cold, verdict, settings)
    plot(out, rows)
    return {"cases": ratios, "batch": batch, "cold_start": cold, "targets": verdict}


def main(argv: list[str] | None = None) -> None:
    """Command line: ``python -m benchmarks.work_precision [--quick] [--out DIR]``."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="3 tolerances, 3 repeats, 100 batch solves (under a minute)")
    parser.add_argument("--out", type=Path, default=Path("results/benchmarks"),
                        help="output folder (default: results/benchmarks)")
    arguments = parser.parse_args(argv)
    started = time.perf_counter()
    run(arguments.out, arguments.quick)
    print((arguments.out / "summary.md").read_text())
    print(f"wrote {arguments.out}/ in {time.perf_counter() - started:.1f} s")


if __name__ == "__main__":
    main()
