"""SciPy's SLSQP fed CasADi's exact derivatives, on NLPs with closed-form optima
(tests/solvers/problems.py)."""

from __future__ import annotations

import numpy as np
import pytest
from solvers.problems import BOX, CLOSED_FORM_CASES, PARAMETERS, rosenbrock

from sso._solvers import slsqp


@pytest.mark.parametrize("case", CLOSED_FORM_CASES, ids=lambda case: case.name)
def test_reaches_the_closed_form_optimum(case):
    nlp, limits = case.build()
    outcome = slsqp.solve(nlp, np.array(case.start), PARAMETERS, limits, 1e-12, 500)
    assert outcome.success and outcome.status == 0
    # SLSQP stops on the change of the objective; on Rosenbrock's flat valley that
    # leaves x about 1e-5 off while f is within 1e-11.
    np.testing.assert_allclose(outcome.x, case.x, atol=1e-4)
    assert outcome.fun == pytest.approx(case.fun, abs=1e-9)
    # The start's evaluation (for ftol) is counted on top of SciPy's own counts.
    assert outcome.nfev >= outcome.nit + 1 and outcome.njev >= 2


def test_bounds_are_kept():
    # The optimum sits on the lower bound x[0] = 0: SLSQP never leaves the box, and
    # stops on the bound to round-off (SciPy 1.17's SLSQP ends 9.9e-16 inside it;
    # earlier releases ended on it exactly).
    case = next(case for case in CLOSED_FORM_CASES if case.name == "bowl on a bound")
    nlp, limits = case.build()
    outcome = slsqp.solve(nlp, np.array(case.start), PARAMETERS, limits, 1e-12, 500)
    assert 0.0 <= outcome.x[0] <= 1e-12
    assert outcome.fun == pytest.approx(1.0, abs=1e-12)


def test_iteration_limit_is_reported_not_raised():
    outcome = slsqp.solve(rosenbrock(), np.array([-1.2, 1.0]), PARAMETERS, BOX, 1e-12, 1)
    assert not outcome.success
    assert outcome.status == 9  # SciPy's SLSQP exit mode 9: iteration limit
    assert outcome.message == "Iteration limit reached"
