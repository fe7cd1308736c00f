"""Cross-check verdicts and the first-order optimality measure."""

import numpy as np
import pytest

import sso
from sso._solvers.crosscheck import crosscheck
from sso._solvers.kkt import projected_gradient_norm

SERIES = sso.ShaftSeries([20.0, 20.0])


def solution(name, fun, kkt=1e-10, success=True, message="ok"):
    return sso.Solution(solver=name, series=SERIES, x=(20.0, 20.0), fun=fun, nit=3, nfev=4,
                        status=0 if success else -1, success=success, message=message,
                        kkt=kkt, time_s=0.01)


def test_equal_objectives_on_different_designs_agree():
    verdict = crosscheck({"ipopt": solution("ipopt", 1e-24), "slsqp": solution("slsqp", 3e-21)})
    assert verdict.agree and verdict.better is None
    assert verdict.objective_gap == pytest.approx(3e-21 - 1e-24)


def test_gap_beyond_tolerance_names_the_better_solver():
    verdict = crosscheck({"ipopt": solution("ipopt", 1.0e-4), "slsqp": solution("slsqp", 1.1e-4)})
    assert not verdict.agree
    assert verdict.better == "ipopt"
    assert "objectives differ by 1e-05" in verdict.message


def test_relative_tolerance_scales_with_objective():
    close = crosscheck({"a": solution("a", 1.0), "b": solution("b", 1.0 + 5e-7)})
    assert close.agree
    far = crosscheck({"a": solution("a", 1.0), "b": solution("b", 1.0 + 2e-6)})
    assert not far.agree


def test_not_stationary_or_failed_disagrees():
    verdict = crosscheck({"ipopt": solution("ipopt", 0.5, kkt=1e-3),
                          "slsqp": solution("slsqp", 0.5, success=False,
                                            message="Iteration limit")})
    assert not verdict.agree
    assert "slsqp failed (Iteration limit)" in verdict.message
    assert "ipopt projected gradient 0.001 exceeds 1e-06" in verdict.message


def test_projected_gradient_ignores_push_against_active_bound():
    lower, upper = np.array([0.0, 0.0]), np.array([1.0, 1.0])
    # at the lower bound with a positive gradient (pushing outwards): stationary
    assert projected_gradient_norm(np.array([0.0, 0.5]), np.array([3.0, 0.0]), lower, upper) == 0.0
    # interior: the gradient itself
    assert projected_gradient_norm(np.array([0.5, 0.5]), np.array([1e-3, -2e-3]), lower,
                                   upper) == pytest.approx(2e-3, rel=1e-12)
    # at the upper bound pulled inwards: counts, capped by the distance to the other bound
    assert projected_gradient_norm(np.array([1.0, 0.5]), np.array([5.0, 0.0]), lower, upper) == 1.0
