"""A column case, optimised (``sso run``) or analysed as built (``sso evaluate``), as its result.

The result is :class:`ColumnRun`: the case as read, the geometry, whether phasing can
cancel, every assembly the report compares, and the results the public API returns
for the case (:class:`sso.PhasingResult`, :class:`sso.SplineResult`,
:class:`sso.JointCentresResult`, the robust part of :mod:`sso._run.column_robust`,
:class:`sso.ExcitationTable` and :class:`sso.SteeringAssessment`), with the warnings
and the package versions. Its report renders it alone
(:mod:`sso._reports.column_report`); ``sso report`` reads it back from
``result.json`` with :meth:`ColumnRun.from_dict`.

The assemblies are every phasing the report compares: as built, in phase, the
textbook correction, the best continuous phasing and the best on the splines. The
excitation is tabulated for the one as built and for the recommended one (best on
the splines when teeth are given, else the best continuous phasing).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from sso._cases.column import ColumnCase
from sso._column.cancel import CancelVerdict, can_cancel
from sso._column.chain_matrix import residual_error
from sso._column.excitation import ExcitationTable, excitation_table
from sso._column.geometry import ColumnGeometry, wrap_half_turn
from sso._column.joint_centres import JointCentresResult, optimise_joint_centres
from sso._column.phasing import PhasingResult, optimise_phasing
from sso._column.splines import SplineResult, best_spline_teeth
from sso._column.steering_criteria import SteeringAssessment, assess_steering
from sso._column.yields import YieldJudgement
from sso._display import Part, TextTable, format_number, format_numbers
from sso._progress import Steps
from sso._record import register_record
from sso._run.case_run import CaseRun, created_utc, package_versions
from sso._run.column_robust import ColumnRobustPart, has_robust_part, robust_part
from sso._run.signed_figures import SignedFigure, figure_lines, signed_figures

MODES = ("optimise", "evaluate")
ANALYSED_VERDICT = "assembly as built analysed; no optimisation"
MOVED_LABEL = "joints moved within their boxes"


@register_record
@dataclass(frozen=True)
class Assembly:
    """One yoke phasing of the column that the report compares.

    Attributes
    ----------
    role : str
        ``"as_built"``, ``"in_phase"``, ``"textbook"``, ``"best"`` or ``"splines"``.
    label : str
        Its name in words.
    yoke_phase_deg : tuple of float
        Yoke phasing per intermediate shaft, deg (fitter's convention).
    phase_deg : tuple of float
        The model phases it gives, deg.
    residual_error : float
        RE of the column at its hardpoints with this phasing.
    """

    role: str
    label: str
    yoke_phase_deg: tuple[float, ...]
    phase_deg: tuple[float, ...]
    residual_error: float


@dataclass(frozen=True)
class RunFigure:
    """RE of one design of a run, as the command's closing table shows it.

    Attributes
    ----------
    label : str
    residual_error : float
    objective : str or None
        The objective the recommended teeth were searched for when it is not RE (a
        column with positions, tolerances or a steering feel), else None.
    objective_at_teeth, objective_continuous : float or None
        That objective at the teeth and at the continuous phasing.
    """

    label: str
    residual_error: float
    objective: str | None = None
    objective_at_teeth: float | None = None
    objective_continuous: float | None = None


@dataclass(frozen=True, eq=False, repr=False)
class ColumnRun(CaseRun):
    """What one column case gave (``sso run`` or ``sso evaluate`` of a column case file).

    Its parts are the objects the Python API returns for the same column, so a report
    is drawn from them alone; ``sso.write_report(run, folder)`` writes the column
    report and ``ColumnRun.from_dict`` reads a saved ``result.json`` back.

    Attributes
    ----------
    case : ColumnCase
        The case as read, every default filled in.
    mode : {"optimise", "evaluate"}
    geometry : sso.ColumnGeometry
        The column at ``hardpoints.points_mm`` (in the ``[tilt]`` position, if given).
    cancel : sso.CancelVerdict
        Whether phasing can cancel the fluctuation (:func:`sso.can_cancel`).
    assemblies : tuple of Assembly
        Every phasing compared (module notes), the one as built first.
    phasing : sso.PhasingResult or None
        The best continuous phasing (:func:`sso.optimise`; ``mode == "optimise"``).
    splines : sso.SplineResult or None
        The teeth recommended to the fitter (``[splines]``): for RE at the
        hardpoints, or for the case's own objective when it has positions,
        tolerances or a steering feel (``splines.objective`` says which).
    nominal_splines : sso.SplineResult or None
        The best teeth for RE at the hardpoints, when ``splines`` are for another
        objective.
    joint_centres : sso.JointCentresResult or None
        The joints moved within their boxes (``[joint_boxes]``, ``mode == "optimise"``).
    robust : ColumnRobustPart or None
        Positions, tolerances, band and steering feel, as the case asks.
    excitation : dict of str to sso.ExcitationTable
        By assembly role: the one as built and the recommended one.
    steering : sso.SteeringAssessment
        Steering figures and criteria of every assembly and robust design.
    recommended : str
        Role of the assembly recommended to the fitter.
    success : bool
        Every solver run succeeded and agreed.
    verdict : str
        Each solver's verdict in words.
    warnings, versions, created_utc
        As :class:`sso._run.case_run.CaseRun`.
    """

    case: ColumnCase
    mode: str
    geometry: ColumnGeometry
    cancel: CancelVerdict
    assemblies: tuple[Assembly, ...]
    phasing: PhasingResult | None
    splines: SplineResult | None
    nominal_splines: SplineResult | None
    joint_centres: JointCentresResult | None
    robust: ColumnRobustPart | None
    excitation: dict[str, ExcitationTable]
    steering: SteeringAssessment
    recommended: str
    success: bool
    verdict: str

    report_kind: ClassVar[str] = "column_run"

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise ValueError(f"mode = {self.mode!r}; allowed: {', '.join(MODES)}")
        if (self.phasing is None) != (self.mode == "evaluate"):
            raise ValueError("an optimise run holds its phasing; an evaluate run none")
        roles = [assembly.role for assembly in self.assemblies]
        if not roles or roles[0] != "as_built":
            raise ValueError(f"assemblies[0].role = {roles[0] if roles else None!r}; the "
                             "assembly as built comes first")
        for name, role in (("recommended", self.recommended),
                           *(("excitation", key) for key in self.excitation)):
            if role not in roles:
                raise ValueError(f"{name} = {role!r} names no assembly; allowed: "
                                 f"{', '.join(roles)}")

    def assembly(self, role: str) -> Assembly:
        """The assembly of ``role``.

        Raises
        ------
        KeyError
            If the run compares no assembly of that role.
        """
        for assembly in self.assemblies:
            if assembly.role == role:
                return assembly
        raise KeyError(f"no assembly {role!r}; the run has "
                       f"{', '.join(item.role for item in self.assemblies)}")

    @property
    def initial(self) -> RunFigure:
        """The assembly as built."""
        as_built = self.assembly("as_built")
        return RunFigure(as_built.label, as_built.residual_error)

    @property
    def optimum(self) -> RunFigure | None:
        """The recommended design, or None for an analysis: the recommended assembly,
        or the moved joints where they reach a lower RE; on the splines for an objective
        of its own, that objective at the teeth and at the continuous phasing."""
        if self.recommended == "as_built":
            return None
        best = self.assembly(self.recommended)
        value, label = best.residual_error, best.label
        moved = self.joint_centres
        if moved is not None and moved.fun < value:
            value, label = moved.fun, MOVED_LABEL
        splines = self.splines
        if self.recommended == "splines" and splines is not None and splines.objective != "RE":
            return RunFigure(label, value, splines.objective, splines.residual_error,
                             splines.continuous_residual_error)
        return RunFigure(label, value)

    @property
    def recommended_yields(self) -> YieldJudgement | None:
        """The yields of the recommended assembly's built columns against the case's
        ``[limits]`` (the ``[tolerances]`` sample), or None without ``[tolerances]``."""
        return self._yields_of(self.recommended)

    @property
    def judged_yields(self) -> YieldJudgement | None:
        """The yields the run is judged by (``sso run`` and ``sso evaluate`` exit 1 unless
        they are signed off): the recommended assembly's when optimising, the assembly's
        as built when evaluating (:attr:`judged_columns`); None without ``[tolerances]``."""
        return self._yields_of(self.recommended if self.mode == "optimise" else "as_built")

    @property
    def judged_columns(self) -> str:
        """Whose built columns :attr:`judged_yields` counts, in words."""
        return ("the recommended assembly's built columns" if self.mode == "optimise"
                else "the built columns of the assembly as built")

    def _yields_of(self, role: str) -> YieldJudgement | None:
        """The yields of the built columns of the assembly of ``role``, or None."""
        if self.robust is None:
            return None
        chosen = self.assembly(role).yoke_phase_deg
        for design in self.robust.designs:
            if design.yields is not None and design.yoke_phase_deg == chosen:
                return design.yields
        return None

    @property
    def signed_figures(self) -> tuple[SignedFigure, ...]:
        """The figures an engineer signs, as given and recommended (the same design
        twice for an analysis): fluctuation, transmission error, excitation at the top
        speed, then RE (:mod:`sso._run.signed_figures`)."""
        designs = {design.role: design for design in self.steering.designs}
        role = self.recommended
        return signed_figures(designs["as_built"], designs[role], self.excitation["as_built"],
                              self.excitation[role],
                              (self.assembly("as_built").residual_error,
                               self.assembly(role).residual_error))

    @property
    def headline(self) -> tuple[str, str | None]:
        """The signed figures in one line (as given to recommended), and the trade of
        the design recommended in another (None when it makes nothing worse)."""
        return figure_lines(self.signed_figures, self.recommended != "as_built")

    def _repr_text(self) -> str:
        optimum = self.optimum
        figures = f"as built RE {format_number(self.initial.residual_error, 4)}" + (
            "" if optimum is None else f", optimum RE {format_number(optimum.residual_error, 4)}")
        status = "OK" if self.success else "FAILED"
        return f"case {self.case.name!r}, column, {self.mode}, {status}: {figures}"

    def _summary_parts(self) -> list[Part]:
        rows = tuple((assembly.label, format_numbers(assembly.yoke_phase_deg),
                      format_number(assembly.residual_error))
                     for assembly in self.assemblies)
        yields = self.judged_yields
        figures, trade = self.headline
        compared = ("" if self.recommended == "as_built" else
                    f" (as built to {self.assembly(self.recommended).label})")
        return [f"Case {self.case.name} (column, {self.mode}): "
                f"{'OK' if self.success else 'FAILED'}: {figures}{compared}",
                *([trade] if trade is not None else []),
                TextTable(("assembly", "yoke phasing delta (deg)", "RE"), rows),
                f"recommended: {self.assembly(self.recommended).label}",
                *([] if yields is None else [f"{self.judged_columns} ([tolerances] "
                                             f"sample): {yields.sentence}"]),
                f"numerics: {self.verdict}"]


def run_column(case: ColumnCase, optimising: bool) -> ColumnRun:
    """Optimise (``sso run``) or analyse as built (``sso evaluate``) a column case.

    Solver failures and disagreements are recorded in the result, never raised;
    warnings are recorded in it, not emitted.

    Raises
    ------
    ValueError
        If the public API refuses the case's values.
    """
    geometry = case.geometry()
    as_built = case.values["phasing.yoke_phase_deg"]
    assemblies = [
        _assembly(geometry, "as_built", "as built (phasing.yoke_phase_deg)", as_built),
        _assembly(geometry, "in_phase", "yokes in phase (delta = 0)",
                  [0.0] * (geometry.joint_count - 1)),
        _assembly(geometry, "textbook", "textbook correction (delta = gamma, phi = 90)",
                  [float(value) for value in wrap_half_turn(geometry.plane_angle_deg)]),
    ]
    verdicts: list[str] = []
    success = True
    recommended = "as_built"
    phasing = moved = robust = splines = nominal_splines = None
    with Steps(case.name, _steps(case, optimising)) as steps:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            if optimising:
                phasing = optimise_phasing(geometry, **case.solver_options())
                # the set's ends are found with the run
                phasing.exact_optimum_extent_deg  # noqa: B018
                assemblies.append(_assembly(geometry, "best", "best yoke phasing (continuous)",
                                            phasing.yoke_phase_deg))
                success = success and phasing.success
                verdicts.append(f"phasing: {phasing.message}")
                recommended = "best"
                steps.finished()
            if optimising and case.has_joint_boxes:
                moved = optimise_joint_centres(geometry, **case.joint_position_options())
                success = success and moved.success
                verdicts.append(f"joint positions: {moved.message}")
                steps.finished()
            teeth_assembly = None
            if has_robust_part(case):
                outcome = robust_part(case, optimising, list(as_built), phasing)
                robust = outcome.part
                success = success and outcome.success
                verdicts += outcome.verdicts
                teeth_assembly = outcome.teeth
                steps.finished()
            if case.teeth is not None:
                splines = best_spline_teeth(geometry, case.teeth)
                label = "best on the splines (whole teeth)"
                if teeth_assembly is not None:
                    # the fitter gets the teeth of the objective the case optimised
                    nominal_splines = splines
                    label, splines = teeth_assembly
                assemblies.append(_assembly(geometry, "splines", label, splines.yoke_phase_deg))
                recommended = "splines"
                steps.finished()
            by_role = {assembly.role: assembly for assembly in assemblies}
            excitation = {role: excitation_table(geometry.series(by_role[role].yoke_phase_deg),
                                                 case.excitation_speeds_rpm(),
                                                 case.values["excitation.vehicle"],
                                                 case.values["excitation.application"])
                          for role in dict.fromkeys(("as_built", recommended))}
            steps.finished()
        steering = _steering(geometry, case, assemblies, robust)
        steps.finished()
    return ColumnRun(
        case=case, mode="optimise" if optimising else "evaluate", geometry=geometry,
        cancel=can_cancel(geometry.beta_deg), assemblies=tuple(assemblies), phasing=phasing,
        splines=splines, nominal_splines=nominal_splines, joint_centres=moved, robust=robust,
        excitation=excitation, steering=steering,
        recommended=recommended, success=success,
        verdict="; ".join(verdicts) if verdicts else ANALYSED_VERDICT,
        warnings=tuple(dict.fromkeys([*case.warnings, *(str(item.message) for item in caught)])),
        versions=package_versions(), created_utc=created_utc())


def _steps(case: ColumnCase, optimising: bool) -> list[str]:
    """What a run of ``case`` does, in order (the steps of its progress bar)."""
    optional = ((optimising, "phasing"), (optimising and case.has_joint_boxes, "joint positions"),
                (has_robust_part(case), "positions, tolerances and feel"),
                (case.teeth is not None, "spline teeth"))
    return [name for wanted, name in optional if wanted] + ["excitation", "steering figures"]


def _assembly(geometry: ColumnGeometry, role: str, label: str,
              yoke_phase_deg: Sequence[float]) -> Assembly:
    yoke = tuple(float(value) for value in yoke_phase_deg)
    phase = geometry.phase_deg_from_yoke(yoke)
    value = float(residual_error(np.radians(geometry.beta_deg), np.radians(phase)))
    return Assembly(role, label, yoke, tuple(float(angle) for angle in phase), value)


def _steering(geometry: ColumnGeometry, case: ColumnCase, assemblies: Sequence[Assembly],
              robust: ColumnRobustPart | None) -> SteeringAssessment:
    """Steering figures and criteria of every assembly, and of the robust part's designs
    not among them (by role, or by name and phasing: the assembly recommended on the
    splines is often one of the robust designs' teeth, and is listed once)."""
    designs = [(assembly.role, assembly.label, assembly.yoke_phase_deg)
               for assembly in assemblies]
    roles = {assembly.role for assembly in assemblies} | {"nominal"}
    listed = {(assembly.label, assembly.yoke_phase_deg) for assembly in assemblies}
    designs += [(design.role, design.label, design.yoke_phase_deg)
                for design in (robust.designs if robust is not None else ())
                if design.role not in roles
                and (design.label, design.yoke_phase_deg) not in listed]
    return assess_steering(geometry, designs, limits=case.steering_limits(),
                           **case.steering_options())
