"""Second-order care: a start at a minimum is returned as is; a saddle point is left.

Reference: x0^2 - x1^2 + x1^4/4 has a saddle at the origin and minima (0, +-sqrt 2)
with value -1 (tests/solvers/problems.py derives both).
"""

from __future__ import annotations

from dataclasses import replace

import casadi
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
from sso._solvers.nlp import compile_nlp
from sso._solvers.saddle import (
    isolated_minimum,
    saddle_direction,
    solve_with_second_order_care,
)


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


def _scaled_saddle(scale, curvature):
    """``scale * (x0^2 - curvature * (x1^2 - x1^4 / 4))``: at the origin a stationary point
    with Hessian ``scale * diag(2, -2 curvature)`` (differentiated by hand), a saddle for
    any ``curvature > 0``; ``p`` is unused."""
    x, p = casadi.SX.sym("x", 2), casadi.SX.sym("p", 1)
    objective = scale * (x[0] ** 2 - curvature * (x[1] ** 2 - x[1] ** 4 / 4))
    return compile_nlp("test_scaled_saddle", x, p, objective + 0.0 * p[0])


def _direction_at_origin(nlp):
    return saddle_direction(nlp, True, 0.0, [0.0, 0.0], PARAMETERS, BOX)


@pytest.mark.parametrize(("curvature", "is_saddle"), [
    # smallest over largest eigenvalue magnitude: -1e-5, ten times the stated threshold
    (1e-5, True),
    (1e-7, False),  # -1e-7: ten times below it, flat to the check
])
def test_negative_curvature_counts_from_its_stated_relative_threshold(curvature, is_saddle):
    # The check counts an eigenvalue below -RELATIVE_CURVATURE (1e-6) times the largest
    # magnitude as negative curvature; the Hessian here is diag(2, -2 curvature).
    found = _direction_at_origin(_scaled_saddle(1.0, curvature))
    assert (found is not None) == is_saddle
    if is_saddle:
        point, direction = found
        np.testing.assert_array_equal(point, [0.0, 0.0])
        np.testing.assert_allclose(np.abs(direction), [0.0, 1.0], atol=1e-9)
    # the same threshold tells an isolated minimum (curvature +1e-5) from a flat one (+1e-7)
    assert isolated_minimum(_scaled_saddle(1.0, -curvature), np.zeros(2), PARAMETERS,
                            BOX) == is_saddle


@pytest.mark.parametrize(("scale", "is_saddle"), [
    (5e-14, True),  # eigenvalues +-1e-13, ten times the stated absolute threshold
    (5e-16, False),  # +-1e-15: ten times below it, round-off to the check
])
def test_negative_curvature_counts_from_its_stated_absolute_threshold(scale, is_saddle):
    # An eigenvalue counts only below -ABSOLUTE_CURVATURE (1e-14) too: the Hessian here is
    # scale * diag(2, -2), so the relative test alone would count any scale.
    found = _direction_at_origin(_scaled_saddle(scale, 1.0))
    assert (found is not None) == is_saddle
    assert isolated_minimum(_scaled_saddle(scale, -1.0), np.zeros(2), PARAMETERS,
                            BOX) == is_saddle


def test_a_nonnegative_objective_above_round_off_zero_is_still_checked():
    # (1e-9 - 1e-3 x1^2)^2 + 1e-7 x0^2 >= 0 is 1e-18 at the origin, a saddle (Hessian
    # diag(2e-7, -4e-12), by hand), with minima 0 at x1 = +-1e-3. sqrt(1e-18) = 1e-9 is
    # seven orders above the round-off of the residual, so the check does not take the
    # origin for a global minimum: only values at or below ZERO_OBJECTIVE (1e-20) are.
    x, p = casadi.SX.sym("x", 2), casadi.SX.sym("p", 1)
    nlp = replace(compile_nlp("test_nonnegative_saddle", x, p,
                              (1e-9 - 1e-3 * x[1] ** 2) ** 2 + 1e-7 * x[0] ** 2 + 0.0 * p[0]),
                  nonnegative_objective=True)
    value = float(nlp.objective_and_gradient(np.zeros(2), PARAMETERS)[0])
    assert value == pytest.approx(1e-18, rel=1e-12)
    found = saddle_direction(nlp, True, value, [0.0, 0.0], PARAMETERS, BOX)
    assert found is not None
    np.testing.assert_allclose(np.abs(found[1]), [0.0, 1.0], atol=1e-9)
    # at round-off zero, ZERO_OBJECTIVE included, no check is made (a global minimum of a
    # nonnegative objective)
    for fun in (1e-21, 1e-20):
        assert saddle_direction(nlp, True, fun, [0.0, 0.0], PARAMETERS, BOX) is None
