"""Every solver from every start, each answer re-measured on the shared graph.

Reference optima: tests/solvers/problems.py (Rosenbrock: 0 at (1, 1); with the
constraints x0^2 <= x1 and x0 + x1 <= 2: 1 at (1, 1)).
"""

from __future__ import annotations

import numpy as np
import pytest
from solvers.problems import (
    BOX,
    CLOSED_FORM_CASES,
    PARAMETERS,
    rosenbrock,
    two_constraints,
)

from sso._solvers.multistart import (
    best_solution,
    distinct_minima,
    run_starts,
    solution_from_run,
)
from sso._solvers.solution import Solution
from sso._solvers.starts import start_points


def _solution(fun: float, success: bool = True) -> Solution:
    return Solution(
        solver="ipopt",
        series=None,
        x=(0.0,),
        fun=fun,
        nit=1,
        nfev=1,
        status=0,
        success=success,
        message="",
        kkt=0.0,
        time_s=0.0,
    )


def test_every_solver_runs_from_every_start_and_is_remeasured():
    nlp = rosenbrock()
    points = start_points(np.array([-1.2, 1.0]), BOX.lower, BOX.upper, 3)
    runs = run_starts(nlp, points, PARAMETERS, BOX, ("ipopt", "slsqp"), 1e-12, 500)
    assert list(runs) == ["ipopt", "slsqp"]
    for name, solver_runs in runs.items():
        assert [run.start_index for run in solver_runs] == [0, 1, 2]
        for run in solver_runs:
            assert run.solver == name and run.outcome.success
            value, _ = nlp.objective_and_gradient(run.outcome.x, PARAMETERS)
            assert run.fun == value  # measured on the graph, not the solver's word
            assert run.fun < 1e-8 and run.kkt < 1e-3 and run.violation == 0.0
            np.testing.assert_allclose(run.outcome.x, [1.0, 1.0], atol=1e-4)


def test_constrained_runs_are_measured_with_their_constraints():
    nlp, limits = two_constraints()
    runs = run_starts(nlp, np.zeros((1, 2)), PARAMETERS, limits, ("ipopt", "slsqp"), 1e-12, 500)
    for (run,) in runs.values():
        assert run.fun == pytest.approx(1.0, abs=1e-8)
        assert run.kkt < 1e-6 and run.violation < 1e-8


def test_failures_are_kept_and_x_is_clipped_onto_the_bounds():
    runs = run_starts(rosenbrock(), np.array([[-1.2, 1.0]]), PARAMETERS, BOX, ("ipopt",), 1e-12, 1)
    (run,) = runs["ipopt"]
    assert not run.outcome.success and run.outcome.status == -1
    assert np.all(run.outcome.x >= BOX.lower) and np.all(run.outcome.x <= BOX.upper)


def test_solution_from_run_sums_the_solvers_evaluations():
    runs = run_starts(
        rosenbrock(),
        np.array([[-1.2, 1.0], [0.0, 0.0]]),
        PARAMETERS,
        BOX,
        ("slsqp",),
        1e-12,
        500,
    )["slsqp"]
    solution = solution_from_run(runs[1], runs, x=(10.0, 20.0))
    assert solution.x == (10.0, 20.0) and solution.start_index == 1
    assert solution.total_nfev == runs[0].outcome.nfev + runs[1].outcome.nfev
    assert solution.fun == runs[1].fun and solution.kkt == runs[1].kkt
    assert solution.series is None


def test_best_solution_prefers_success_then_the_lower_objective():
    failed_lower = _solution(0.1, success=False)
    assert best_solution([_solution(0.5), failed_lower, _solution(0.3)]).fun == 0.3
    assert best_solution([failed_lower, _solution(0.2, success=False)]) is failed_lower


def test_distinct_minima_merges_values_within_tolerance():
    solutions = [_solution(value) for value in (1.0, 1.0 + 1e-9, 2.0, 2.5e-3)]
    solutions.append(_solution(0.0, success=False))
    assert distinct_minima(solutions, rtol=1e-6, atol=1e-14) == (2.5e-3, 1.0, 2.0)
    assert distinct_minima(solutions, rtol=0.0, atol=0.0) == (
        2.5e-3,
        1.0,
        1.0 + 1e-9,
        2.0,
    )


def test_ipopts_relaxed_bound_is_measured_on_the_bound():
    """IPOPT may stop about 1e-8 outside a bound (bound_relax_factor) with an objective a
    little below the true minimum 1; the measurement clips x onto the bound first."""
    case = next(case for case in CLOSED_FORM_CASES if case.name == "bowl on a bound")
    nlp, limits = case.build()
    (run,) = run_starts(nlp, np.array([case.start]), PARAMETERS, limits, ("ipopt",), 1e-12, 500)[
        "ipopt"
    ]
    assert run.outcome.x[0] == 0.0
    assert run.fun == pytest.approx(1.0, abs=1e-12)
