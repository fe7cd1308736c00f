"""The residual-error NLP as a CasADi graph, built once per shape and reused.

A shape is ``(joints, option, model, quadrature angles)``; the fixed angles enter
as parameters ``p`` and the bounds as ``lbx``/``ubx``, so a new design, new
bounds or a new start reuse the same graph. Each thread gets its own cache: a
CasADi function object is never shared between threads.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field
from typing import Any

from sso.design.objective import angle_grid, squared_ratio_error
from sso.design.options import DesignProblem

_cache = threading.local()


@dataclass(frozen=True)
class ShapeKey:
    """What fixes the structure of the NLP graph."""

    n_joints: int
    option: int
    model: str
    samples: int


@dataclass
class CompiledNLP:
    """CasADi functions of one shape.

    Attributes
    ----------
    objective_and_gradient : casadi.Function
        ``(x, p) -> (RE, dRE/dx)``, used by SLSQP and by the optimality measure.
    ipopt_solvers : dict
        ``nlpsol`` instances keyed by their option tuple, built on first use.
    """

    key: ShapeKey
    symbols: dict[str, Any]
    objective_and_gradient: Any
    ipopt_solvers: dict[tuple, Any] = field(default_factory=dict)

    def ipopt(self, options: dict[str, Any]) -> Any:
        """The IPOPT ``nlpsol`` for these options (exact Hessian), built once."""
        import casadi

        options_key = tuple(sorted(options.items()))
        solver = self.ipopt_solvers.get(options_key)
        if solver is None:
            solver = casadi.nlpsol(
                f"sso_ipopt_{self.key.n_joints}_{self.key.option}_{self.key.model}",
                "ipopt",
                self.symbols,
                {
                    "print_time": False,
                    "error_on_fail": False,
                    "ipopt": {"print_level": 0, "sb": "yes", **options},
                },
            )
            self.ipopt_solvers[options_key] = solver
        return solver


def compiled_nlp(problem: DesignProblem, samples: int) -> CompiledNLP:
    """The cached CasADi NLP for the shape of ``problem`` at ``samples`` angles."""
    key = ShapeKey(problem.n_joints, problem.option, problem.model, samples)
    cache = getattr(_cache, "nlps", None)
    if cache is None:
        cache = _cache.nlps = {}
    nlp = cache.get(key)
    if nlp is None:
        nlp = cache[key] = _build(problem, key)
    return nlp


def _build(problem: DesignProblem, key: ShapeKey) -> CompiledNLP:
    import casadi

    x = casadi.SX.sym("x", problem.n_free)
    p = casadi.SX.sym("p", len(problem.parameters_rad))
    beta, phase = problem.split([x[i] for i in range(problem.n_free)],
                                [p[i] for i in range(p.numel())])
    cos_theta, sin_theta = angle_grid(key.samples)
    terms = squared_ratio_error(casadi, casadi.DM(cos_theta), casadi.DM(sin_theta), beta,
                                phase, key.model)
    objective = casadi.sum1(terms) / key.samples
    gradient = casadi.gradient(objective, x)
    objective_and_gradient = casadi.Function("re_and_gradient", [x, p], [objective, gradient],
                                             ["x", "p"], ["f", "grad"])
    return CompiledNLP(key=key, symbols={"x": x, "p": p, "f": objective},
                       objective_and_gradient=objective_and_gradient)
