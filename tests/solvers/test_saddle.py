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

from sso.solvers import ipopt, slsqp
from sso.solvers.saddle import solve_with_second_order_care


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
