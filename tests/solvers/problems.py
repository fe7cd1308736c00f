"""Small NLPs with optima known in closed form, for the generic solver layer.

Each optimum is derived by hand in its docstring (first-order conditions, and the
sign of the multipliers or of the curvature), independently of any solver.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import casadi
import numpy as np

from sso._solvers.nlp import CompiledNLP, compile_nlp
from sso._solvers.run import RunLimits

BOX = RunLimits(np.array([-2.0, -2.0]), np.array([2.0, 2.0]))
PARAMETERS = np.array([1.0])


def rosenbrock() -> CompiledNLP:
    """p * ((1 - x0)^2 + 100 (x1 - x0^2)^2): the minimum 0 at (1, 1) for p > 0.

    With x0 <= 0.5 the minimum moves to (0.5, 0.25), value 0.25: for fixed x0 the
    second term vanishes at x1 = x0^2, leaving (1 - x0)^2, which falls as x0 rises to 0.5.
    """
    x, p = casadi.SX.sym("x", 2), casadi.SX.sym("p", 1)
    return compile_nlp(
        "test_rosenbrock",
        x,
        p,
        p[0] * ((1 - x[0]) ** 2 + 100 * (x[1] - x[0] ** 2) ** 2),
    )


def rosenbrock_gradient(x: np.ndarray) -> np.ndarray:
    """d/dx of the Rosenbrock function (p = 1), differentiated by hand."""
    return np.array(
        [
            -2.0 * (1 - x[0]) - 400.0 * x[0] * (x[1] - x[0] ** 2),
            200.0 * (x[1] - x[0] ** 2),
        ]
    )


def two_constraints() -> tuple[CompiledNLP, RunLimits]:
    """min (x0 - 2)^2 + (x1 - 1)^2  s.t.  x0^2 - x1 <= 0,  x0 + x1 <= 2.

    Optimum (1, 1), value 1: both constraints are active there, and
    -grad f = (2, 0) = (2/3) (2, -1) + (2/3) (1, 1) with both multipliers positive.
    """
    x, p = casadi.SX.sym("x", 2), casadi.SX.sym("p", 1)
    nlp = compile_nlp(
        "test_two_constraints",
        x,
        p,
        p[0] * ((x[0] - 2) ** 2 + (x[1] - 1) ** 2),
        casadi.vertcat(x[0] ** 2 - x[1], x[0] + x[1]),
    )
    limits = RunLimits(BOX.lower, BOX.upper, np.array([-np.inf, -np.inf]), np.array([0.0, 2.0]))
    return nlp, limits


def one_equality() -> tuple[CompiledNLP, RunLimits]:
    """min x0^2 + x1^2  s.t.  x0 + x1 = 1: optimum (0.5, 0.5), value 0.5 (by symmetry
    and the Lagrange condition 2 x = lambda (1, 1))."""
    x, p = casadi.SX.sym("x", 2), casadi.SX.sym("p", 1)
    nlp = compile_nlp("test_one_equality", x, p, p[0] * (x[0] ** 2 + x[1] ** 2), x[0] + x[1])
    return nlp, RunLimits(BOX.lower, BOX.upper, np.array([1.0]), np.array([1.0]))


def saddle() -> CompiledNLP:
    """x0^2 - x1^2 + x1^4 / 4: a saddle at the origin (Hessian diag(2, -2)), minima
    at (0, +-sqrt 2) with value -2 + 1 = -1 (d/dx1 = -2 x1 + x1^3 = 0)."""
    x, p = casadi.SX.sym("x", 2), casadi.SX.sym("p", 1)
    return compile_nlp("test_saddle", x, p, p[0] * (x[0] ** 2 - x[1] ** 2 + x[1] ** 4 / 4))


def bowl() -> CompiledNLP:
    """x0^2 + x1^2: minimum 0 at the origin, positive curvature everywhere."""
    x, p = casadi.SX.sym("x", 2), casadi.SX.sym("p", 1)
    return compile_nlp("test_bowl", x, p, p[0] * (x[0] ** 2 + x[1] ** 2))


def shifted_bowl() -> CompiledNLP:
    """(x0 + 1)^2 + (x1 - 0.5)^2 on [0, 1]^2: minimum at (0, 0.5) on the bound x0 = 0,
    value 1."""
    x, p = casadi.SX.sym("x", 2), casadi.SX.sym("p", 1)
    return compile_nlp("test_shifted_bowl", x, p, p[0] * ((x[0] + 1) ** 2 + (x[1] - 0.5) ** 2))


SADDLE_MINIMUM = -1.0
SADDLE_MINIMUM_X1 = math.sqrt(2.0)


@dataclass(frozen=True)
class ClosedFormCase:
    """One problem with its start and its known optimum."""

    name: str
    build: Callable[[], tuple[CompiledNLP, RunLimits]]
    start: tuple[float, float]
    x: tuple[float, float]
    fun: float


CLOSED_FORM_CASES = (
    ClosedFormCase("rosenbrock", lambda: (rosenbrock(), BOX), (-1.2, 1.0), (1.0, 1.0), 0.0),
    ClosedFormCase(
        "rosenbrock with x0 <= 0.5",
        lambda: (rosenbrock(), RunLimits(np.array([-2.0, -2.0]), np.array([0.5, 2.0]))),
        (-1.2, 1.0),
        (0.5, 0.25),
        0.25,
    ),
    ClosedFormCase(
        "bowl on a bound",
        lambda: (shifted_bowl(), RunLimits(np.zeros(2), np.ones(2))),
        (0.5, 0.2),
        (0.0, 0.5),
        1.0,
    ),
    ClosedFormCase("two active constraints", two_constraints, (0.0, 0.0), (1.0, 1.0), 1.0),
    ClosedFormCase("one equality", one_equality, (0.0, 0.0), (0.5, 0.5), 0.5),
)
