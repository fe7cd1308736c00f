"""IPOPT through CasADi on NLPs whose optima are known in closed form
(tests/solvers/problems.py)."""

from __future__ import annotations

import numpy as np
import pytest
from solvers.problems import BOX, CLOSED_FORM_CASES, PARAMETERS, rosenbrock

from sso.solvers import ipopt


@pytest.mark.parametrize("case", CLOSED_FORM_CASES, ids=lambda case: case.name)
def test_reaches_the_closed_form_optimum(case):
    nlp, limits = case.build()
    outcome = ipopt.solve(nlp, np.array(case.start), PARAMETERS, limits, 1e-12, 500)
    assert outcome.success and outcome.status == 0 and outcome.message == "Solve_Succeeded"
    # IPOPT relaxes bounds by about 1e-8 (its bound_relax_factor), hence 1e-7 on bounds.
    np.testing.assert_allclose(outcome.x, case.x, atol=1e-7)
    assert outcome.fun == pytest.approx(case.fun, abs=1e-7)
    assert outcome.nit > 0 and outcome.nfev >= outcome.nit and outcome.time_s > 0.0


def test_unconstrained_minimum_to_round_off():
    outcome = ipopt.solve(rosenbrock(), np.array([-1.2, 1.0]), PARAMETERS, BOX, 1e-12, 500)
    np.testing.assert_allclose(outcome.x, [1.0, 1.0], atol=1e-9)
    assert 0.0 <= outcome.fun < 1e-20


def test_iteration_limit_is_reported_not_raised():
    outcome = ipopt.solve(rosenbrock(), np.array([-1.2, 1.0]), PARAMETERS, BOX, 1e-12, 1)
    assert not outcome.success
    assert outcome.status == ipopt.RETURN_STATUS_CODES["Maximum_Iterations_Exceeded"] == -1
    assert outcome.message == "Maximum_Iterations_Exceeded"
    assert outcome.nit == 1 and np.all(np.isfinite(outcome.x))


def test_status_codes_are_ipopts_application_return_status():
    # IpReturnCodes_inc.h of IPOPT 3.14: success codes are >= 0, failures negative.
    codes = ipopt.RETURN_STATUS_CODES
    assert codes["Solve_Succeeded"] == 0 and codes["Solved_To_Acceptable_Level"] == 1
    assert codes["Invalid_Number_Detected"] == -13 and codes["Internal_Error"] == -199
    assert len(set(codes.values())) == len(codes)
    assert ipopt.UNKNOWN_STATUS not in codes.values()
