"""Second-order care: a start at a minimum is returned as is; a saddle point is left.

Reference: x0^2 - x1^2 + x1^4/4 has a saddle at the origin and minima (0, +-sqrt 2)
with value -1 (tests/solvers/problems.py derives both).
"""

from __future__ import annotations

import numpy as np
import pytest
from solvers.problems import (
    BOX,
    PARAMETERS,
    SADDLE_MINIMUM,
    SADDLE_MINIMUM_X1,
    bowl,
    saddle,
)

from sso._solvers import ipopt, slsqp
from sso._solvers.saddle import solve_with_second_order_care


@pytest.mark.parametrize("backend", [ipopt, slsqp], ids=["ipopt", "slsqp"])
def test_a_solver_started_on_the_saddle_is_moved_off_it(backend):
    nlp = saddle()

    def solve(start):
        return backend.solve(nlp, start, PARAMETERS, BOX, 1e-12, 500)

    plain = solve(np.zeros(2))
    assert plain.fun == pytest.approx(0.0, abs=1e-12)  # stuck: the gradient is zero there
    outcome = solve_with_second_order_care(solve, nlp, np.zeros(2), PARAMETERS, BOX, 1e-12)
    assert outcome.success
    assert outcome.fun == pytest.approx(SADDLE_MINIMUM, abs=1e-10)
    assert abs(outcome.x[1]) == pytest.approx(SADDLE_MINIMUM_X1, abs=1e-6)
    assert outcome.message.endswith("(after leaving a saddle point)")
    # The two legs' counts and the checks' own evaluations are all counted.
    assert outcome.nfev > plain.nfev and outcome.njev > plain.njev


def test_a_start_at_a_minimum_skips_the_solver():
    calls = []

    def solve(start):
        calls.append(start)
        return ipopt.solve(bowl(), start, PARAMETERS, BOX, 1e-12, 500)

    outcome = solve_with_second_order_care(solve, bowl(), np.zeros(2), PARAMETERS, BOX, 1e-12)
    assert calls == []
    assert outcome.success and outcome.nit == 0 and outcome.fun == 0.0
    assert outcome.message.startswith("start is a minimum to tolerance")
    # Evaluations the checks made: the start's value and gradient, the curvature check's
    # gradient and 2 n = 4 gradients of the difference Hessian.
    assert (outcome.nfev, outcome.njev) == (1, 1 + 1 + 4)


def test_an_ordinary_start_runs_the_solver_once():
    nlp = bowl()
    calls = []

    def solve(start):
        calls.append(start)
        return ipopt.solve(nlp, start, PARAMETERS, BOX, 1e-12, 500)

    outcome = solve_with_second_order_care(
        solve, nlp, np.array([1.0, -0.5]), PARAMETERS, BOX, 1e-12
    )
    assert len(calls) == 1
    np.testing.assert_allclose(outcome.x, [0.0, 0.0], atol=1e-9)
    assert "saddle" not in outcome.message


def test_closed_form_hessian_agrees_with_central_differences_of_the_gradient():
    # The exact model supplies its Hessian; the check's own central differences of
    # the gradient (step 1e-4, truncation ~1e-8) are the independent reference.
    from dataclasses import replace

    from sso._shafts.options import build_problem
    from sso._shafts.problem import compiled_nlp
    from sso._solvers.saddle import _Counts, _hessian

    problem = build_problem([15.0, 20.0, 9.0, 25.0], [30.0, 40.0, 70.0], "exact", 3,
                            (0.0, 40.0), (0.0, 180.0))
    nlp = compiled_nlp(problem, 0)
    point = problem.start_rad.tolist()
    free = [0, 2, 3, 5]
    closed = _hessian(nlp, point, problem.parameters_rad, _Counts(), free)
    counts = _Counts()
    differences = _hessian(replace(nlp, objective_hessian=None), point, problem.parameters_rad,
                           counts, free)
    assert counts.gradient == 2 * len(free)
    np.testing.assert_allclose(closed, differences, rtol=1e-6,
                               atol=1e-7 * np.abs(differences).max())
