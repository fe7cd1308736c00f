"""The robust-phasing part of a column result document (``document["robust"]``).

Built when a column case has ``[hardpoints.positions]``, ``[tolerances]``, ``[band]``
or ``[feel]`` (:mod:`sso._cases.column_robust`). Layout::

    robust: {
      designs: [{role, label, yoke_phase_deg, nominal_re, splines? (a teeth assembly),
                 position_re?, worst_position_re?, active_positions?,
                 study?: SampleStudy.to_dict(), feel?: SteeringFeel.to_dict(),
                 band?: ToleranceBand.to_dict() | band_note?: str}],
      phase_error: {errors_deg, re: {role -> {"yoke_phase_deg[k]" -> [RE]}}},
      positions?: {names, geometry: {name -> ColumnGeometry.to_dict()},
                   result?: PositionsResult.to_dict()},
      tolerances?: {settings, result?: RobustResult.to_dict(),
                    samples_re: {role -> sorted RE over the sample}},
      feel?: {settings, result?: OnCentreResult.to_dict(),
              wheel_deg, ratio: {role -> [ratio]}},
      band?: {re_limit},
    }

Designs compared (every figure is of each one, on ``hardpoints.points_mm`` unless
said): ``sso evaluate`` the assembly as built; ``sso run`` the best phasing (the
nominal optimum), the positions' shared phasing, the tolerance-aware phasing and
the on-centre phasing, as the case asks.
"""

from __future__ import annotations

from dataclasses import asdict
from typing import Any

import numpy as np

from sso._cases.column import ColumnCase
from sso._column.geometry import ColumnGeometry

PHASE_ERROR_SPAN_DEG = 10.0
PHASE_ERROR_POINTS = 201
WHEEL_STEP_DEG = 0.5
# An on-centre objective at or below this is a cancelled fluctuation (RE ~ 1e-25).
CANCELLED_OBJECTIVE = 1e-20


def has_robust_part(case: ColumnCase) -> bool:
    """True when the case asks for positions, tolerances, a band or the steering feel."""
    return any(case.values.get(label) is not None
               for label in ("hardpoints.positions", "tolerances.hardpoint_mm",
                             "band.re_limit", "feel.lock_deg"))


def robust_part(case: ColumnCase, optimising: bool, as_built: list[float],
                best: Any) -> tuple[dict[str, Any], bool, list[str], Any]:
    """The ``robust`` section, whether its solvers succeeded, their verdicts, and the
    teeth assembly of the case's own objective (None without teeth or optimisation).

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
    as_built : list of float
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
    designs: list[dict[str, Any]] = []
    section: dict[str, Any] = {}
    success = True
    verdicts: list[str] = []

    teeth_assemblies: list[tuple[str, Any]] = []

    def add(role: str, label: str, yoke: Any) -> dict[str, Any]:
        entry = {"role": role, "label": label, "yoke_phase_deg": [float(v) for v in yoke]}
        designs.append(entry)
        return entry

    def add_teeth(role: str, label: str, result: Any) -> None:
        if case.teeth is None:
            return
        teeth = result.on_splines(case.teeth)
        entry = add(f"{role}_splines", f"{label}, on the splines (whole teeth)",
                    teeth.yoke_phase_deg)
        entry["splines"] = asdict(teeth)
        teeth_assemblies.append((f"{label}, on the splines (whole teeth)", teeth))

    if optimising:
        add("nominal", "nominal optimum (best phasing of the hardpoints)", best.yoke_phase_deg)
    else:
        add("as_built", "as built (phasing.yoke_phase_deg)", as_built)
    positions = case.positions()
    if positions is not None:
        section["positions"] = {"names": list(positions),
                                "geometry": {name: column.to_dict()
                                             for name, column in positions.items()}}
        if optimising:
            from sso._column.positions import optimise_positions

            objective = case.values["phasing.positions_objective"]
            shared = optimise_positions(positions, positions_objective=objective,
                                        weights=case.values["phasing.position_weights"],
                                        **options)
            section["positions"]["result"] = _without_geometries(shared._document_dict())
            add("positions", f"one phasing for every position ({objective})",
                shared.yoke_phase_deg)
            add_teeth("positions", f"one phasing for every position ({objective})", shared)
            success = success and shared.success
            verdicts.append(f"positions: {shared.message}")
    tolerances = case.tolerances()
    if tolerances is not None:
        section["tolerances"] = {"settings": {
            **tolerances.to_dict(), "robust_objective": case.values["tolerances.robust_objective"]}}
        if optimising:
            from sso._column.robust_phasing import optimise_robust

            robust = optimise_robust(geometry, tolerances,
                                     robust_objective=case.values["tolerances.robust_objective"],
                                     **options)
            section["tolerances"]["result"] = _without_geometries(robust._document_dict())
            add("robust", robust.design_label, robust.yoke_phase_deg)
            add_teeth("robust", robust.design_label, robust)
            success = success and robust.success
            verdicts.append(f"tolerances: {robust.message}")
    feel: dict[str, Any] | None = case.feel_options()
    if feel is not None:
        section["feel"] = {"settings": feel}
        if optimising:
            from sso._column.feel import optimise_on_centre, steering_feel

            least = steering_feel(best, **feel).objective
            if least <= CANCELLED_OBJECTIVE:
                # RE + weight * V cannot go below 0: the cancelling optimum is the
                # on-centre optimum too (its ratio is flat everywhere), and the
                # scaled NLP would have nothing to scale by.
                section["feel"]["note"] = (
                    f"the nominal optimum cancels the fluctuation (objective {least:.3g}): its "
                    "ratio is flat on-centre and at lock, so it is the on-centre phasing too")
            else:
                centred = optimise_on_centre(geometry, **feel, **options)
                section["feel"]["result"] = centred._document_dict()
                add("on_centre", "on-centre (steering feel)", centred.yoke_phase_deg)
                add_teeth("on_centre", "on-centre (steering feel)", centred)
                success = success and centred.success
                verdicts.append(f"steering feel: {centred.message}")
    limit = case.values.get("band.re_limit")
    if limit is not None:
        section["band"] = {"re_limit": limit}
    sample = None if tolerances is None else tolerances.sample(geometry)
    samples_re: dict[str, list[float]] = {}
    for entry in designs:
        _design_figures(entry, geometry, positions, sample, samples_re, feel, limit)
    if sample is not None:
        section["tolerances"]["samples_re"] = samples_re
        if optimising:
            section["tolerances"]["nominal_equivalents"] = _equivalents(geometry, best, sample)
    section["designs"] = designs
    section["phase_error"] = _phase_error(geometry, designs)
    if feel is not None:
        section["feel"].update(_feel_curves(geometry, designs, feel))
    return section, success, verdicts, teeth_assemblies[0] if teeth_assemblies else None


def _design_figures(entry: dict[str, Any], geometry: ColumnGeometry,
                    positions: dict[str, ColumnGeometry] | None, sample: Any,
                    samples_re: dict[str, list[float]], feel: dict[str, Any] | None,
                    limit: float | None) -> None:
    """Every figure of one design, added to its entry."""
    from sso._column.band import tolerance_band
    from sso._column.chain_matrix import residual_error
    from sso._column.feel import steering_feel
    from sso._column.tolerances import SampleStudy

    yoke = entry["yoke_phase_deg"]

    def re_of(column: ColumnGeometry) -> float:
        return float(residual_error(np.radians(column.beta_deg),
                                    np.radians(column.phase_deg_from_yoke(yoke))))

    nominal = re_of(geometry)
    entry["nominal_re"] = nominal
    if positions is not None:
        by_name = {name: re_of(column) for name, column in positions.items()}
        worst = max(by_name.values())
        entry.update(position_re=by_name, worst_position_re=worst,
                     active_positions=[name for name, value in by_name.items()
                                       if value >= worst * (1.0 - 1e-6)])
    if sample is not None:
        values = sample.residual_error(yoke)
        entry["study"] = asdict(SampleStudy.of(nominal, values))
        samples_re[entry["role"]] = sorted(float(value) for value in values)
    if feel is not None:
        entry["feel"] = asdict(steering_feel((geometry, yoke), **feel))
    if limit is not None:
        if nominal <= limit:
            band = tolerance_band((geometry, yoke), limit)._document_dict()
            band.pop("geometry")
            entry["band"] = band
        else:
            entry["band_note"] = (f"RE {nominal:.6g} at the hardpoints is above band.re_limit = "
                                  f"{limit:g}: no band")


def _equivalents(geometry: ColumnGeometry, best: Any, sample: Any) -> list[dict[str, Any]]:
    """The tolerance study of every equivalent nominal optimum (mirror solutions reach
    the same nominal RE but need not be equally robust)."""
    from sso._column.chain_matrix import residual_error
    from sso._column.tolerances import SampleStudy

    rows = []
    for yoke in best.equivalent_yoke_phase_deg:
        nominal = float(residual_error(np.radians(geometry.beta_deg),
                                       np.radians(geometry.phase_deg_from_yoke(yoke))))
        rows.append({"yoke_phase_deg": [float(value) for value in yoke],
                     "study": asdict(SampleStudy.of(nominal, sample.residual_error(yoke)))})
    return rows


def _phase_error(geometry: ColumnGeometry, designs: list[dict[str, Any]]) -> dict[str, Any]:
    from sso._column.band import re_against_phase_error

    curves: dict[str, dict[str, list[float]]] = {}
    errors: list[float] = []
    for entry in designs:
        found = re_against_phase_error((geometry, entry["yoke_phase_deg"]),
                                       span_deg=PHASE_ERROR_SPAN_DEG, points=PHASE_ERROR_POINTS)
        curves[entry["role"]] = {name: values.tolist() for name, (_, values) in found.items()}
        errors = next(iter(found.values()))[0].tolist()
    return {"errors_deg": errors, "re": curves}


def _feel_curves(geometry: ColumnGeometry, designs: list[dict[str, Any]],
                 feel: dict[str, Any]) -> dict[str, Any]:
    """Speed ratio against the steering-wheel angle from straight ahead, past each lock."""
    from sso._column.feel import speed_ratio

    reach = feel["lock_deg"] + feel["window_deg"]
    wheel = np.arange(-reach, reach + WHEEL_STEP_DEG / 2, WHEEL_STEP_DEG)
    ratio = {entry["role"]: speed_ratio(geometry, entry["yoke_phase_deg"],
                                        feel["straight_ahead_deg"] + wheel).tolist()
             for entry in designs}
    return {"wheel_deg": wheel.tolist(), "ratio": ratio}


def _without_geometries(result: dict[str, Any]) -> dict[str, Any]:
    """A result's dictionary without its geometries (the section holds them once)."""
    return {name: value for name, value in result.items() if name not in ("geometry",
                                                                           "geometries")}
