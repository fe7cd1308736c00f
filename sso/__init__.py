"""sso: Shaft Series Optimisation.

Constrained design of shafts joined in series by Hooke (Cardan) joints, and
kinematic analysis of the planar linkages of three mechanism papers.

The public API is re-exported here lazily: ``import sso`` loads neither CasADi,
SciPy, matplotlib nor dask; each is imported by the first call that needs it.
"""

from importlib import import_module
from typing import Any

from sso.distribution import VERSION as __version__  # noqa: F401  (in __all__ below)

# Public name -> module that defines it (docs/architecture.md, "Public API").
_EXPORTS: dict[str, str] = {
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
    "ToleranceResult": "sso.batch.results",
    "ColumnToleranceResult": "sso.batch.column_tolerance",
    "FourBarDesignResult": "sso.linkages.fourbar_swing",
    "FourBar": "sso.linkages.mechanisms",
    "SliderCrank": "sso.linkages.mechanisms",
    "QuickReturn": "sso.linkages.mechanisms",
    "MechanismTable": "sso.linkages.mechanisms",
    "slider_crank_method_difference": "sso.linkages.mechanisms",
    "ColumnGeometry": "sso.column.geometry",
    "can_cancel": "sso.column.cancel",
    "CancelVerdict": "sso.column.cancel",
    "JointCentresResult": "sso.column.joint_positions",
    "PhasingResult": "sso.column.phasing",
    "SplineResult": "sso.column.splines",
    "YokeInstruction": "sso.column.splines",
    "excitation_table": "sso.column.excitation",
    "ExcitationRow": "sso.column.excitation",
    "ExcitationTable": "sso.column.excitation",
    "equivalent_angles": "sso.column.excitation",
    "EquivalentAngles": "sso.column.excitation",
    "PositionsResult": "sso.column.positions",
    "Tolerances": "sso.column.tolerances",
    "SampleStudy": "sso.column.tolerances",
    "RobustResult": "sso.column.robust_phasing",
    "tolerance_band": "sso.column.band",
    "ToleranceBand": "sso.column.band",
    "Interval": "sso.column.band",
    "re_against_phase_error": "sso.column.band",
    "steering_feel": "sso.column.feel",
    "SteeringFeel": "sso.column.feel",
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
    value = getattr(import_module(where), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return __all__
