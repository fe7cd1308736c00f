"""sso: Shaft Series Optimisation.

Constrained design of shafts joined in series by Hooke (Cardan) joints, and
kinematic analysis of the planar linkages of three mechanism papers.

The public API is re-exported here lazily: ``import sso`` loads neither CasADi,
SciPy, matplotlib nor dask; each is imported by the first call that needs it.
"""

from importlib import import_module
from typing import Any

__version__ = "0.1.0"

_EXPORTS = {
    "ShaftSeries": "sso.series",
    "Evaluation": "sso.evaluation",
    "optimise": "sso.optimisation",
    "OptimisationResult": "sso.optimisation",
    "Solution": "sso.solvers.solution",
    "CrossCheck": "sso.solvers.solution",
    "sweep": "sso.batch.sweep",
    "SweepResult": "sso.batch.sweep",
    "tolerance": "sso.batch.tolerance",
    "ToleranceResult": "sso.batch.tolerance",
    "design_fourbar": "sso.design.fourbar_swing",
    "FourBarDesignResult": "sso.design.fourbar_swing",
    "InertPhaseWarning": "sso.series",
    "StartMovedWarning": "sso.design.options",
    "QuadratureWarning": "sso.design.quadrature",
}

__all__ = sorted([*_EXPORTS, "__version__"])


def __getattr__(name: str) -> Any:
    module_name = _EXPORTS.get(name)
    if module_name is None:
        raise AttributeError(f"module 'sso' has no attribute {name!r}")
    value = getattr(import_module(module_name), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return __all__
