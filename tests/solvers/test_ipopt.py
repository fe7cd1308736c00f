"""IPOPT through CasADi on NLPs whose optima are known in closed form
(tests/solvers/problems.py)."""

from __future__ import annotations

import numpy as np
import pytest
from solvers.problems import BOX, CLOSED_FORM_CASES, PARAMETERS, rosenbrock

from sso._solvers import ipopt


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


@pytest.mark.parametrize(("first_beta_deg", "starts"), [(21.864406779661017, 4),
                                                        (21.932773109243698, 8)])
def test_an_answer_in_a_flat_valley_ending_on_a_bound_is_put_on_the_bound(first_beta_deg,
                                                                         starts):
    """Two points of a sweep of the paper's option-1 case (cases/paper_option1_exact.toml,
    first angle from 10 to 30 deg in 60 and 120 steps): the two phases' valley ends on the
    bound phase_2 = 0. IPOPT stopped 5e-4 and 1.2e-4 rad off it (its multiplier pushing
    against it, its answer stationary to 3e-9 per rad), RE 1.9e-4 and 1.1e-6 relative above
    SLSQP's, and the cross-check said "disagree". Its own answer now ends on the bound,
    within the cross-check's tolerance of SLSQP's; the reference for the corner is a
    brute force of RE along phase_1 there (the rectangle rule on 256 angles, not the
    closed form the solvers use)."""
    import warnings

    import sso
    from sso._shafts.objective import residual_error

    series = sso.ShaftSeries([first_beta_deg, 20.0, 9.0], [30.0, 40.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = sso.optimise(series, 1, beta_bounds_deg=(0.0, 40.0),
                              phase_bounds_deg=(0.0, 180.0), starts=starts)
    answer = result.solutions["ipopt"]
    assert answer.role == "solve" and answer.success
    assert answer.x[1] == 0.0  # on the bound
    assert result.crosscheck.agree, result.crosscheck.message
    phase_1 = np.radians(np.linspace(89.99, 90.01, 2001)).reshape(-1, 1)
    corner = residual_error(list(np.radians(series.beta_deg)), [phase_1, 0.0 * phase_1],
                            "exact", 256)
    assert answer.fun <= corner.min() * (1 + 1e-9)
