"""The residual-error NLP as a CasADi graph, built once per shape and reused.

A shape is ``(joints, option, model, quadrature angles)``; the fixed angles enter
as parameters ``p`` and the bounds as ``lbx``/``ubx``, so a new design, new
bounds or a new start reuse the same graph. Each thread gets its own cache: a
CasADi function object is never shared between threads.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field
from typing import Any, Callable, Hashable

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
    """CasADi functions of one problem shape, shared by every solver.

    Attributes
    ----------
    name : str
        Name given to the CasADi functions.
    symbols : dict
        ``{"x", "p", "f"}`` and ``"g"`` when there are constraints.
    objective_and_gradient : casadi.Function
        ``(x, p) -> (f, df/dx)``, used by SLSQP and by the optimality measure.
    constraints_and_jacobian : casadi.Function or None
        ``(x, p) -> (g, dg/dx)`` when the problem has constraint functions.
    ipopt_solvers : dict
        ``nlpsol`` instances keyed by their option tuple, built on first use.
    """

    name: str
    symbols: dict[str, Any]
    objective_and_gradient: Any
    constraints_and_jacobian: Any = None
    ipopt_solvers: dict[tuple, Any] = field(default_factory=dict)

    def ipopt(self, options: dict[str, Any]) -> Any:
        """The IPOPT ``nlpsol`` for these options (exact Hessian), built once."""
        import casadi

        options_key = tuple(sorted(options.items()))
        solver = self.ipopt_solvers.get(options_key)
        if solver is None:
            solver = casadi.nlpsol(
                f"{self.name}_ipopt",
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
    return cached_nlp(key, lambda: _build(problem, key))


def cached_nlp(key: Hashable, build: Callable[[], CompiledNLP]) -> CompiledNLP:
    """This thread's NLP for ``key``, built by ``build()`` the first time."""
    cache = getattr(_cache, "nlps", None)
    if cache is None:
        cache = _cache.nlps = {}
    nlp = cache.get(key)
    if nlp is None:
        nlp = cache[key] = build()
    return nlp


def compile_nlp(name: str, x: Any, p: Any, objective: Any, constraints: Any = None) -> CompiledNLP:
    """Wrap CasADi symbols of an NLP into the functions the solvers use.

    Parameters
    ----------
    name : str
        Name of the CasADi functions.
    x, p : casadi.SX
        Design variables and parameters (column vectors).
    objective : casadi.SX
        Scalar objective.
    constraints : casadi.SX, optional
        Constraint functions ``g(x, p)``, bounded per solve.
    """
    import casadi

    symbols = {"x": x, "p": p, "f": objective}
    objective_and_gradient = casadi.Function(f"{name}_f", [x, p],
                                             [objective, casadi.gradient(objective, x)],
                                             ["x", "p"], ["f", "grad"])
    constraints_and_jacobian = None
    if constraints is not None:
        symbols["g"] = constraints
        constraints_and_jacobian = casadi.Function(f"{name}_g", [x, p],
                                                   [constraints, casadi.jacobian(constraints, x)],
                                                   ["x", "p"], ["g", "jac"])
    return CompiledNLP(name=name, symbols=symbols, objective_and_gradient=objective_and_gradient,
                       constraints_and_jacobian=constraints_and_jacobian)


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
