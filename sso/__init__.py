"""sso: Shaft Series Optimisation.

Constrained design of shafts joined in series by Hooke (Cardan) joints, and
kinematic analysis of the planar linkages of three mechanism papers.

The public API is re-exported here lazily: ``import sso`` loads neither CasADi,
SciPy, matplotlib nor dask; each is imported by the first call that needs it.
"""

from importlib import import_module
from typing import Any

__version__ = "0.1.0"

# Public name -> module that defines it, or (module, name there) for an alias.
_EXPORTS: dict[str, str | tuple[str, str]] = {
    "ShaftSeries": "sso.shafts.series",
    "Evaluation": "sso.shafts.evaluation",
    "optimise": "sso.column.dispatch",
    "OptimisationResult": "sso.shafts.optimise",
    "SOLVERS": "sso.limits",
    "optimise_batch": "sso.shafts.batch",
    "BatchResult": "sso.shafts.batch",
    "Solution": "sso.solvers.solution",
    "CrossCheck": "sso.solvers.solution",
    "sweep": "sso.batch.sweep",
    "SweepResult": "sso.batch.results",
    "tolerance_study": "sso.batch.tolerance_study",
    "tolerance": ("sso.batch.tolerance_study", "tolerance_study"),
    "ToleranceResult": "sso.batch.results",
    "design_fourbar": "sso.linkages.fourbar_swing",
    "FourBarDesignResult": "sso.linkages.fourbar_swing",
    "FourBar": "sso.linkages.mechanisms",
    "SliderCrank": "sso.linkages.mechanisms",
    "QuickReturn": "sso.linkages.mechanisms",
    "MechanismTable": "sso.linkages.mechanisms",
    "slider_crank_method_difference": "sso.linkages.mechanisms",
    "ColumnGeometry": "sso.column.geometry",
    "can_cancel": "sso.column.cancel",
    "CancelVerdict": "sso.column.cancel",
    "optimise_phasing": "sso.column.phasing",
    "optimise_joint_positions": "sso.column.joint_positions",
    "JointPositionResult": "sso.column.joint_positions",
    "PhasingResult": "sso.column.phasing",
    "best_spline_teeth": "sso.column.splines",
    "SplineResult": "sso.column.splines",
    "YokeInstruction": "sso.column.splines",
    "excitation_table": "sso.column.excitation",
    "ExcitationRow": "sso.column.excitation",
    "ExcitationTable": "sso.column.excitation",
    "equivalent_angles": "sso.column.excitation",
    "EquivalentAngles": "sso.column.excitation",
    "optimise_positions": "sso.column.positions",
    "PositionsResult": "sso.column.positions",
    "Tolerances": "sso.column.tolerances",
    "SampleStudy": "sso.column.tolerances",
    "optimise_robust": "sso.column.robust_phasing",
    "RobustResult": "sso.column.robust_phasing",
    "tolerance_band": "sso.column.band",
    "ToleranceBand": "sso.column.band",
    "Interval": "sso.column.band",
    "re_against_phase_error": "sso.column.band",
    "steering_feel": "sso.column.feel",
    "SteeringFeel": "sso.column.feel",
    "optimise_on_centre": "sso.column.feel",
    "OnCentreResult": "sso.column.feel",
    "steering_range": "sso.column.steering_range",
    "SteeringRange": "sso.column.steering_range",
    "assess_steering": "sso.column.steering_criteria",
    "SteeringAssessment": "sso.column.steering_criteria",
    "SteeringLimits": "sso.column.steering_criteria",
    "practice_notes": "sso.column.practice",
    "PracticeNote": "sso.column.practice",
    "PracticeWarning": "sso.column.practice",
    "InertPhaseWarning": "sso.shafts.series",
    "StartMovedWarning": "sso.shafts.options",
    "QuadratureWarning": "sso.shafts.quadrature",
    "write_report": "sso.reports.kinds",
}

__all__ = sorted([*_EXPORTS, "__version__"])


def __getattr__(name: str) -> Any:
    where = _EXPORTS.get(name)
    if where is None:
        raise AttributeError(f"module 'sso' has no attribute {name!r}")
    module_name, attribute = (where, name) if isinstance(where, str) else where
    value = getattr(import_module(module_name), attribute)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return __all__
