"""The residual-error NLP of a shaft series as a CasADi graph, built once per shape.

A shape is ``(joints, option, model, quadrature angles)``; the fixed angles enter
as parameters ``p`` and the bounds as ``lbx``/``ubx``, so a new design, new
bounds or a new start reuse the same graph (cached by :func:`sso._solvers.nlp.cached_nlp`).

The exact model's RE has a closed form (:mod:`sso._kinematics.hooke_matrix`), the
squared norm of two residuals: its graph has no quadrature (``samples = 0`` in the
shape, so bounds never change the shape), costs ``O(joints)`` to build and
evaluate, and carries the residuals for the least-squares solver (``"lm"``). The
paper's model has no closed form and keeps the rectangle rule on ``samples``
angles (:mod:`sso._shafts.objective`).

IPOPT keeps CasADi's exact Hessian of the closed form: it costs little (a 30-joint
option-3 solve takes 16 iterations and about 8 ms), and the Gauss-Newton Hessian
``2 J^T J`` was measured worse. With two residuals it has rank 2 while option 3
has ``2n - 1 >= 5`` free variables, so IPOPT must regularise it: on a random
3-joint option-3 case it stopped at the iteration limit (500) with RE 1.8e-15,
where the exact Hessian converged in 11 iterations to 5e-24; at 30 joints it took
22 iterations against 16.

The paper model's graph: up to :data:`sso._limits.QUADRATURE_BLOCK_SAMPLES` angles
the objective is one expression graph (fastest to evaluate); beyond that a block of
that many angles is one CasADi function mapped over the grid, so the graph and its
build time do not grow with the angle count that the bounds call for.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from sso._kinematics.hooke_matrix import (
    residual_and_jacobian_complex,
    residual_hessian_complex,
    residuals,
)
from sso._limits import QUADRATURE_BLOCK_SAMPLES
from sso._shafts.objective import angle_grid, squared_ratio_error
from sso._shafts.options import DesignProblem
from sso._solvers.nlp import CompiledNLP, cached_nlp, compile_nlp


class ShapeKey(NamedTuple):
    """What fixes the structure of the NLP graph (``samples`` is 0 for the exact model).

    The cache is looked up with the plain tuple of the same values (equal, with the same
    hash): a named tuple's constructor is a Python function, which every solve would pay.
    """

    n_joints: int
    option: int
    model: str
    samples: int


def compiled_nlp(problem: DesignProblem, samples: int) -> CompiledNLP:
    """The cached CasADi NLP for the shape of ``problem``.

    ``samples`` (quadrature angles) counts for the paper model only; the exact
    model's closed form needs none, so its shape ignores it.
    """
    key = (problem.n_joints, problem.option, problem.model,
           samples if problem.model == "paper" else 0)
    return cached_nlp(key, lambda: _build(problem, ShapeKey(*key)))


def _build(problem: DesignProblem, key: ShapeKey) -> CompiledNLP:
    import casadi

    name = f"sso_re_{key.n_joints}_{key.option}_{key.model}_{key.samples}"
    if key.model == "paper":
        nlp = _quadrature_nlp(problem, key, name)
    else:
        x = casadi.SX.sym("x", problem.n_free)
        p = casadi.SX.sym("p", len(problem.parameters_deg))
        beta, phase = problem.split([x[i] for i in range(problem.n_free)],
                                    [p[i] for i in range(p.numel())])
        first, second = residuals(casadi, beta, phase)
        residual = casadi.vertcat(first, second)
        float_residual = _float_residuals(problem)
        objective, objective_floats = _float_objective(float_residual)
        nlp = compile_nlp(name, x, p, casadi.dot(residual, residual),
                          objective_and_gradient=objective)
        nlp.objective_and_gradient_floats = objective_floats
        nlp.residuals_and_jacobian = float_residual
        nlp.residuals = residual
        nlp.objective_hessian = _float_hessian(problem)
    nlp.nonnegative_objective = True
    return nlp


def _quadrature_nlp(problem: DesignProblem, key: ShapeKey, name: str) -> CompiledNLP:
    """The rectangle-rule RE of the paper model on ``key.samples`` angles."""
    import casadi

    cos_theta, sin_theta = angle_grid(key.samples)
    if key.samples <= QUADRATURE_BLOCK_SAMPLES:
        x = casadi.SX.sym("x", problem.n_free)
        p = casadi.SX.sym("p", len(problem.parameters_deg))
        total = _block_sum(problem, key.model, x, p, casadi.DM(cos_theta), casadi.DM(sin_theta))
        return compile_nlp(name, x, p, total / key.samples)
    block = QUADRATURE_BLOCK_SAMPLES
    x_block = casadi.SX.sym("x", problem.n_free)
    p_block = casadi.SX.sym("p", len(problem.parameters_deg))
    cos_block = casadi.SX.sym("cos_theta", block)
    sin_block = casadi.SX.sym("sin_theta", block)
    block_sum = casadi.Function(
        f"{name}_block", [x_block, p_block, cos_block, sin_block],
        [_block_sum(problem, key.model, x_block, p_block, cos_block, sin_block)])
    blocks = key.samples // block
    # x and p are shared by every block (inputs 0 and 1); the block sums are added.
    mapped = block_sum.map(f"{name}_blocks", "serial", blocks, [0, 1], [0])
    x_graph = casadi.MX.sym("x", problem.n_free)
    p_graph = casadi.MX.sym("p", len(problem.parameters_deg))
    total = mapped(x_graph, p_graph, casadi.DM(cos_theta.reshape(blocks, block).T),
                   casadi.DM(sin_theta.reshape(blocks, block).T))
    return compile_nlp(name, x_graph, p_graph, total / key.samples)


def _block_sum(problem: DesignProblem, model: str, x: Any, p: Any, cos_theta: Any,
               sin_theta: Any) -> Any:
    """Sum of the squared ratio errors at the given angles, as a CasADi expression."""
    import casadi

    beta, phase = problem.split([x[i] for i in range(problem.n_free)],
                                [p[i] for i in range(p.numel())])
    return casadi.sum1(squared_ratio_error(casadi, cos_theta, sin_theta, beta, phase, model))


def _float_residuals(problem: DesignProblem) -> Any:
    """``(x, p) -> (rho, jacobian)`` over the free variables, in Python complex numbers.

    ``x`` and ``p`` are lists of floats (rad); see
    :func:`sso._kinematics.hooke_matrix.residual_and_jacobian_complex`.
    """
    split = problem.split
    beta_free, phase_free = problem.beta_free, problem.phase_free
    # The last point and its answer: the second-order check at a start, the solver's
    # first step and the final measure of its answer each ask for a point that was
    # just evaluated. The closure lives in one thread's NLP cache. Callers read the
    # Jacobian list and never change it, so the answer is handed out uncopied.
    last: list[Any] = [None, None, None]

    def evaluate(x: list[float], fixed: list[float]) -> tuple[complex, list[complex]]:
        if x == last[0] and fixed == last[1]:
            answer: tuple[complex, list[complex]] = last[2]
            return answer
        answer = residual_and_jacobian_complex(*split(x, fixed), beta_free=beta_free,
                                               phase_free=phase_free)
        last[0], last[1], last[2] = list(x), list(fixed), answer
        return answer

    return evaluate


def _float_hessian(problem: DesignProblem) -> Any:
    """``(x, p) -> d2 RE / dx2`` over the free variables, a list of lists of floats (per rad^2).

    ``x`` and ``p`` are sequences of floats (rad); see
    :func:`sso._kinematics.hooke_matrix.residual_hessian_complex`.
    """
    split = problem.split
    beta_free, phase_free = problem.beta_free, problem.phase_free
    # The last point and its Hessian: a solver's answer is checked for negative
    # curvature after its run and for an isolated minimum in the cross-check. Callers
    # copy what they keep and never change it, so the answer is handed out uncopied.
    last: list[Any] = [None, None, None]

    def evaluate(x: Any, fixed: Any) -> list[list[float]]:
        point = x if type(x) is list else np.asarray(x, dtype=float).tolist()
        parameters = fixed if type(fixed) is list else np.asarray(fixed, dtype=float).tolist()
        if point == last[0] and parameters == last[1]:
            hessian: list[list[float]] = last[2]
            return hessian
        hessian = residual_hessian_complex(*split(point, parameters), beta_free=beta_free,
                                           phase_free=phase_free)[2]
        last[0], last[1], last[2] = list(point), list(parameters), hessian
        return hessian

    return evaluate


def _float_objective(float_residual: Any) -> tuple[Any, Any]:
    """``(x, p) -> (RE, dRE/dx)`` from the closed form in Python floats: the gradient as a
    numpy array, and as a list of floats.

    The exact model's measure of every answer (objective and projected gradient,
    the same for every solver), its saddle checks and SLSQP's objective use it: for
    a few joints it costs less than one call of the CasADi function through numpy
    buffers. IPOPT keeps the CasADi graph (its exact Hessian); the tests check the
    two against each other.
    """

    def floats(x: Any, parameters: Any) -> tuple[float, list[float]]:
        point = x if type(x) is list else np.asarray(x, dtype=float).tolist()
        rho, jacobian = float_residual(point, parameters if type(parameters) is list
                                       else np.asarray(parameters, dtype=float).tolist())
        r1, r2 = 2.0 * rho.real, 2.0 * rho.imag
        return (rho.real * rho.real + rho.imag * rho.imag,
                [r1 * entry.real + r2 * entry.imag for entry in jacobian])

    def evaluate(x: Any, parameters: Any) -> tuple[float, np.ndarray]:
        value, gradient = floats(x, parameters)
        return value, np.array(gradient)

    return evaluate, floats
