"""Where the IPOPT solve of the paper's option-3 default call spends its CPU time.

``python -m benchmarks.ipopt_share [--rounds R] [--solves N]`` builds the paper's
option-3 case (exact model, start 30/40/50 deg and 90/90 deg, beta within 10..40 deg)
as :func:`sso.optimise` builds it, and runs the IPOPT solve of its default call (the
same ``nlpsol``, options, start and bounds: :func:`sso._solvers.ipopt.solve`) in ``R``
rounds of ``N`` solves, each round followed by ``N`` solves of the skilled baseline
(:mod:`benchmarks.skilled_baseline`). It prints, as medians over the rounds:

* IPOPT's iterations and CasADi's calls of the NLP's functions per solve (objective,
  gradient, Hessian of the Lagrangian);
* the share of IPOPT's CPU time (this process's, ``time.process_time``) that CasADi's own
  timers give to evaluating those functions (``t_proc_nlp_*`` of the solver's
  statistics): what compiling them to machine code could save at most;
* IPOPT's CPU time per solve over the skilled baseline's.

The rest of IPOPT's time is its own: the factorisations of its step system (MUMPS),
its line search and its bookkeeping.
"""

from __future__ import annotations

import argparse
import statistics
import time
import warnings
from typing import Any

import numpy as np

from benchmarks.skilled_baseline import solve as skilled_solve
from sso._limits import DEFAULT_MAX_ITERATIONS, DEFAULT_SHAFT_SOLVER_TOL
from sso._shafts.options import build_problem
from sso._shafts.problem import compiled_nlp
from sso._solvers import ipopt
from sso._solvers.run import RunLimits

BETA_DEG = (30.0, 40.0, 50.0)
PHASE_DEG = (90.0, 90.0)
BETA_BOUNDS_DEG = (10.0, 40.0)
PHASE_BOUNDS_DEG = (0.0, 180.0)
OPTION = 3
FUNCTIONS = ("nlp_f", "nlp_grad_f", "nlp_hess_l")
"""The NLP's functions IPOPT calls on a problem with bounds only."""


def measure(rounds: int, solves: int) -> dict[str, Any]:
    """The figures of the module docstring, medians over ``rounds`` interleaved rounds."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the start's 50 deg is moved onto its bound
        problem = build_problem(BETA_DEG, PHASE_DEG, "exact", OPTION, BETA_BOUNDS_DEG,
                                PHASE_BOUNDS_DEG)
    nlp = compiled_nlp(problem, 0)
    limits = RunLimits(problem.lower_rad, problem.upper_rad)
    start, parameters = problem.start_rad, problem.parameters_rad

    def solve_ipopt() -> Any:
        return ipopt.solve(nlp, start, parameters, limits, DEFAULT_SHAFT_SOLVER_TOL,
                           DEFAULT_MAX_ITERATIONS)

    def solve_skilled() -> Any:
        return skilled_solve(np.array(BETA_DEG), np.array(PHASE_DEG), OPTION, BETA_BOUNDS_DEG,
                             PHASE_BOUNDS_DEG)

    outcome = solve_ipopt()
    (solver,) = nlp.ipopt_solvers.values()
    for _ in range(solves):
        solve_ipopt()
        solve_skilled()
    shares, ipopt_cpu, skilled_cpu = [], [], []
    calls: dict[str, list[float]] = {name: [] for name in FUNCTIONS}
    for _ in range(rounds):
        evaluation_s = 0.0
        counts = dict.fromkeys(FUNCTIONS, 0)
        started = time.process_time()
        for _ in range(solves):
            outcome = solve_ipopt()
            stats = solver.stats()
            evaluation_s += sum(stats[f"t_proc_{name}"] for name in FUNCTIONS)
            for name in FUNCTIONS:
                counts[name] += stats[f"n_call_{name}"]
        elapsed = time.process_time() - started
        shares.append(evaluation_s / elapsed)
        ipopt_cpu.append(elapsed / solves)
        for name in FUNCTIONS:
            calls[name].append(counts[name] / solves)
        started = time.process_time()
        for _ in range(solves):
            solve_skilled()
        skilled_cpu.append((time.process_time() - started) / solves)
    return {
        "iterations": outcome.nit,
        "calls_per_solve": {name: statistics.median(values) for name, values in calls.items()},
        "evaluation_share_of_ipopt_cpu": statistics.median(shares),
        "ipopt_cpu_over_skilled_cpu": statistics.median(
            [own / skilled for own, skilled in zip(ipopt_cpu, skilled_cpu, strict=True)]),
        "rounds": rounds,
        "solves_per_round": solves,
    }


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=15, help="interleaved rounds (15)")
    parser.add_argument("--solves", type=int, default=50, help="solves per round (50)")
    arguments = parser.parse_args(argv)
    figures = measure(arguments.rounds, arguments.solves)
    calls = ", ".join(f"{name} {count:g}" for name, count in figures["calls_per_solve"].items())
    print(f"paper option 3, exact model: IPOPT {figures['iterations']} iterations; "
          f"calls per solve: {calls}")
    print(f"CasADi's evaluations of the NLP functions: "
          f"{figures['evaluation_share_of_ipopt_cpu']:.1%} of IPOPT's CPU time")
    print(f"IPOPT's CPU time per solve: {figures['ipopt_cpu_over_skilled_cpu']:.2f}x the skilled "
          f"baseline's ({figures['rounds']} rounds of {figures['solves_per_round']} solves, "
          "medians)")


if __name__ == "__main__":
    main()
