"""The residual-error NLP of a shaft series as a CasADi graph, built once per shape.

A shape is ``(joints, option, model, quadrature angles)``; the fixed angles enter
as parameters ``p`` and the bounds as ``lbx``/``ubx``, so a new design, new
bounds or a new start reuse the same graph (cached by :func:`sso.solvers.nlp.cached_nlp`).
"""

from __future__ import annotations

from dataclasses import dataclass

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

    x = casadi.SX.sym("x", problem.n_free)
    p = casadi.SX.sym("p", len(problem.parameters_deg))
    beta, phase = problem.split([x[i] for i in range(problem.n_free)],
                                [p[i] for i in range(p.numel())])
    cos_theta, sin_theta = angle_grid(key.samples)
    terms = squared_ratio_error(casadi, casadi.DM(cos_theta), casadi.DM(sin_theta), beta,
                                phase, key.model)
    objective = casadi.sum1(terms) / key.samples
    return compile_nlp(f"sso_re_{key.n_joints}_{key.option}_{key.model}_{key.samples}", x, p,
                       objective)
