"""Throughput of ``optimise_batch`` and single-solve latency, against the skilled baseline.

Four measurements in one run, every figure a ratio against
:mod:`benchmarks.skilled_baseline` (closed form, complex-step gradient, SLSQP, one
start) timed in the same process:

1. **Batch.** ``optimise_batch`` on ``--starts`` (default 2,000) random three-joint
   option-3 starts (beta in [10, 40] deg, phase in [0, 180] deg): designs per
   second (best of ``--repeats``), against the baseline's solves per second on the
   same starts; the fraction reaching RE <= 1e-10, and that fraction among the
   starts where the baseline reaches it; and the time per design against the
   arithmetic it must do (:func:`arithmetic_figures`).
2. **Shapes.** ``--shape-starts`` (default 300) random starts of 3 to 6 joints for
   each option (beta in [5, 35] deg; option 1 keeps the start's angles): designs
   per second against the baseline's solves per second on the same starts, and how
   many starts end with a higher or lower RE than the baseline's (by more than
   1e-12).
3. **One design.** The paper's three options (``cases/paper_option*_exact.toml``):
   the baseline, ``sso.optimise`` with SLSQP and one start, with IPOPT and one
   start, the default call (both solvers, its default starts) and
   ``optimise_batch`` with one row: median wall time and CPU time after a warm-up
   (NLP built), the methods taking passes of a few calls in turn in each round
   (interleaved), and RE reached. The issue's targets: the fastest sso solver >= 10x faster than the
   baseline, the default call <= 5x the baseline.

Usage::

    python -m benchmarks.batch_throughput [--starts 2000] [--repeats 3] [--out DIR]

Writes ``batch_throughput.json`` and ``batch_throughput.md`` into ``DIR`` (default
``results/benchmarks/``, ignored by git) and prints the summary.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

import sso
from benchmarks.skilled_baseline import solve as baseline_solve
from sso._files import write_text_atomic
from sso._shafts.batch import optimise_batch

REACHED = 1e-10
BETA_BOUNDS_DEG = (10.0, 40.0)
PHASE_BOUNDS_DEG = (0.0, 180.0)
SEED = 20261123
TARGET_DESIGNS_PER_S = 100_000.0
TARGET_BATCH_RATIO = 20.0
TARGET_FASTEST_RATIO = 10.0
# Element-wise numpy operations timed for the arithmetic floor: as many elements as the
# batch has designs, and a longer array that still stays in cache (the per-call
# overhead spread thin: the arithmetic alone).
FLOOR_REPEATS = 200
LONG_ELEMENTS = 65_536
TARGET_DEFAULT_RATIO = 5.0
# The paper's cases (cases/paper_option*_exact.toml): start, beta bounds.
PAPER_CASES = {
    1: ((15.0, 20.0, 9.0), (30.0, 40.0), (0.0, 40.0)),
    2: ((10.0, 15.0, 30.0), (90.0, 90.0), (7.0, 25.0)),
    3: ((30.0, 40.0, 50.0), (90.0, 90.0), (10.0, 40.0)),
}
LATENCY_REPEATS = 21
LATENCY_CALLS_PER_PASS = 5
"""Calls of one method in a row in each round of the one-design timing."""
WARM_UP_CALLS = 3
"""Calls of each method before it is timed (the issue's limit: at most 3)."""


def batch_figures(count: int, repeats: int) -> dict[str, Any]:
    """Designs per second of ``optimise_batch`` and of the baseline on the same starts.

    ``optimise_batch`` is timed best of ``repeats``, after a first call of one row that
    builds the shape's functions (timed apart). The starts reaching RE <= 1e-10 are
    compared with the baseline's and with the single solve's (``sso.optimise`` with
    ``"lm"`` and one start).
    """
    rng = np.random.default_rng(SEED)
    beta_deg = rng.uniform(*BETA_BOUNDS_DEG, (count, 3))
    phase_deg = rng.uniform(*PHASE_BOUNDS_DEG, (count, 2))
    arguments: dict[str, Any] = {"option": 3, "beta_bounds_deg": BETA_BOUNDS_DEG,
                                 "phase_bounds_deg": PHASE_BOUNDS_DEG}

    def timed() -> tuple[list[float], Any]:
        times = []
        for _ in range(repeats):
            started = time.perf_counter()
            result = optimise_batch(beta_deg, phase_deg, **arguments)
            times.append(time.perf_counter() - started)
        return times, result

    started = time.perf_counter()
    optimise_batch(beta_deg[:1], phase_deg[:1], **arguments)
    first_call_s = time.perf_counter() - started
    times, result = timed()
    started = time.perf_counter()
    baseline = [baseline_solve(beta_deg[row], phase_deg[row], 3, BETA_BOUNDS_DEG,
                               PHASE_BOUNDS_DEG) for row in range(count)]
    baseline_time = time.perf_counter() - started
    single_fun = np.array([sso.optimise(sso.ShaftSeries(beta_deg[row], phase_deg[row]), 3,
                                        solvers=("lm",), starts=1,
                                        beta_bounds_deg=BETA_BOUNDS_DEG,
                                        phase_bounds_deg=PHASE_BOUNDS_DEG).fun
                           for row in range(count)])
    baseline_fun = np.array([solve.fun for solve in baseline])
    baseline_reached = baseline_fun <= REACHED
    single_reached = single_fun <= REACHED
    batch_reached = result.fun <= REACHED
    designs_per_s = count / min(times)
    baseline_per_s = count / baseline_time
    arithmetic = arithmetic_figures(result, min(times), count)
    return {
        **arithmetic,
        "starts": count,
        "first_call_s": first_call_s,
        "batch_time_s": min(times),
        "batch_times_s": times,
        "designs_per_s": designs_per_s,
        "baseline_time_s": baseline_time,
        "baseline_solves_per_s": baseline_per_s,
        "ratio": designs_per_s / baseline_per_s,
        "batch_fraction_reached": float(np.mean(batch_reached)),
        "baseline_fraction_reached": float(np.mean(baseline_reached)),
        "batch_reached_where_baseline_did": float(np.mean(batch_reached[baseline_reached])),
        "single_fraction_reached": float(np.mean(single_reached)),
        "batch_reached_where_single_did": float(np.mean(batch_reached[single_reached])),
        "batch_success": float(np.mean(result.success)),
        "batch_nit_median": float(np.median(result.nit)),
        "batch_nit_max": int(np.max(result.nit)),
        "baseline_nit_median": float(np.median([solve.nit for solve in baseline])),
        "lower_re_than_baseline": int(np.sum(result.fun < baseline_fun - 1e-12)),
        "higher_re_than_baseline": int(np.sum(result.fun > baseline_fun + 1e-12)),
    }


def arithmetic_figures(result: Any, batch_time_s: float, count: int) -> dict[str, Any]:
    """The batch's time per design against the arithmetic it must do.

    The arithmetic of one iteration is the operations of the rules' iteration for the
    shape (:func:`iteration_operations`: one residual-and-Jacobian
    evaluation and the step, every branch computed, as the batch computes them); a
    design does it once per evaluation (``nfev``, the start's included). The floor is
    that many element-wise numpy operations, timed in this run on arrays of ``count``
    elements (what array-at-a-time code can do at this batch size) and on a longer
    array that stays in cache (the arithmetic alone, numpy's call overhead spread thin).
    """
    from sso._shafts.options import build_problem
    from sso._shafts.problem import compiled_nlp
    problem = build_problem([20.0] * 3, [90.0] * 2, "exact", 3, BETA_BOUNDS_DEG, PHASE_BOUNDS_DEG)
    operations = iteration_operations(compiled_nlp(problem, 0))
    per_design = operations * float(np.mean(result.nfev))
    short = _element_time_s(count)
    long = _element_time_s(LONG_ELEMENTS)
    time_per_design = batch_time_s / count
    return {
        "operations_per_iteration": operations,
        "evaluations_per_design": float(np.mean(result.nfev)),
        "operations_per_design": per_design,
        "time_per_design_s": time_per_design,
        "element_op_s_at_batch_size": short,
        "element_op_s_long_array": long,
        "over_array_floor": time_per_design / (per_design * short),
        "over_long_array_floor": time_per_design / (per_design * long),
    }


def iteration_operations(nlp: Any) -> int:
    """Arithmetic operations of one Gauss-Newton iteration of the rules for the NLP's shape
    (one residual-and-Jacobian evaluation and the step, every branch computed): the
    instructions of its SX function less those that only read inputs or constants and
    write outputs."""
    import casadi

    from sso._solvers.lm_kernel import iteration_functions

    _, iteration = iteration_functions(nlp.symbols["x"], nlp.symbols["p"], nlp.residuals,
                                       "gauss_newton")
    bookkeeping = {casadi.OP_INPUT, casadi.OP_OUTPUT, casadi.OP_CONST}
    return sum(iteration.instruction_id(index) not in bookkeeping
               for index in range(iteration.n_instructions()))


def _element_time_s(elements: int) -> float:
    """Seconds per element of one element-wise numpy operation (a multiply into a buffer)
    on arrays of ``elements`` entries: the best of :data:`FLOOR_REPEATS` timings."""
    first, second, out = np.random.default_rng(SEED).uniform(1.0, 2.0, (3, elements))
    best = np.inf
    repeats = max(1, FLOOR_REPEATS * 2000 // elements)
    for _ in range(5):
        started = time.perf_counter()
        for _ in range(repeats):
            np.multiply(first, second, out=out)
        best = min(best, (time.perf_counter() - started) / repeats)
    return best / elements


def shape_figures(count: int) -> list[dict[str, Any]]:
    """Batch against baseline for 3 to 6 joints and each option; the batch timed warm (a
    first call of one row builds the shape's functions)."""
    rows = []
    bounds = (5.0, 35.0)
    for n_joints in range(3, 7):
        for option in (1, 2, 3):
            rng = np.random.default_rng(SEED + 10 * n_joints + option)
            beta_deg = rng.uniform(*bounds, (count, n_joints))
            phase_deg = rng.uniform(*PHASE_BOUNDS_DEG, (count, n_joints - 1))
            optimise_batch(beta_deg[:1], phase_deg[:1], option=option, beta_bounds_deg=bounds)
            started = time.perf_counter()
            result = optimise_batch(beta_deg, phase_deg, option=option, beta_bounds_deg=bounds)
            batch_time = time.perf_counter() - started
            started = time.perf_counter()
            baseline = np.array([baseline_solve(beta_deg[row], phase_deg[row], option, bounds,
                                                PHASE_BOUNDS_DEG).fun for row in range(count)])
            baseline_time = time.perf_counter() - started
            rows.append({
                "joints": n_joints, "option": option, "starts": count,
                "designs_per_s": count / batch_time,
                "baseline_solves_per_s": count / baseline_time,
                "ratio": baseline_time / batch_time,
                "success": float(np.mean(result.success)),
                "nit_max": int(np.max(result.nit)),
                "higher_re_than_baseline": int(np.sum(result.fun > baseline + 1e-12)),
                "lower_re_than_baseline": int(np.sum(result.fun < baseline - 1e-12)),
            })
    return rows


def _interleaved_medians(methods: dict[str, Callable[[], float]]
                         ) -> dict[str, tuple[float, float, float]]:
    """Median wall time (s) and median CPU time of this process (s) of one call of each
    method, and the RE it returns: after a warm-up of :data:`WARM_UP_CALLS` calls each,
    :data:`LATENCY_REPEATS`
    rounds in which every method in turn makes a pass of :data:`LATENCY_CALLS_PER_PASS`
    calls (a method's time is its pass's over the calls), so a burst of the machine's
    other work falls on every method alike and each is timed warm, as in a run of many
    designs. On a machine shared with other work the CPU time is the work the call did;
    the wall time adds the time it waited for a core (more for a longer call: it
    outlasts more scheduler slices)."""
    for _ in range(WARM_UP_CALLS):
        funs = {name: call() for name, call in methods.items()}
    walls: dict[str, list[float]] = {name: [] for name in methods}
    cpus: dict[str, list[float]] = {name: [] for name in methods}
    for _ in range(LATENCY_REPEATS):
        for name, call in methods.items():
            started, started_cpu = time.perf_counter(), time.process_time()
            for _ in range(LATENCY_CALLS_PER_PASS):
                funs[name] = call()
            cpus[name].append((time.process_time() - started_cpu) / LATENCY_CALLS_PER_PASS)
            walls[name].append((time.perf_counter() - started) / LATENCY_CALLS_PER_PASS)
    return {name: (statistics.median(walls[name]), statistics.median(cpus[name]), funs[name])
            for name in methods}


def _methods(option: int, beta_deg: tuple[float, ...], phase_deg: tuple[float, ...],
             beta_bounds: tuple[float, float]) -> dict[str, Callable[[], float]]:
    """One solve of the case by each method, returning the RE reached."""
    series = sso.ShaftSeries(beta_deg, phase_deg)
    arguments: dict[str, Any] = {"beta_bounds_deg": beta_bounds,
                                 "phase_bounds_deg": PHASE_BOUNDS_DEG}
    return {
        "skilled_baseline": lambda: baseline_solve(
            np.array(beta_deg), np.array(phase_deg), option, beta_bounds, PHASE_BOUNDS_DEG).fun,
        "sso_slsqp_1_start": lambda: sso.optimise(
            series, option, solvers=("slsqp",), starts=1, **arguments).fun,
        "sso_ipopt_1_start": lambda: sso.optimise(
            series, option, solvers=("ipopt",), starts=1, **arguments).fun,
        "sso_lm_1_start": lambda: sso.optimise(
            series, option, solvers=("lm",), starts=1, **arguments).fun,
        "sso_default": lambda: sso.optimise(series, option, **arguments).fun,
        "optimise_batch_1_row": lambda: float(optimise_batch(
            [beta_deg], [phase_deg], option=option, **arguments).fun[0]),
    }


def latency_figures() -> dict[str, Any]:
    """One-design wall time of every method on the paper's three options."""
    figures: dict[str, Any] = {}
    for option, (beta_deg, phase_deg, beta_bounds) in PAPER_CASES.items():
        methods = _methods(option, beta_deg, phase_deg, beta_bounds)
        case: dict[str, Any] = {}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            for name, (seconds, cpu_seconds, fun) in _interleaved_medians(methods).items():
                case[name] = {"time_s": seconds, "cpu_time_s": cpu_seconds, "fun": fun}
        base = case["skilled_baseline"]["time_s"]
        base_cpu = case["skilled_baseline"]["cpu_time_s"]
        for name in methods:
            case[name]["baseline_over_method"] = base / case[name]["time_s"]
            case[name]["baseline_over_method_cpu"] = base_cpu / case[name]["cpu_time_s"]
        fastest = max(("sso_slsqp_1_start", "sso_ipopt_1_start", "sso_lm_1_start"),
                      key=lambda name: case[name]["baseline_over_method"])
        case["fastest_sso_solver"] = fastest
        case["fastest_target_met"] = case[fastest]["baseline_over_method"] >= TARGET_FASTEST_RATIO
        case["default_over_baseline"] = case["sso_default"]["time_s"] / base
        case["default_over_baseline_cpu"] = case["sso_default"]["cpu_time_s"] / base_cpu
        case["default_target_met"] = case["default_over_baseline"] <= TARGET_DEFAULT_RATIO
        figures[f"option{option}"] = case
    return figures


def summary(batch: dict[str, Any], shapes: list[dict[str, Any]], latency: dict[str, Any]) -> str:
    """The measured figures and the targets met or missed, as Markdown."""
    met = {True: "met", False: "missed"}
    lines = [
        "# Batch throughput and one-design latency (ratios measured in one run)",
        "",
        (f"## optimise_batch: {batch['starts']} random 3-joint option-3 starts "
        f"(beta {BETA_BOUNDS_DEG}, phase {PHASE_BOUNDS_DEG} deg)"),
        "",
        (f"- optimise_batch: {batch['designs_per_s']:,.0f} designs/s "
        f"({batch['batch_time_s'] * 1e3:.1f} ms, best of {len(batch['batch_times_s'])}); "
        f"target {TARGET_DESIGNS_PER_S:,.0f}: "
        f"{met[batch['designs_per_s'] >= TARGET_DESIGNS_PER_S]}"),
        (f"- the first call of one row (the shape's functions built): "
         f"{batch['first_call_s']:.2f} s"),
        (f"- skilled baseline: {batch['baseline_solves_per_s']:,.0f} solves/s; ratio "
        f"{batch['ratio']:.1f}x, target {TARGET_BATCH_RATIO:.0f}x: "
        f"{met[batch['ratio'] >= TARGET_BATCH_RATIO]}"),
        (f"- RE <= {REACHED:g}: batch {batch['batch_fraction_reached']:.2%}, baseline "
        f"{batch['baseline_fraction_reached']:.2%}, single solve (lm, one start) "
        f"{batch['single_fraction_reached']:.2%}; batch where the baseline reached it "
        f"{batch['batch_reached_where_baseline_did']:.2%}, where the single solve did "
        f"{batch['batch_reached_where_single_did']:.2%}"),
        (f"- iterations: batch median {batch['batch_nit_median']:g} "
         f"(max {batch['batch_nit_max']}), "
        f"baseline median {batch['baseline_nit_median']:g}"),
        (f"- arithmetic: {batch['operations_per_iteration']} operations per iteration x "
         f"{batch['evaluations_per_design']:.2f} evaluations = "
         f"{batch['operations_per_design']:,.0f} per design; "
         f"{batch['time_per_design_s'] * 1e9:,.0f} ns per design is "
         f"{batch['over_array_floor']:.1f}x that many element-wise numpy operations on "
         f"{batch['starts']:,}-element arrays "
         f"({batch['element_op_s_at_batch_size'] * 1e9:.2f} ns each) and "
         f"{batch['over_long_array_floor']:.1f}x on {LONG_ELEMENTS:,}-element arrays "
         f"({batch['element_op_s_long_array'] * 1e9:.2f} ns each)"),
        "",
        "## optimise_batch by shape (beta in [5, 35] deg, phase in [0, 180] deg)",
        "",
        ("| joints | option | designs/s | baseline solves/s | ratio | success | max nit "
         "| RE higher / lower than baseline |"),
        "|---|---|---|---|---|---|---|---|",
        *[f"| {row['joints']} | {row['option']} | {row['designs_per_s']:,.0f} | "
          f"{row['baseline_solves_per_s']:,.0f} | {row['ratio']:.1f} | {row['success']:.0%} | "
          f"{row['nit_max']} | {row['higher_re_than_baseline']} / {row['lower_re_than_baseline']} |"
          for row in shapes],
        "",
        ("## One design, the paper's options (median of "
         f"{LATENCY_REPEATS} interleaved rounds of {LATENCY_CALLS_PER_PASS} calls per method "
         "after a warm-up; baseline time / method time)"),
        "",
        "| option | method | time (ms) | CPU time (ms) | RE | baseline / method "
        "| baseline / method, CPU |",
        "|---|---|---|---|---|---|---|",
    ]
    for option, case in latency.items():
        for name, figures in case.items():
            if isinstance(figures, dict):
                lines.append(f"| {option} | {name} | {figures['time_s'] * 1e3:.3f} | "
                             f"{figures['cpu_time_s'] * 1e3:.3f} | {figures['fun']:.3e} | "
                             f"{figures['baseline_over_method']:.2f} | "
                             f"{figures['baseline_over_method_cpu']:.2f} |")
    lines.append("")
    for option, case in latency.items():
        lines.append(
            f"- {option}: fastest sso solver ({case['fastest_sso_solver']}) "
            f"{case[case['fastest_sso_solver']]['baseline_over_method']:.2f}x the baseline's "
            f"speed, target >= {TARGET_FASTEST_RATIO:g}x: {met[case['fastest_target_met']]}; "
            f"default call {case['default_over_baseline']:.1f}x the baseline's time "
            f"({case['default_over_baseline_cpu']:.1f}x its CPU time), target "
            f"<= {TARGET_DEFAULT_RATIO:g}x: {met[case['default_target_met']]}")
    return "\n".join(lines) + "\n"


SCREENING_STARTS = (8, 32, 64, 128, 512)
SCREENING_CASES = {
    # Option 1 cannot cancel: every start is screened (the batch's case).
    "option 1 (paper), RE > 0": ((15.0, 20.0, 9.0), (30.0, 40.0), 1, (0.0, 40.0)),
    # Option 3 cancels from the user's start: the screening stops there.
    "option 3 (paper), RE -> 0": ((30.0, 40.0, 40.0), (90.0, 90.0), 3, (10.0, 40.0)),
}


def screening_figures(repeats: int = 3) -> list[dict[str, Any]]:
    """Multi-start screening with and without the batch, at several start counts.

    ``sso.optimise(..., solvers=("lm",), starts=k)`` as shipped (the user's start
    alone, then the rest in one batch when it stops above zero and at least
    ``BATCH_SCREEN_STARTS`` remain) against the same call with the batch switched
    off (every start one by one): best wall time of ``repeats``, the ratio, and
    the RE each reaches.
    """
    from sso._solvers import multistart

    shipped_threshold = multistart.BATCH_SCREEN_STARTS
    rows = []
    for name, (beta_deg, phase_deg, option, beta_bounds) in SCREENING_CASES.items():
        series = sso.ShaftSeries(beta_deg, phase_deg)
        for starts in SCREENING_STARTS:
            figures: dict[str, Any] = {"case": name, "starts": starts}
            for label, threshold in (("one_by_one", 10**9), ("shipped", shipped_threshold)):
                multistart.BATCH_SCREEN_STARTS = threshold
                try:
                    figures[f"{label}_time_s"], figures[f"{label}_fun"] = _screening_time(
                        series, option, beta_bounds, starts, repeats)
                finally:
                    multistart.BATCH_SCREEN_STARTS = shipped_threshold
            figures["ratio"] = figures["one_by_one_time_s"] / figures["shipped_time_s"]
            rows.append(figures)
    return rows


def _screening_time(series: sso.ShaftSeries, option: int, beta_bounds: tuple[float, float],
                    starts: int, repeats: int) -> tuple[float, float]:
    """Best wall time (s) of ``repeats`` lm-only multi-start calls, and the RE reached."""
    def call() -> Any:
        return sso.optimise(series, option, solvers=("lm",), starts=starts,
                            beta_bounds_deg=beta_bounds, phase_bounds_deg=PHASE_BOUNDS_DEG)

    fun = call().fun
    times = []
    for _ in range(repeats):
        started = time.perf_counter()
        call()
        times.append(time.perf_counter() - started)
    return min(times), fun


def screening_summary(rows: list[dict[str, Any]]) -> str:
    """The screening table as Markdown."""
    lines = ["## Screening many starts (lm alone; one by one against the shipped rule)", "",
             "| case | starts | one by one (ms) | shipped (ms) | ratio | RE one by one | "
             "RE shipped |", "|---|---|---|---|---|---|---|"]
    lines += [f"| {row['case']} | {row['starts']} | {row['one_by_one_time_s'] * 1e3:.2f} | "
              f"{row['shipped_time_s'] * 1e3:.2f} | {row['ratio']:.2f} | "
              f"{row['one_by_one_fun']:.4g} | {row['shipped_fun']:.4g} |" for row in rows]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> None:
    """Run the measurements, print the summary and write the results."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--starts", type=int, default=2000, help="random starts (default 2000)")
    parser.add_argument("--repeats", type=int, default=3, help="batch repeats (default 3)")
    parser.add_argument("--shape-starts", type=int, default=300,
                        help="starts per shape (default 300)")
    parser.add_argument("--out", type=Path, default=Path("results/benchmarks"),
                        help="output folder (default: results/benchmarks)")
    arguments = parser.parse_args(argv)
    batch = batch_figures(arguments.starts, arguments.repeats)
    shapes = shape_figures(arguments.shape_starts)
    latency = latency_figures()
    screening = screening_figures()
    text = summary(batch, shapes, latency) + "\n" + screening_summary(screening)
    print(text)
    arguments.out.mkdir(parents=True, exist_ok=True)
    write_text_atomic(arguments.out / "batch_throughput.json",
                      json.dumps({"batch": batch, "shapes": shapes, "latency": latency,
                                  "screening": screening}, indent=2) + "\n")
    write_text_atomic(arguments.out / "batch_throughput.md", text)


if __name__ == "__main__":
    main()
