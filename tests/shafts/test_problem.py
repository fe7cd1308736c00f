"""The shaft-series NLP graph: its objective is the residual error, one graph per shape.

Reference: one joint's RE = (1 - cos b)^2 / (2 cos b) (derived in tests/shafts/test_objective.py).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from sso._shafts.objective import residual_error
from sso._shafts.options import build_problem
from sso._shafts.problem import compiled_nlp


def test_one_joint_graph_gives_the_closed_form_re():
    problem = build_problem([30.0], [], "exact", 2, (0, 40), (0, 180))
    nlp = compiled_nlp(problem, 256)
    beta = math.radians(25.0)
    value, gradient = nlp.objective_and_gradient(np.array([beta]), problem.parameters_rad)
    c = math.cos(beta)
    assert value == pytest.approx((1 - c) ** 2 / (2 * c), rel=1e-13)
    # d/db of (1 - c)^2 / (2 c) = s (1 - c)(1 + c) / (2 c^2), by hand.
    expected = math.sin(beta) * (1 - c) * (1 + c) / (2 * c * c)
    assert gradient[0] == pytest.approx(expected, rel=1e-12)


def test_fixed_angles_enter_as_parameters_in_order():
    problem = build_problem([30.0, 20.0, 10.0], [70.0, 110.0], "paper", 1, (0, 40), (0, 180))
    nlp = compiled_nlp(problem, 64)
    phases = np.radians([50.0, 130.0])
    value, _ = nlp.objective_and_gradient(phases, problem.parameters_rad)
    assert value == pytest.approx(
        residual_error(np.radians([30.0, 20.0, 10.0]), phases, "paper", 64), rel=1e-13
    )


def test_one_graph_per_shape():
    first = build_problem([30.0, 40.0], [90.0], "exact", 3, (0, 40), (0, 180))
    other_design = build_problem([10.0, 20.0], [45.0], "exact", 3, (5, 30), (0, 90))
    assert compiled_nlp(first, 64) is compiled_nlp(other_design, 64)
    # The exact model's graph is the closed form: no quadrature angles in its shape.
    assert compiled_nlp(first, 64) is compiled_nlp(first, 32)
    paper = build_problem([30.0, 40.0], [90.0], "paper", 3, (0, 40), (0, 180))
    assert compiled_nlp(paper, 64) is not compiled_nlp(paper, 32)
    assert compiled_nlp(paper, 64) is not compiled_nlp(first, 64)


@pytest.mark.parametrize("option", [1, 2, 3])
def test_the_exact_models_three_evaluators_agree(option):
    # The exact model's NLP carries the CasADi graph (IPOPT), the closed form in
    # Python complex numbers (the shared measure) and the residuals as an SX expression
    # (the "lm" solver's functions): three codings of one formula, compared at random
    # designs of four joints to 1e-12.
    import casadi

    rng = np.random.default_rng(41)
    problem = build_problem([20.0, 30.0, 10.0, 25.0], [40.0, 80.0, 120.0], "exact", option,
                            (0.0, 60.0), (-180.0, 180.0))
    nlp = compiled_nlp(problem, 0)
    parameters = problem.parameters_rad
    points = rng.uniform(problem.lower_rad, problem.upper_rad, (5, problem.n_free))
    residuals = casadi.Function("r", [nlp.symbols["x"], nlp.symbols["p"]],
                                [nlp.residuals, casadi.jacobian(nlp.residuals, nlp.symbols["x"])])
    evaluated = [residuals(point, parameters) for point in points]
    residual = [np.array(pair[0]).ravel() for pair in evaluated]
    jacobian = [np.array(pair[1]) for pair in evaluated]
    for row, point in enumerate(points):
        rho, complex_jacobian = nlp.residuals_and_jacobian(point.tolist(), parameters.tolist())
        # rho = r1 - i r2
        np.testing.assert_allclose([rho.real, -rho.imag], residual[row], rtol=1e-12,
                                   atol=1e-14)
        np.testing.assert_allclose(np.array([[entry.real for entry in complex_jacobian],
                                             [-entry.imag for entry in complex_jacobian]]),
                                   jacobian[row], rtol=1e-12, atol=1e-14)
        value, gradient = nlp.objective_and_gradient(point, parameters)
        graph = casadi.Function("f", [nlp.symbols["x"], nlp.symbols["p"]],
                                [nlp.symbols["f"], casadi.gradient(nlp.symbols["f"],
                                                                   nlp.symbols["x"])])
        graph_value, graph_gradient = graph(point, parameters)
        assert value == pytest.approx(float(graph_value), rel=1e-12, abs=1e-15)
        np.testing.assert_allclose(gradient, np.array(graph_gradient).ravel(), rtol=1e-10,
                                   atol=1e-14)
        # The measures' plain-float form gives the same numbers, bit for bit.
        assert nlp.objective_and_gradient_floats(point.tolist(), parameters.tolist()) == (
            value, gradient.tolist())
