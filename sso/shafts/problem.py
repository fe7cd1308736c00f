"""The residual-error NLP of a shaft series as a CasADi graph, built once per shape.

A shape is ``(joints, option, model, quadrature angles)``; the fixed angles enter
as parameters ``p`` and the bounds as ``lbx``/``ubx``, so a new design, new
bounds or a new start reuse the same graph (cached by :func:`sso.solvers.nlp.cached_nlp`).

Up to :data:`sso.limits.QUADRATURE_BLOCK_SAMPLES` angles the objective is one
expression graph (fastest to evaluate); beyond that a block of that many angles
is one CasADi function mapped over the grid, so the graph and its build time do
not grow with the angle count that the bounds call for.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from sso.limits import QUADRATURE_BLOCK_SAMPLES
from sso.shafts.objective import angle_grid, squared_ratio_error
from sso.shafts.options import DesignProblem
from sso.solvers.nlp import CompiledNLP, cached_nlp, compile_nlp


@dataclass(frozen=True)
class ShapeKey:
    """What fixes the structure of the NLP graph."""

    n_joints: int
    option: int
    model: str
    samples: int


def compiled_nlp(problem: DesignProblem, samples: int) -> CompiledNLP:
    """The cached CasADi NLP for the shape of ``problem`` at ``samples`` angles."""
    key = ShapeKey(problem.n_joints, problem.option, problem.model, samples)
    return cached_nlp(key, lambda: _build(problem, key))


def _build(problem: DesignProblem, key: ShapeKey) -> CompiledNLP:
    import casadi

    name = f"sso_re_{key.n_joints}_{key.option}_{key.model}_{key.samples}"
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
