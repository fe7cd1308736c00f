"""The result document of a 3D-column case, built by calling the public API.

Layout (``schema_version`` as :data:`sso.run.document.SCHEMA_VERSION`)::

    schema_version, kind ("column"), mode ("optimise" | "evaluate"), created_utc,
    case, case_file,
    geometry: {points_mm, beta_deg, plane_angle_deg, shaft_length_mm, straight_joints,
               bend_normals},
    cancel: sso.can_cancel(beta).to_dict(),
    assemblies: [{role, label, yoke_phase_deg, phase_deg, residual_error}],
    phasing? (optimise): best continuous phasing, its optima and the cross-check,
    splines? ([splines] given): best teeth, loss, fitter's instructions, for the
        case's own objective when it has positions, tolerances or a steering feel
        (``objective`` says which; the one position's then in
        ``splines_single_position``),
    joint_positions? (optimise with [joint_boxes]): JointCentresResult.to_dict(),
    robust? (positions, tolerances, band or feel given):
        :mod:`sso.run.column_robust_document`,
    excitation: {vehicle, application, rows: {role -> [ExcitationRow]}, angles: {role -> ...}},
    steering: SteeringAssessment.to_dict() of every assembly compared (and the
        robust part's designs),
    designs: {initial, optimum?} -> {label, evaluation: {residual_error}},
    success, verdict, warnings, versions

The assemblies are every phasing the report compares: as built, in phase, the
textbook correction, the best continuous phasing and the best on the splines.
The excitation is tabulated for the one as built and for the recommended one
(best on the splines when teeth are given, else the best continuous phasing).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import asdict
from typing import Any

import numpy as np

from sso.cases.column import ColumnCase
from sso.column.cancel import can_cancel
from sso.column.chain_matrix import residual_error
from sso.column.excitation import equivalent_angles, excitation_table
from sso.column.geometry import ColumnGeometry, wrap_half_turn
from sso.column.steering_criteria import assess_steering
from sso.run.column_robust_document import has_robust_part, robust_part
from sso.run.document import document_header, package_versions


def column_document(case: ColumnCase, optimising: bool) -> dict[str, Any]:
    """Analyse (``sso evaluate``) or optimise (``sso run``) a column case into its document.

    Parameters
    ----------
    case : ColumnCase
        A checked case (:mod:`sso.cases.column`).
    optimising : bool
        Find the best yoke phasing, spline teeth and (with joint boxes) joint
        positions; else analyse the assembly as built.

    Returns
    -------
    dict
        JSON-ready; solver failures and disagreements are recorded, never raised.

    Raises
    ------
    ValueError
        If the API refuses the case's values.
    """
    geometry = case.geometry()
    as_built = case.values["phasing.yoke_phase_deg"]
    document: dict[str, Any] = {
        **document_header(case, "optimise" if optimising else "evaluate"),
        "geometry": {**geometry.to_dict(), "straight_joints": list(geometry.straight_joints),
                     "bend_normals": geometry.bend_normals.tolist()},
        "cancel": asdict(can_cancel(geometry.beta_deg)),
    }
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
    phasing: Any = None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if optimising:
            from sso.column.phasing import optimise_phasing

            phasing = optimise_phasing(geometry, **case.solver_options())
            assemblies.append(_assembly(geometry, "best", "best yoke phasing (continuous)",
                                        phasing.yoke_phase_deg))
            document["phasing"] = _phasing_dict(phasing)
            success = success and phasing.success
            verdicts.append(f"phasing: {phasing.message}")
            recommended = "best"
        if optimising and case.has_joint_boxes:
            from sso.column.joint_positions import optimise_joint_centres

            moved = optimise_joint_centres(geometry, **case.joint_position_options())
            document["joint_positions"] = moved._document_dict()
            success = success and moved.success
            verdicts.append(f"joint positions: {moved.message}")
        teeth_assembly = None
        if has_robust_part(case):
            robust, robust_success, robust_verdicts, teeth_assembly = robust_part(
                case, optimising, list(as_built), phasing)
            document["robust"] = robust
            success = success and robust_success
            verdicts += robust_verdicts
        if case.teeth is not None:
            from sso.column.splines import best_spline_teeth

            splines = best_spline_teeth(geometry, case.teeth)
            label = "best on the splines (whole teeth)"
            if teeth_assembly is not None:
                # the fitter gets the teeth of the objective the case optimised
                document["splines_single_position"] = asdict(splines)
                label, splines = teeth_assembly
            assemblies.append(_assembly(geometry, "splines", label, splines.yoke_phase_deg))
            document["splines"] = asdict(splines)
            recommended = "splines"
        excitation = _excitation(geometry, case, {entry["role"]: entry for entry in assemblies},
                                 ("as_built", recommended))
    document["assemblies"] = assemblies
    document["excitation"] = excitation
    document["steering"] = _steering(geometry, case, assemblies, document.get("robust"))
    document["designs"] = _designs(assemblies, recommended, document.get("joint_positions"),
                                   document.get("splines"))
    document.update(
        success=success,
        verdict="; ".join(verdicts) if verdicts else "assembly as built analysed; no optimisation",
        recommended=recommended,
        warnings=list(dict.fromkeys([*case.warnings, *(str(item.message) for item in caught)])),
        versions=package_versions(),
    )
    return document


def _assembly(geometry: ColumnGeometry, role: str, label: str,
              yoke_phase_deg: Sequence[float]) -> dict[str, Any]:
    yoke = [float(value) for value in yoke_phase_deg]
    phase = geometry.phase_deg_from_yoke(yoke)
    value = float(residual_error(np.radians(geometry.beta_deg), np.radians(phase)))
    return {"role": role, "label": label, "yoke_phase_deg": yoke, "phase_deg": list(phase),
            "residual_error": value}


def _phasing_dict(phasing: Any) -> dict[str, Any]:
    run = phasing.optimisation
    return {
        "yoke_phase_deg": list(phasing.yoke_phase_deg),
        "phase_deg": list(phasing.phase_deg),
        "fun": phasing.fun,
        "equivalent_yoke_phase_deg": [list(row) for row in phasing.equivalent_yoke_phase_deg],
        "optimum_set_is_continuum": phasing.optimum_set_is_continuum,
        "minimum_residual_error": phasing.minimum_residual_error,
        "in_phase_re": phasing.in_phase_re,
        "plane_corrected_re": phasing.plane_corrected_re,
        "success": phasing.success,
        "message": phasing.message,
        "exact_optima": _exact_optima(phasing),
        "solutions": {name: solution.to_dict() for name, solution in run.solutions.items()},
        "crosscheck": None if run.crosscheck is None else run.crosscheck.to_dict(),
    }


def _exact_optima(phasing: Any) -> dict[str, Any] | None:
    """The set of exact optima of the phasing (RE at round-off zero): how the phasing was
    chosen within it and its extent per intermediate shaft; None without such a set."""
    extent = phasing.exact_optimum_extent_deg
    if extent is None:
        return None
    return {"criterion": phasing.exact_optimum_criterion,
            "dimension": phasing.optimisation.exact_optima.dimension,
            "extent_yoke_phase_deg": [list(pair) for pair in extent]}


def _excitation(geometry: ColumnGeometry, case: ColumnCase, assemblies: dict[str, Any],
                roles: Sequence[str]) -> dict[str, Any]:
    speeds = case.excitation_speeds_rpm()
    vehicle = case.values["excitation.vehicle"]
    application = case.values["excitation.application"]
    rows, angles = {}, {}
    for role in dict.fromkeys(roles):
        series = geometry.series(assemblies[role]["yoke_phase_deg"])
        rows[role] = [row.to_dict() for row in excitation_table(series, speeds, vehicle,
                                                                application)]
        angles[role] = asdict(equivalent_angles(series))
    return {"vehicle": vehicle, "application": application, "rows": rows, "angles": angles}


def _steering(geometry: ColumnGeometry, case: ColumnCase, assemblies: list[dict[str, Any]],
              robust: dict[str, Any] | None) -> dict[str, Any]:
    """Steering figures and criteria of every assembly, and of the robust part's designs
    not among them."""
    designs = [(entry["role"], entry["label"], entry["yoke_phase_deg"]) for entry in assemblies]
    roles = {entry["role"] for entry in assemblies} | {"nominal"}
    designs += [(entry["role"], entry["label"], entry["yoke_phase_deg"])
                for entry in (robust or {}).get("designs", []) if entry["role"] not in roles]
    return assess_steering(geometry, designs, limits=case.steering_limits(),
                           **case.steering_options())._document_dict()


def _designs(assemblies: list[dict[str, Any]], recommended: str,
             joint_positions: dict[str, Any] | None,
             splines: dict[str, Any] | None) -> dict[str, Any]:
    """Initial and best RE in the shape the command's summary reads; on the splines for
    an objective of its own, that objective at the teeth and at the continuous phasing."""
    by_role = {entry["role"]: entry for entry in assemblies}
    designs = {"initial": {"label": by_role["as_built"]["label"],
                           "evaluation": {"residual_error": by_role["as_built"]["residual_error"]}}}
    if recommended != "as_built":
        best = by_role[recommended]
        value = best["residual_error"]
        label = best["label"]
        if joint_positions is not None and joint_positions["fun"] < value:
            value, label = joint_positions["fun"], "joints moved within their boxes"
        designs["optimum"] = {"label": label, "evaluation": {"residual_error": value}}
        if recommended == "splines" and splines is not None and splines["objective"] != "RE":
            designs["optimum"]["objective"] = {
                "name": splines["objective"], "at_teeth": splines["residual_error"],
                "continuous": splines["continuous_residual_error"]}
    return designs
