"""A shaft-series case, optimised (``sso run``) or evaluated (``sso evaluate``), as its result.

The result is :class:`ShaftSeriesRun`: the case as read, the optimisation the public
API returned (:func:`sso.optimise`), the designs the report compares (each with its
evaluation and speed curve), the warnings and the package versions. Its report
renders it alone (:mod:`sso._reports.shaft_report`); ``sso report`` reads it back from
``result.json`` with :meth:`ShaftSeriesRun.from_dict`.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import ClassVar

from sso._cases.shaft_series import Case
from sso._display import Part, TextTable, format_number, format_numbers
from sso._progress import Steps
from sso._run.case_run import CaseRun, created_utc, package_versions
from sso._shafts.curves import ComparedDesign, compared_design
from sso._shafts.optimise import OptimisationResult, optimise

MODES = ("optimise", "evaluate")
EVALUATED_VERDICT = "evaluated as given; no optimisation"


@dataclass(frozen=True, eq=False, repr=False)
class ShaftSeriesRun(CaseRun):
    """What one shaft-series case gave.

    Attributes
    ----------
    case : sso._cases.shaft_series.Case
        The case as read, every default filled in.
    mode : {"optimise", "evaluate"}
    optimisation : sso.OptimisationResult or None
        What :func:`sso.optimise` returned (``mode == "optimise"``).
    compared : tuple of ComparedDesign
        The designs beside the optimisation's own: the design as given (evaluate)
        and the case's reference design, if it gives one.
    warnings, versions, created_utc
        As :class:`sso._run.case_run.CaseRun`.
    """

    case: Case
    mode: str
    optimisation: OptimisationResult | None
    compared: tuple[ComparedDesign, ...]

    report_kind: ClassVar[str] = "shaft_series_run"

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise ValueError(f"mode = {self.mode!r}; allowed: {', '.join(MODES)}")
        if (self.optimisation is None) != (self.mode == "evaluate"):
            raise ValueError("an optimise run holds its optimisation; an evaluate run none")
        if not self.designs:
            raise ValueError("compared is empty: a run holds at least the design it started "
                             "from (role 'initial')")

    @property
    def designs(self) -> tuple[ComparedDesign, ...]:
        """Every design the report compares: initial, optimum (if any), reference (if any)."""
        own = () if self.optimisation is None else self.optimisation.compared
        return (*own, *self.compared)

    def design(self, role: str) -> ComparedDesign | None:
        """The design of ``role`` (``"initial"``, ``"optimum"``, ``"reference"``), or None."""
        return next((design for design in self.designs if design.role == role), None)

    @property
    def success(self) -> bool:
        """True for an evaluation, and for an optimisation that succeeded."""
        return self.optimisation is None or self.optimisation.success

    @property
    def verdict(self) -> str:
        """The run's verdict in words."""
        return EVALUATED_VERDICT if self.optimisation is None else self.optimisation.verdict

    def _repr_text(self) -> str:
        figures = ", ".join(f"{design.role} RE {format_number(design.evaluation.residual_error, 4)}"
                            for design in self.designs)
        status = "OK" if self.success else "FAILED"
        return f"case {self.case.name!r}, {self.mode}, {status}: {figures}"

    def _summary_parts(self) -> list[Part]:
        rows = tuple((design.label, format_numbers(design.series.beta_deg),
                      format_numbers(design.series.phase_deg),
                      format_number(design.evaluation.residual_error))
                     for design in self.designs)
        return [f"Case {self.case.name} ({self.mode}): {'OK' if self.success else 'FAILED'}: "
                f"{self.verdict}",
                TextTable(("design", "beta (deg)", "phase (deg)", "RE"), rows)]


def run_shaft_series(case: Case, optimising: bool) -> ShaftSeriesRun:
    """Optimise (``sso run``) or evaluate (``sso evaluate``) a shaft-series case.

    Solver failures and disagreements are recorded in the result, never raised;
    warnings are recorded in it, not emitted. An evaluation builds no NLP and
    imports no CasADi.

    Raises
    ------
    ValueError
        If the public API refuses the case's values.
    """
    options = {"quadrature_rtol": case.quadrature_rtol, "quadrature_atol": case.quadrature_atol}
    compared: list[ComparedDesign] = []
    optimisation = None
    reference = case.reference_series()
    names = ["optimisation" if optimising else "evaluation",
             *(["reference"] if reference is not None else [])]
    with Steps(case.name, names) as steps, warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if optimising:
            optimisation = optimise(case.series(), case.option, **case.optimise_options())
            optimisation.compared  # noqa: B018 - the curves are computed with the run
        else:
            series = case.series()
            compared.append(compared_design(
                "initial", "design (as given)", series,
                series.evaluate(case.input_speed_rpm, **options)))
        steps.finished()
        if reference is not None:
            compared.append(compared_design(
                "reference", case.reference_label, reference,
                reference.evaluate(case.input_speed_rpm, **options)))
            steps.finished()
    noted = [*case.warnings, *(optimisation.warnings if optimisation else ()),
             *(str(warning.message) for warning in caught)]
    return ShaftSeriesRun(case=case, mode="optimise" if optimising else "evaluate",
                          optimisation=optimisation, compared=tuple(compared),
                          warnings=tuple(dict.fromkeys(noted)), versions=package_versions(),
                          created_utc=created_utc())
