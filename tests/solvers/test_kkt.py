"""First-order optimality measures against hand-solved KKT conditions.

Reference: min x0^2 + x1^2 s.t. x0 + x1 >= 1 has its optimum at (0.5, 0.5) with
gradient (1, 1) = 1 * (1, 1), the active constraint's normal times multiplier 1.
"""

from __future__ import annotations

import numpy as np
import pytest

from sso._solvers.kkt import constraint_violation, kkt_residual, projected_gradient_norm
from sso._solvers.run import RunLimits

BOX = RunLimits(np.array([-2.0, -2.0]), np.array([2.0, 2.0]))
HALF_PLANE = RunLimits(BOX.lower, BOX.upper, np.array([1.0]), np.array([np.inf]))
NORMAL = np.array([[1.0, 1.0]])


def test_projected_gradient_of_an_empty_design_is_zero():
    assert projected_gradient_norm(np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0)) == 0.0


def test_without_constraints_kkt_is_the_projected_gradient():
    x, gradient = np.array([-2.0, 0.3]), np.array([5.0, -0.25])
    # x0 on its lower bound pushed outwards does not count; x1 moves by 0.25.
    assert kkt_residual(x, gradient, BOX) == projected_gradient_norm(
        x, gradient, BOX.lower, BOX.upper
    )
    assert kkt_residual(x, gradient, BOX) == pytest.approx(0.25, rel=1e-15)


def test_kkt_point_of_a_constrained_problem_has_zero_residual():
    x = np.array([0.5, 0.5])
    residual = kkt_residual(x, 2 * x, HALF_PLANE, NORMAL @ x, NORMAL)
    assert residual == pytest.approx(0.0, abs=1e-15)


def test_residual_is_what_no_non_negative_multiplier_can_explain():
    # At (0.6, 0.4) the constraint is active; gradient (1.2, 0.8) minus lambda (1, 1) is
    # smallest in the least-squares sense at lambda = 1, leaving (0.2, -0.2).
    x = np.array([0.6, 0.4])
    assert kkt_residual(x, 2 * x, HALF_PLANE, NORMAL @ x, NORMAL) == pytest.approx(0.2, rel=1e-12)
    # A gradient pulling away from the constraint cannot use a negative multiplier.
    assert kkt_residual(x, -np.array([1.0, 1.0]), HALF_PLANE, NORMAL @ x, NORMAL) == (
        pytest.approx(1.0, rel=1e-12)
    )


def test_an_inactive_constraint_leaves_the_whole_gradient():
    x = np.array([1.0, 1.0])  # x0 + x1 = 2 > 1: inactive
    assert kkt_residual(x, np.array([0.3, -0.7]), HALF_PLANE, NORMAL @ x, NORMAL) == (
        pytest.approx(0.7, rel=1e-15)
    )


def test_constraint_violation():
    inside = np.array([0.5, 0.5])
    assert constraint_violation(inside, HALF_PLANE, NORMAL @ inside) == 0.0
    short = np.array([0.2, 0.3])  # x0 + x1 = 0.5, 0.5 below its lower bound 1
    assert constraint_violation(short, HALF_PLANE, NORMAL @ short) == pytest.approx(0.5)
    outside_box = np.array([2.25, 0.0])
    assert constraint_violation(outside_box, BOX) == pytest.approx(0.25)
    assert constraint_violation(np.array([-2.5, 3.0]), BOX) == pytest.approx(1.0)
