"""sso: Shaft Series Optimisation.

Constrained design of shafts joined in series by Hooke (Cardan) joints, and
kinematic analysis of the planar linkages of three mechanism papers.

The public API is re-exported here lazily: ``import sso`` loads neither CasADi,
SciPy, matplotlib nor dask; each is imported by the first call that needs it.
"""

from importlib import import_module
from typing import Any

from sso._distribution import VERSION as __version__  # noqa: F401  (in __all__ below)

# Public name -> module that defines it (docs/architecture.md, "Public API").
_EXPORTS: dict[str, str] = {
    "ShaftSeries": "sso._shafts.series",
    "Evaluation": "sso._shafts.evaluation",
    "optimise": "sso._column.dispatch",
    "OptimisationResult": "sso._shafts.optimise",
    "SOLVERS": "sso._limits",
    "optimise_batch": "sso._shafts.batch",
    "BatchResult": "sso._shafts.batch",
    "Solution": "sso._solvers.solution",
    "CrossCheck": "sso._solvers.solution",
    "sweep": "sso._studies.sweep",
    "SweepResult": "sso._studies.results",
    "tolerance_study": "sso._studies.tolerance_study",
    "ToleranceResult": "sso._studies.results",
    "ColumnToleranceResult": "sso._studies.column_tolerance",
    "FourBarDesignResult": "sso._linkages.fourbar_swing",
    "FourBar": "sso._linkages.mechanisms",
    "SliderCrank": "sso._linkages.mechanisms",
    "QuickReturn": "sso._linkages.mechanisms",
    "MechanismTable": "sso._linkages.mechanisms",
    "slider_crank_method_difference": "sso._linkages.mechanisms",
    "ColumnGeometry": "sso._column.geometry",
    "can_cancel": "sso._column.cancel",
    "CancelVerdict": "sso._column.cancel",
    "JointCentresResult": "sso._column.joint_centres",
    "PhasingResult": "sso._column.phasing",
    "SplineResult": "sso._column.splines",
    "ColumnRun": "sso._run.column",
    "run_case": "sso._run.run_case",
    "ShaftSeriesRun": "sso._run.shaft_series",
    "MechanismRun": "sso._run.mechanism_run",
    "YokeInstruction": "sso._column.splines",
    "excitation_table": "sso._column.excitation",
    "ExcitationRow": "sso._column.excitation",
    "ExcitationTable": "sso._column.excitation",
    "equivalent_angles": "sso._column.excitation",
    "EquivalentAngles": "sso._column.excitation",
    "PositionsResult": "sso._column.positions",
    "Tolerances": "sso._column.tolerances",
    "SampleStudy": "sso._column.tolerances",
    "RobustResult": "sso._column.robust_phasing",
    "tolerance_band": "sso._column.band",
    "ToleranceBand": "sso._column.band",
    "Interval": "sso._column.band",
    "re_against_phase_error": "sso._column.band",
    "steering_feel": "sso._column.feel",
    "SteeringFeel": "sso._column.feel",
    "OnCentreResult": "sso._column.feel",
    "steering_range": "sso._column.steering_range",
    "SteeringRange": "sso._column.steering_range",
    "assess_steering": "sso._column.steering_criteria",
    "SteeringAssessment": "sso._column.steering_criteria",
    "SteeringLimits": "sso._column.steering_criteria",
    "practice_notes": "sso._column.practice",
    "PracticeNote": "sso._column.practice",
    "PracticeWarning": "sso._column.practice",
    "InertPhaseWarning": "sso._shafts.series",
    "StartMovedWarning": "sso._shafts.options",
    "QuadratureWarning": "sso._shafts.quadrature",
    "write_report": "sso._reports.kinds",
    "Driveline": "sso._driveline.model",
    "NamedPosition": "sso._driveline.model",
    "Tube": "sso._driveline.tube",
    "analyse_driveline": "sso._driveline.figures",
    "DrivelineResult": "sso._driveline.figures",
    "PhasingAdvice": "sso._driveline.phasing",
    "LayoutBox": "sso._driveline.layout_box",
    "LayoutAdvice": "sso._driveline.layout_advice",
    "DrivelineRun": "sso._run.driveline",
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
