"""Sweep points of a column case: each point's row, and its axes checked beforehand.

A point of a column sweep is a column case (:mod:`sso._cases.column`) with the axes'
values set: any key as written in a case file (``hardpoints.points_mm[1][2]``,
``phasing.yoke_phase_deg[0]``, ``splines.teeth[1]``, ``tilt.angle_deg``, ...). Its row
(the columns :data:`sso._studies.table.COLUMN_RESULT_COLUMNS`) holds:

* ``"evaluate"``: the assembly as built (``phasing.yoke_phase_deg``) on the point's
  hardpoints;
* ``"optimise"``: the best continuous yoke phasing (:func:`sso.optimise`, its solvers
  cross-checked), and with ``[splines]`` the best phasing on the splines (exact over
  whole teeth, ``tooth_offset`` per intermediate shaft), which is then the design of
  the row.

Both give the design's RE, the least RE any phasing reaches (closed form), the
operating and bend-plane angles, and the steering figures from lock to lock
(:func:`sso.steering_range` with the case's ``[steering]`` keys). Each point also runs
what its case asks for, as ``sso run`` / ``sso evaluate`` would at those hardpoints:

* ``[joint_boxes]`` (``"optimise"``): the joint-centre design
  (:func:`sso._column.joint_centres.optimise_joint_centres`, the exact optimum of
  largest margin to the boxes where RE = 0): its RE, moved joint centres and margin;
* ``[tolerances]``: the p95 RE of the row's design over the case's built columns, and
  (``"optimise"``) the tolerance-aware phasing
  (:func:`sso._column.robust_phasing.optimise_robust`) with its p95.

``[hardpoints.positions]``, ``[band]`` and ``[feel]`` are refused beforehand
(:func:`check_sweepable`, see :data:`UNSWEPT_TABLES`).

Each axis value is read beforehand, as a case file is read, with the base case's
other values (:func:`check_axis_values`): a value the case refuses is bad input
naming the axis, the key and the allowed range, before any point is computed.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from sso._cases.schema import CaseError, parse_case
from sso._column.cancel import can_cancel
from sso._column.chain_matrix import residual_error
from sso._column.phasing import optimise_phasing
from sso._column.robust_phasing import optimise_robust
from sso._column.splines import best_spline_teeth
from sso._column.steering_range import steering_range
from sso._studies.axes import Axis, point_document
from sso._validation import shown

UNSWEPT_TABLES = {
    "hardpoints.positions": (
        "[hardpoints.positions]: a sweep's axes move hardpoints.points_mm (and the [tilt] "
        "position), not the named positions, so one shared phasing per point would mix "
        "moved and unmoved positions; sweep tilt.angle_deg, or run each case with sso run"),
    "band.re_limit": (
        "[band]: the band's RE limit must lie above each design's RE, which the sweep "
        "moves from point to point; run sso run at the points of interest"),
    "feel.lock_deg": (
        "[feel]: the on-centre phasing is a further optimisation per point, not swept; run "
        "sso run at the points of interest (the rows hold the on-centre fluctuation)"),
}
"""A column case's tables a sweep point does not run, keyed by the case value that says
the table is there, with the reason."""
MOST_CHECKED_VALUES = 20_000
"""Most axis values read beforehand; a sweep with more reads only each axis's first and
last values beforehand (a range's ends: a value of the wrong kind, or a range reaching
past its key's limits, is refused before any point runs) and reports any other refused
value in the point's row."""


def check_axis_values(document: Mapping[str, Any], axes: Sequence[Axis]) -> None:
    """Read the base case with each axis value set in turn; raise for a value it refuses.

    Raises
    ------
    ValueError
        Naming the axis, the value and the case's reason (key and allowed range).
    """
    every = sum(len(axis.values) for axis in axes) <= MOST_CHECKED_VALUES
    for axis in axes:
        seen: list[Any] = []
        for value in axis.values if every else (*axis.values[:1], *axis.values[-1:]):
            if value in seen:
                continue
            seen.append(value)
            try:
                parse_case(point_document(document, {axis.path: value}), "base case")
            except CaseError as error:
                raise ValueError(f"axis {shown(axis.path)} = {shown(value)}: {error.reason}"
                                 ) from None


def check_sweepable(case: Any) -> None:
    """Refuse a column case with a table a sweep point does not run.

    Raises
    ------
    ValueError
        Naming the table and the reason (:data:`UNSWEPT_TABLES`).
    """
    for key, reason in UNSWEPT_TABLES.items():
        if case.values.get(key) is not None:
            raise ValueError(f"a sweep of a column case does not run {reason}")


def column_row(case: Any, action: str) -> dict[str, Any]:
    """The result cells of one column point (see the module notes)."""
    geometry = case.geometry()
    verdict = can_cancel(geometry.beta_deg)
    row: dict[str, Any] = {"minimum_residual_error": verdict.minimum_residual_error,
                           "can_cancel": verdict.possible,
                           "design_beta_deg": list(geometry.beta_deg),
                           "plane_angle_deg": list(geometry.plane_angle_deg)}
    yoke = list(case.values["phasing.yoke_phase_deg"])
    if action == "optimise":
        row.update(_optimised(case, geometry))
        yoke = row.pop("design_yoke_phase_deg")

    row["yoke_phase_deg"] = [float(value) for value in yoke]
    row["residual_error"] = float(residual_error(
        np.radians(geometry.beta_deg), np.radians(geometry.phase_deg_from_yoke(yoke))))
    if action == "optimise" and case.has_joint_boxes:
        row.update(_joint_centres(case, geometry))
    tolerances = case.tolerances()
    if tolerances is not None:
        row.update(_tolerances(case, geometry, tolerances, yoke, action))
    figures = steering_range((geometry, yoke), **case.steering_options())
    for name in ("speed_fluctuation_percent", "torque_fluctuation_percent",
                 "largest_transmission_error_deg", "transmission_error_peak_to_peak_deg",
                 "on_centre_fluctuation_percent"):
        row[name] = getattr(figures, name)
    return row


def _optimised(case: Any, geometry: Any) -> dict[str, Any]:
    """The best continuous phasing, and on the splines when the case has teeth."""
    phasing = optimise_phasing(geometry, **case.solver_options())
    check = phasing.optimisation.crosscheck
    row: dict[str, Any] = {
        "continuous_residual_error": phasing.fun,
        "continuous_yoke_phase_deg": list(phasing.yoke_phase_deg),
        "design_yoke_phase_deg": list(phasing.yoke_phase_deg),
        "success": phasing.success,
        "crosscheck_agree": None if check is None else check.agree,
        "crosscheck_objective_gap": None if check is None else check.objective_gap,
    }
    if case.teeth is not None:
        splines = best_spline_teeth(geometry, case.teeth)
        row["design_yoke_phase_deg"] = list(splines.yoke_phase_deg)
        row["tooth_offset"] = list(splines.tooth_offset)
    return row


def _joint_centres(case: Any, geometry: Any) -> dict[str, Any]:
    """The joint-centre design of ``[joint_boxes]`` at the point's hardpoints."""
    from sso._column.joint_centres import optimise_joint_centres

    moved = optimise_joint_centres(geometry, **case.joint_position_options())
    return {"joint_centres_residual_error": moved.fun,
            "joint_centres_points_mm": [list(point) for point in moved.points_mm[1:-1]],
            "joint_centres_margin_mm": (None if moved.exact_optima is None
                                        else moved.exact_optima.margin),
            "joint_centres_success": moved.success}


def _tolerances(case: Any, geometry: Any, tolerances: Any, yoke: Any,
                action: str) -> dict[str, Any]:
    """The p95 RE of the row's design over the built columns; with ``"optimise"``, the
    tolerance-aware phasing and its p95 on the same sample."""
    sample = tolerances.sample(geometry)
    row: dict[str, Any] = {
        "tolerance_p95_residual_error": float(np.percentile(sample.residual_error(yoke), 95.0))}
    if action == "optimise":
        robust = optimise_robust(geometry, tolerances,
                                 robust_objective=case.values["tolerances.robust_objective"],
                                 **case.solver_options())
        row.update(robust_yoke_phase_deg=list(robust.yoke_phase_deg),
                   robust_p95_residual_error=robust.robust_study.p95)
    return row
