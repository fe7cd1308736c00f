"""The robust phasing of a column case: the part :class:`ColumnRobustPart` of its result.

Built when a column case has ``[hardpoints.positions]``, ``[tolerances]``, ``[band]``
or ``[feel]`` (:mod:`sso._cases.column_robust`). It holds the results the public
API returns (:class:`sso.PositionsResult`, :class:`sso.RobustResult`,
:class:`sso.OnCentreResult`, :class:`sso.SampleStudy`, :class:`sso.SteeringFeel`,
:class:`sso.ToleranceBand`, :class:`sso.SplineResult`) and the curves its plots
draw, so its report computes nothing.

Designs compared (every figure is of each one, on ``hardpoints.points_mm`` unless
said): ``sso evaluate`` the assembly as built; ``sso run`` the best phasing (the
nominal optimum), the positions' shared phasing, the tolerance-aware phasing and
the on-centre phasing, as the case asks, each with its whole-teeth assembly when
the case gives ``[splines]``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from sso._cases.column import ColumnCase
from sso._column.band import ToleranceBand, re_against_phase_error, tolerance_band
from sso._column.built_columns import built_angles
from sso._column.built_figures import built_column_figures, limited_figures
from sso._column.chain_matrix import residual_error
from sso._column.feel import (
    OnCentreResult,
    SteeringFeel,
    optimise_on_centre,
    speed_ratio,
    steering_feel,
)
from sso._column.geometry import ColumnGeometry
from sso._column.phasing import PhasingResult
from sso._column.positions import PositionsResult, optimise_positions
from sso._column.robust_phasing import RobustResult, optimise_robust
from sso._column.splines import SplineResult
from sso._column.tolerances import SampleStudy, Tolerances, ToleranceSample, drawn_errors
from sso._column.yields import YieldJudgement, column_limits, judge_yields
from sso._limits import DEFAULT_PHASE_ERROR_POINTS, DEFAULT_PHASE_ERROR_SPAN_DEG
from sso._record import register_record

WHEEL_STEP_DEG = 0.5
"""Steering-wheel step of the speed-ratio curves of the steering feel, deg."""
CANCELLED_OBJECTIVE = 1e-20
"""An on-centre objective at or below this is a cancelled fluctuation (RE ~ 1e-25)."""


@register_record
@dataclass(frozen=True)
class PositionFigures:
    """RE of one design at every named position.

    Attributes
    ----------
    position_re : dict of str to float
        RE at each position.
    worst_re : float
        The largest of them.
    active_positions : tuple of str
        Positions within ``1e-6`` relative of ``worst_re``.
    """

    position_re: dict[str, float]
    worst_re: float
    active_positions: tuple[str, ...]


@register_record
@dataclass(frozen=True)
class RobustDesign:
    """One design the robust part compares, and every figure of it.

    Attributes
    ----------
    role, label : str
        Which design (``"nominal"``, ``"as_built"``, ``"positions"``, ``"robust"``,
        ``"on_centre"``, or one of those with ``"_splines"``) and its name in words.
    yoke_phase_deg : tuple of float
        Its yoke phasing, deg (fitter's convention).
    nominal_re : float
        RE at ``hardpoints.points_mm``.
    splines : sso.SplineResult or None
        The whole-teeth assembly this design is (a ``..._splines`` role).
    positions : PositionFigures or None
        RE at every named position (``[hardpoints.positions]``).
    study : sso.SampleStudy or None
        RE over the case's sample of built columns (``[tolerances]``).
    feel : sso.SteeringFeel or None
        Its steering feel (``[feel]``).
    band : sso.ToleranceBand or None
        Its tolerance band (``[band]``, where the design is within the limit).
    band_note : str or None
        Why it has no band (RE above ``band.re_limit``).
    yields : YieldJudgement or None
        Its built columns (the ``[tolerances]`` sample) against the case's ``[limits]``:
        the yield of each limit and of all together, and the verdict against
        ``[limits] yield`` (:mod:`sso._column.yields`).
    """

    role: str
    label: str
    yoke_phase_deg: tuple[float, ...]
    nominal_re: float
    splines: SplineResult | None = None
    positions: PositionFigures | None = None
    study: SampleStudy | None = None
    feel: SteeringFeel | None = None
    band: ToleranceBand | None = None
    band_note: str | None = None
    yields: YieldJudgement | None = None


@register_record
@dataclass(frozen=True)
class PositionsPart:
    """The named positions and the phasing shared by all of them.

    Attributes
    ----------
    geometries : dict of str to ColumnGeometry
        Each position (``[hardpoints.positions]``).
    result : sso.PositionsResult or None
        What :func:`sso.optimise` of the positions returned (``sso run``).
    """

    geometries: dict[str, ColumnGeometry]
    result: PositionsResult | None


@register_record
@dataclass(frozen=True)
class EquivalentStudy:
    """The tolerance study of one equivalent nominal optimum (a mirror of the best phasing).

    Attributes
    ----------
    yoke_phase_deg : tuple of float
    study : sso.SampleStudy
    """

    yoke_phase_deg: tuple[float, ...]
    study: SampleStudy


@register_record
@dataclass(frozen=True)
class TolerancesPart:
    """The case's tolerances, the tolerance-aware phasing and every design's sample.

    Attributes
    ----------
    tolerances : sso.Tolerances
        The sample's settings (``[tolerances]``).
    robust_objective : str
        ``tolerances.robust_objective``.
    result : sso.RobustResult or None
        What :func:`sso.optimise` with ``tolerances=`` returned (``sso run``).
    samples_re : dict of str to tuple of float
        Per design role, its RE over the sample, sorted (the plot's curve).
    nominal_equivalents : tuple of EquivalentStudy
        The study of every equivalent nominal optimum (``sso run``).
    """

    tolerances: Tolerances
    robust_objective: str
    result: RobustResult | None
    samples_re: dict[str, tuple[float, ...]]
    nominal_equivalents: tuple[EquivalentStudy, ...]


@register_record
@dataclass(frozen=True)
class FeelPart:
    """The steering feel's settings, the on-centre phasing and the speed-ratio curves.

    Attributes
    ----------
    straight_ahead_deg, window_deg, lock_deg, on_centre_weight : float
        ``[feel]``.
    result : sso.OnCentreResult or None
        What :func:`sso.optimise` with ``lock_deg=`` returned (``sso run``), unless
        the nominal optimum already cancels the fluctuation (``note``).
    note : str or None
        Why no on-centre phasing was optimised.
    wheel_deg : tuple of float
        Steering-wheel angles from straight ahead of the curves, deg.
    ratio : dict of str to tuple of float
        Per design role, the speed ratio (output over input) at ``wheel_deg``.
    """

    straight_ahead_deg: float
    window_deg: float
    lock_deg: float
    on_centre_weight: float
    result: OnCentreResult | None
    note: str | None
    wheel_deg: tuple[float, ...]
    ratio: dict[str, tuple[float, ...]]

    @property
    def settings(self) -> dict[str, float]:
        """The keywords of :func:`sso.steering_feel`."""
        return {"straight_ahead_deg": self.straight_ahead_deg, "window_deg": self.window_deg,
                "lock_deg": self.lock_deg, "on_centre_weight": self.on_centre_weight}


@register_record
@dataclass(frozen=True)
class PhaseErrorCurves:
    """RE against each yoke phasing's error, the others at nominal, for every design.

    Attributes
    ----------
    errors_deg : tuple of float
        The errors, deg (:func:`sso.re_against_phase_error`).
    curves : dict of str to dict of str to tuple of float
        Per design role, per phasing (``"yoke_phase_deg[k]"``), RE at each error.
    """

    errors_deg: tuple[float, ...]
    curves: dict[str, dict[str, tuple[float, ...]]]


@register_record
@dataclass(frozen=True)
class ColumnRobustPart:
    """The robust phasing of a column case (module notes).

    Attributes
    ----------
    designs : tuple of RobustDesign
        The designs compared, each with its figures.
    phase_error : PhaseErrorCurves
    positions : PositionsPart or None
    tolerances : TolerancesPart or None
    feel : FeelPart or None
    band_re_limit : float or None
        ``band.re_limit`` (``[band]``).
    """

    designs: tuple[RobustDesign, ...]
    phase_error: PhaseErrorCurves
    positions: PositionsPart | None
    tolerances: TolerancesPart | None
    feel: FeelPart | None
    band_re_limit: float | None


@dataclass(frozen=True)
class RobustOutcome:
    """What :func:`robust_part` gives the column run besides the part itself."""

    part: ColumnRobustPart
    success: bool
    verdicts: tuple[str, ...]
    teeth: tuple[str, SplineResult] | None
    """Label and whole-teeth assembly of the case's own objective (None without teeth
    or optimisation): the first of positions, tolerances, on-centre that the case has."""


def has_robust_part(case: ColumnCase) -> bool:
    """True when the case asks for positions, tolerances, a band or the steering feel."""
    return any(case.values.get(label) is not None
               for label in ("hardpoints.positions", "tolerances.hardpoint_mm",
                             "band.re_limit", "feel.lock_deg"))


def robust_part(case: ColumnCase, optimising: bool, as_built: Sequence[float],
                best: PhasingResult | None) -> RobustOutcome:
    """The robust part of a column case's result, solved through the public API.

    With ``[splines]`` teeth, each robust design (the positions' shared phasing, the
    tolerance-aware one, the on-centre one) gets its whole-teeth assembly, searched
    for its own objective (``on_splines``); the one recommended to the fitter is the
    first of positions, tolerances, on-centre that the case has (the column is used
    at every position; the tolerances and the feel refine one position).

    Parameters
    ----------
    case : ColumnCase
    optimising : bool
        ``sso run`` (optimise the robust designs) or ``sso evaluate`` (figures of
        the assembly as built only).
    as_built : sequence of float
        ``phasing.yoke_phase_deg``.
    best : PhasingResult or None
        The nominal optimum of ``hardpoints.points_mm`` (``sso run``).

    Raises
    ------
    ValueError
        If the API refuses a value (named by its case key).
    """
    geometry = case.geometry()
    options = case.solver_options()
    designs: list[tuple[str, str, tuple[float, ...], SplineResult | None]] = []
    success = True
    verdicts: list[str] = []
    teeth_assemblies: list[tuple[str, SplineResult]] = []

    def add(role: str, label: str, yoke: Sequence[float],
            splines: SplineResult | None = None) -> None:
        designs.append((role, label, tuple(float(value) for value in yoke), splines))

    def add_solved(role: str, label: str, result: Any) -> None:
        nonlocal success
        add(role, label, result.yoke_phase_deg)
        if case.teeth is not None:
            teeth = result.on_splines(case.teeth)
            add(f"{role}_splines", f"{label}, on the splines (whole teeth)",
                teeth.yoke_phase_deg, teeth)
            teeth_assemblies.append((f"{label}, on the splines (whole teeth)", teeth))
        success = success and result.success

    if optimising:
        assert best is not None
        add("nominal", "nominal optimum (best phasing of the hardpoints)", best.yoke_phase_deg)
    else:
        add("as_built", "as built (phasing.yoke_phase_deg)", as_built)
    positions = case.positions()
    positions_part = None
    if positions is not None:
        shared = None
        if optimising:
            objective = case.values["phasing.positions_objective"]
            shared = optimise_positions(positions, positions_objective=objective,
                                        weights=case.values["phasing.position_weights"],
                                        **options)
            add_solved("positions", f"one phasing for every position ({objective})", shared)
            verdicts.append(f"positions: {shared.message}")
        positions_part = PositionsPart(geometries=positions, result=shared)
    tolerances = case.tolerances()
    robust = None
    if tolerances is not None and optimising:
        robust = optimise_robust(geometry, tolerances,
                                 robust_objective=case.values["tolerances.robust_objective"],
                                 **options)
        add_solved("robust", robust.design_label, robust)
        verdicts.append(f"tolerances: {robust.message}")
    feel: dict[str, Any] | None = case.feel_options()
    centred, note = None, None
    if feel is not None and optimising:
        assert best is not None
        least = steering_feel(best, **feel).objective
        if least <= CANCELLED_OBJECTIVE:
            # RE + weight * V cannot go below 0: the cancelling optimum is the
            # on-centre optimum too (its ratio is flat everywhere), and the
            # scaled NLP would have nothing to scale by.
            note = (f"the nominal optimum cancels the fluctuation (objective {least:.3g}): its "
                    "ratio is flat on-centre and at lock, so it is the on-centre phasing too")
        else:
            centred = optimise_on_centre(geometry, **feel, **options)
            add_solved("on_centre", "on-centre (steering feel)", centred)
            verdicts.append(f"steering feel: {centred.message}")
    limit = case.values.get("band.re_limit")
    sample = None if tolerances is None else tolerances.sample(geometry)
    judge = None if tolerances is None else _yield_judge(case, geometry, tolerances)
    compared = tuple(_design(role, label, yoke, splines, geometry, positions, sample, feel, limit,
                             judge)
                     for role, label, yoke, splines in designs)
    tolerances_part = None
    if tolerances is not None:
        assert sample is not None
        tolerances_part = TolerancesPart(
            tolerances=tolerances, robust_objective=case.values["tolerances.robust_objective"],
            result=robust,
            samples_re={design.role: tuple(sorted(float(value) for value in
                                                  sample.residual_error(design.yoke_phase_deg)))
                        for design in compared},
            nominal_equivalents=(() if best is None else _equivalents(geometry, best, sample)))
    feel_part = None
    if feel is not None:
        wheel, ratio = _feel_curves(geometry, compared, feel)
        feel_part = FeelPart(**feel, result=centred, note=note, wheel_deg=wheel, ratio=ratio)
    part = ColumnRobustPart(designs=compared, phase_error=_phase_error(geometry, compared),
                            positions=positions_part, tolerances=tolerances_part,
                            feel=feel_part, band_re_limit=limit)
    return RobustOutcome(part, success, tuple(verdicts),
                         teeth_assemblies[0] if teeth_assemblies else None)


def _design(role: str, label: str, yoke: tuple[float, ...], splines: SplineResult | None,
            geometry: ColumnGeometry, positions: dict[str, ColumnGeometry] | None,
            sample: ToleranceSample | None, feel: dict[str, float] | None,
            limit: float | None,
            judge: Callable[[Sequence[float]], YieldJudgement] | None) -> RobustDesign:
    """One design with every figure the case asks for."""
    nominal = _re_of(geometry, yoke)
    figures = None
    if positions is not None:
        by_name = {name: _re_of(column, yoke) for name, column in positions.items()}
        worst = max(by_name.values())
        figures = PositionFigures(
            position_re=by_name, worst_re=worst,
            active_positions=tuple(name for name, value in by_name.items()
                                   if value >= worst * (1.0 - 1e-6)))
    study = None if sample is None else SampleStudy.of(nominal, sample.residual_error(yoke))
    felt = None if feel is None else steering_feel((geometry, yoke), **feel)
    band, band_note = None, None
    if limit is not None:
        if nominal <= limit:
            band = tolerance_band((geometry, yoke), limit)
        else:
            band_note = (f"RE {nominal:.6g} at the hardpoints is above band.re_limit = "
                         f"{limit:g}: no band")
    return RobustDesign(role=role, label=label, yoke_phase_deg=yoke, nominal_re=nominal,
                        splines=splines, positions=figures, study=study, feel=felt, band=band,
                        band_note=band_note, yields=None if judge is None else judge(yoke))


def _yield_judge(case: ColumnCase, geometry: ColumnGeometry,
                 tolerances: Tolerances) -> Callable[[Sequence[float]], YieldJudgement]:
    """The yields of a design's built columns against the case's limits: the case's
    ``yield_samples`` built columns, drawn from the tolerances' seed as the sample is.

    Raises
    ------
    ValueError
        If a built column is not a column (``hardpoint_mm`` too large for it).
    """
    limits = column_limits(case.steering_limits())
    steering = case.steering_options()
    count = case.yield_samples
    assert count is not None  # the case has [tolerances]
    offsets, phase_errors = drawn_errors(geometry, tolerances, count)
    try:
        beta_deg, gamma_deg = built_angles(np.asarray(geometry.points_mm) + offsets)
    except ValueError as refused:
        raise ValueError(f"tolerances.hardpoint_mm = {tolerances.hardpoint_mm:g} mm is too "
                         f"large for this column: {refused}") from None
    beta_rad = np.radians(beta_deg)

    def judge(yoke: Sequence[float]) -> YieldJudgement:
        phase_rad = np.radians(90.0 + np.asarray(yoke) + phase_errors - gamma_deg)
        figures = built_column_figures(beta_rad, phase_rad, steering["straight_ahead_deg"],
                                       steering["lock_deg"])
        return judge_yields(limited_figures(beta_deg, figures), limits, case.required_yield)

    return judge


def _re_of(column: ColumnGeometry, yoke: Sequence[float]) -> float:
    return float(residual_error(np.radians(column.beta_deg),
                                np.radians(column.phase_deg_from_yoke(yoke))))


def _equivalents(geometry: ColumnGeometry, best: PhasingResult,
                 sample: ToleranceSample) -> tuple[EquivalentStudy, ...]:
    """The tolerance study of every equivalent nominal optimum (mirror solutions reach
    the same nominal RE but need not be equally robust)."""
    return tuple(EquivalentStudy(yoke_phase_deg=tuple(float(value) for value in yoke),
                                 study=SampleStudy.of(_re_of(geometry, yoke),
                                                      sample.residual_error(yoke)))
                 for yoke in best.equivalent_yoke_phase_deg)


def _phase_error(geometry: ColumnGeometry,
                 designs: Sequence[RobustDesign]) -> PhaseErrorCurves:
    curves: dict[str, dict[str, tuple[float, ...]]] = {}
    errors: tuple[float, ...] = ()
    for design in designs:
        found = re_against_phase_error((geometry, design.yoke_phase_deg),
                                       span_deg=DEFAULT_PHASE_ERROR_SPAN_DEG,
                                       points=DEFAULT_PHASE_ERROR_POINTS)
        curves[design.role] = {name: _floats(values) for name, (_, values) in found.items()}
        errors = _floats(next(iter(found.values()))[0])
    return PhaseErrorCurves(errors_deg=errors, curves=curves)


def _feel_curves(geometry: ColumnGeometry, designs: Sequence[RobustDesign],
                 feel: dict[str, float]) -> tuple[tuple[float, ...],
                                                   dict[str, tuple[float, ...]]]:
    """Speed ratio against the steering-wheel angle from straight ahead, past each lock."""
    reach = feel["lock_deg"] + feel["window_deg"]
    wheel = np.arange(-reach, reach + WHEEL_STEP_DEG / 2, WHEEL_STEP_DEG)
    angles = feel["straight_ahead_deg"] + wheel
    return _floats(wheel), {design.role: _floats(speed_ratio(geometry, design.yoke_phase_deg,
                                                             angles))
                            for design in designs}


def _floats(values: np.ndarray) -> tuple[float, ...]:
    return tuple(float(value) for value in values)
