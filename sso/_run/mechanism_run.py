"""A mechanism case, analysed or designed (``sso run``, ``sso evaluate``), as its result.

The result is :class:`MechanismRun`: the case as read, the design the public API
returned (:func:`sso.optimise` of a four-bar, for a ``fourbar_design`` case), and for
each linkage (``given`` for an analysis, ``initial`` and ``optimum`` for a design)
:class:`LinkageCurves`: the table at the case's crank angles, the curves the plots
draw, the positions at the plotted angles and the true extremes. Its report renders
it alone (:mod:`sso._reports.mechanism_report`); ``sso report`` reads it back from
``result.json`` with :meth:`MechanismRun.from_dict`.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from sso._cases.mechanism import DESIGN_KIND, MechanismCase, angle_grid
from sso._display import Part, TextTable, format_number
from sso._linkages.fourbar_swing import FourBarDesignResult, design_fourbar
from sso._linkages.mechanisms import (
    FourBar,
    SliderCrank,
    slider_crank_method_difference,
)
from sso._linkages.registry import Mechanism, OnUnassembled, linkage_of
from sso._linkages.table import MechanismTable
from sso._progress import Steps
from sso._record import Record, register_record
from sso._run.case_run import CaseRun, created_utc, package_versions

FINE_STEP_DEG = 0.1
"""Crank-angle step of the extremes (deg): finer than any paper's grid."""
CURVE_STEP_DEG = 1.0
"""Crank-angle step of the curves the plots draw (deg)."""
MODES = ("analyse", "optimise", "evaluate")
ROLE_NAMES = {"given": "linkage", "initial": "initial linkage", "optimum": "optimum linkage"}


@register_record
@dataclass(frozen=True)
class Extreme:
    """Smallest and largest value of one table column over a crank revolution.

    Attributes
    ----------
    column, unit : str
        The column and its unit (``length`` stands for the case's length unit).
    min, max : float
        The extremes.
    min_at_deg, max_at_deg : float
        Crank angles where they occur, deg.
    """

    column: str
    unit: str
    min: float
    min_at_deg: float
    max: float
    max_at_deg: float


@register_record
@dataclass(frozen=True, eq=False)
class LinkageCurves(Record):
    """One linkage of a mechanism run and everything its report shows of it.

    Attributes
    ----------
    role : {"given", "initial", "optimum"}
    mechanism : a linkage (FourBar, SliderCrank, QuickReturn)
    grashof : str or None
        A four-bar's Grashof class; None for other linkages.
    swing_deg : float or None
        A crank-rocker's rocker swing, deg; None otherwise.
    table : MechanismTable
        At the case's crank angles (a four-bar's with its coupler point's path).
    curve : MechanismTable
        Every :data:`CURVE_STEP_DEG` over at least one revolution from the case's
        start, unassembled angles marked: the lines of the plots.
    positions : MechanismTable
        At the case's ``plots.crank_angles_deg``: the link positions drawn.
    extremes : tuple of Extreme
        Of the main columns, sampled every :data:`FINE_STEP_DEG` over the revolution.
    """

    role: str
    mechanism: Mechanism
    grashof: str | None
    swing_deg: float | None
    table: MechanismTable
    curve: MechanismTable
    positions: MechanismTable
    extremes: tuple[Extreme, ...]

    @property
    def label(self) -> str:
        """How the report names this linkage."""
        return ROLE_NAMES[self.role]


@dataclass(frozen=True, eq=False, repr=False)
class MechanismRun(CaseRun):
    """What one mechanism case gave.

    Attributes
    ----------
    case : sso._cases.mechanism.MechanismCase
        The case as read, every default filled in.
    mode : {"analyse", "optimise", "evaluate"}
        An analysis, a design optimised, or a design's start linkage analysed.
    design : sso.FourBarDesignResult or None
        What :func:`sso.optimise` returned (``mode == "optimise"``).
    linkages : tuple of LinkageCurves
        ``given``, or ``initial`` (and ``optimum``) of a design.
    method_difference : MechanismTable or None
        An in-line slider-crank's exact against series piston motion.
    verdict : str
    warnings, versions, created_utc
        As :class:`sso._run.case_run.CaseRun`.
    """

    case: MechanismCase
    mode: str
    design: FourBarDesignResult | None
    linkages: tuple[LinkageCurves, ...]
    method_difference: MechanismTable | None
    verdict: str

    report_kind: ClassVar[str] = "mechanism_run"

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise ValueError(f"mode = {self.mode!r}; allowed: {', '.join(MODES)}")
        if (self.design is None) != (self.mode != "optimise"):
            raise ValueError("an optimise run holds its design; other runs none")

    @property
    def success(self) -> bool:
        """True for an analysis, and for a design that succeeded."""
        return self.design is None or self.design.success

    @property
    def main(self) -> LinkageCurves:
        """The linkage the report leads with: the optimum of a design, else the first."""
        return next((linkage for linkage in self.linkages if linkage.role == "optimum"),
                    self.linkages[0])

    def _repr_text(self) -> str:
        status = "OK" if self.success else "FAILED"
        return (f"case {self.case.name!r} ({self.case.kind}), {self.mode}, {status}: "
                f"{len(self.main.table)} crank angles")

    def _summary_parts(self) -> list[Part]:
        rows = tuple((linkage.label, ", ".join(
            f"{name} {format_number(value)}" for name, value in vars(linkage.mechanism).items()
            if not isinstance(value, str)), linkage.grashof or "-") for linkage in self.linkages)
        return [f"Case {self.case.name} ({self.case.kind}, {self.mode}): "
                f"{'OK' if self.success else 'FAILED'}: {self.verdict}",
                TextTable(("linkage", f"lengths ({self.case.length_unit})", "Grashof class"),
                          rows)]


def run_mechanism(case: MechanismCase, optimising: bool) -> MechanismRun:
    """Analyse (or design, then analyse) a mechanism case.

    Parameters
    ----------
    case : MechanismCase
        A checked case (:mod:`sso._cases.mechanism`).
    optimising : bool
        For a ``fourbar_design`` case: solve the design problem (``sso run``) or
        only analyse the start linkage (``sso evaluate``). Analysis kinds ignore it.

    Raises
    ------
    ValueError
        If the API refuses the case's values.
    """
    start = case.mechanism()
    caught_messages: list[str] = []
    linkages: dict[str, Mechanism]
    design = None
    designing = case.kind == DESIGN_KIND and optimising
    with Steps(case.name, ["design", "tables"] if designing else ["tables"]) as steps:
        if case.kind != DESIGN_KIND:
            mode, linkages, verdict = "analyse", {"given": start}, _analysis_verdict(case)
        elif optimising:
            if not isinstance(start, FourBar):
                raise TypeError(f"a {DESIGN_KIND} case starts from a FourBar, not {start!r}")
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                design = design_fourbar(start, **case.design_options())
            caught_messages = [str(warning.message) for warning in caught]
            mode, linkages, verdict = "optimise", {"initial": start,
                                                   "optimum": design.optimum}, design.verdict
            steps.finished()
        else:
            mode, linkages = "evaluate", {"initial": start}
            verdict = "start linkage analysed as given; no optimisation"
        difference = None
        if isinstance(start, SliderCrank) and start.offset == 0.0:
            difference = slider_crank_method_difference(
                start.crank, start.rod, case.crank_speed_rad_s, case.crank_angles_deg())
        curves = tuple(linkage_curves(role, mechanism, case)
                       for role, mechanism in linkages.items())
        steps.finished()
    return MechanismRun(
        case=case, mode=mode, design=design, linkages=curves,
        method_difference=difference, verdict=verdict,
        warnings=tuple(dict.fromkeys([*case.warnings, *caught_messages])),
        versions=package_versions(), created_utc=created_utc())


def linkage_curves(role: str, mechanism: Mechanism, case: MechanismCase) -> LinkageCurves:
    """Everything the report shows of one linkage of ``case``."""
    grashof = mechanism.grashof() if isinstance(mechanism, FourBar) else None
    return LinkageCurves(
        role=role, mechanism=mechanism, grashof=grashof,
        swing_deg=(mechanism.swing_angle_deg() if isinstance(mechanism, FourBar)
                   and grashof == "crank-rocker" else None),
        table=analysis_table(mechanism, case),
        curve=analysis_table(mechanism, case, angle_grid(
            case.values["drive.start_deg"], revolution_stop_deg(case), CURVE_STEP_DEG), "mark"),
        positions=analysis_table(mechanism, case, np.asarray(
            case.values["plots.crank_angles_deg"], dtype=float), "mark"),
        extremes=extremes(mechanism, case))


def analysis_table(mechanism: Mechanism, case: MechanismCase,
                   crank_angles_deg: np.ndarray | None = None,
                   on_unassembled: OnUnassembled | None = None) -> MechanismTable:
    """The mechanism's table over the case's crank angles (or ``crank_angles_deg``).

    A four-bar's table gains ``coupler_point_x`` and ``coupler_point_y``: the path
    of the case's coupler point (``plots.coupler_point``, in coupler lengths along
    and to the left of A -> B).
    """
    angles = case.crank_angles_deg() if crank_angles_deg is None else crank_angles_deg
    table = mechanism.analyse(angles, crank_speed=case.crank_speed_rad_s,
                              crank_accel=case.crank_accel_rad_s2,
                              on_unassembled=on_unassembled or case.on_unassembled)
    if not linkage_of(mechanism).coupler_point:
        return table
    if not isinstance(mechanism, FourBar):
        raise TypeError(f"coupler points are computed for a FourBar, not {mechanism!r}")
    point = coupler_point(mechanism, table, case.values["plots.coupler_point"])
    columns = {**table.columns, "coupler_point_x": point.real, "coupler_point_y": point.imag}
    units = {**table.units, "coupler_point_x": "length", "coupler_point_y": "length"}
    return MechanismTable(name=table.name, columns=columns, units=units)


def coupler_point(fourbar: FourBar, table: MechanismTable,
                  point_in_coupler_lengths: tuple[float, float]) -> NDArray[np.complex128]:
    """Positions of a point fixed to the coupler, as complex numbers (length units).

    Parameters
    ----------
    fourbar : FourBar
    table : MechanismTable
        The four-bar's table (joint A and the coupler angle).
    point_in_coupler_lengths : (float, float)
        The point's distance along A -> B and to the left of it, in coupler lengths.
    """
    along, across = point_in_coupler_lengths
    joint_a = table["joint_a_x"] + 1j * table["joint_a_y"]
    direction: NDArray[np.complex128] = np.exp(1j * np.radians(table["coupler_angle_deg"]))
    return joint_a + fourbar.coupler * (along + 1j * across) * direction


def revolution_stop_deg(case: MechanismCase) -> float:
    """End of the curves and extremes: at least one revolution from the case's start (deg)."""
    start, stop = case.values["drive.start_deg"], case.values["drive.stop_deg"]
    return float(max(stop, start + 360.0))


def fine_crank_angles_deg(case: MechanismCase) -> np.ndarray:
    """From the case's start to :func:`revolution_stop_deg` at :data:`FINE_STEP_DEG` (deg)."""
    return angle_grid(case.values["drive.start_deg"], revolution_stop_deg(case), FINE_STEP_DEG)


def extremes(mechanism: Mechanism, case: MechanismCase) -> tuple[Extreme, ...]:
    """Smallest and largest value of the main columns over a whole crank revolution.

    Sampled every :data:`FINE_STEP_DEG` deg from the case's start over at least one
    revolution (:func:`fine_crank_angles_deg`), so the extremes are the true ones to
    that resolution, not the grid samples the papers quote.
    """
    angles = fine_crank_angles_deg(case)
    table = analysis_table(mechanism, case, angles, on_unassembled="mark")
    rows = []
    for column in linkage_of(mechanism).extreme_columns:
        if column not in table.columns:
            continue
        values = np.asarray(table[column], dtype=float)
        if not np.isfinite(values).any():
            continue
        low, high = int(np.nanargmin(values)), int(np.nanargmax(values))
        rows.append(Extreme(column=column, unit=table.units[column], min=float(values[low]),
                            min_at_deg=float(angles[low]), max=float(values[high]),
                            max_at_deg=float(angles[high])))
    return tuple(rows)


def _analysis_verdict(case: MechanismCase) -> str:
    angles = case.crank_angles_deg()
    values = case.values
    return (f"analysed over {len(angles)} crank angles, {values['drive.start_deg']:g} to "
            f"{angles[-1]:g} deg in steps of {values['drive.step_deg']:g} deg, at "
            f"{case.crank_speed_rad_s:g} rad/s and {case.crank_accel_rad_s2:g} rad/s^2")
