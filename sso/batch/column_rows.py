"""Sweep points of a column case: each point's row, and its axes checked beforehand.

A point of a column sweep is a column case (:mod:`sso.cases.column`) with the axes'
values set: any key as written in a case file (``hardpoints.points_mm[1][2]``,
``phasing.yoke_phase_deg[0]``, ``splines.teeth[1]``, ``tilt.angle_deg``, ...). Its row
(the columns :data:`sso.batch.table.COLUMN_RESULT_COLUMNS`) holds:

* ``"evaluate"``: the assembly as built (``phasing.yoke_phase_deg``) on the point's
  hardpoints;
* ``"optimise"``: the best continuous yoke phasing (:func:`sso.optimise`, its solvers
  cross-checked), and with ``[splines]`` the best phasing on the splines (exact over
  whole teeth, ``tooth_offset`` per intermediate shaft), which is then the design of
  the row.

Both give the design's RE, the least RE any phasing reaches (closed form), the
operating and bend-plane angles, and the steering figures from lock to lock
(:func:`sso.steering_range` with the case's ``[steering]`` keys). The joint-centre
design (``[joint_boxes]``) and the robust studies (``[tolerances]``, positions, band,
feel) run in ``sso run`` only; a sweep point does not run them.

Each axis value is read beforehand, as a case file is read, with the base case's
other values (:func:`check_axis_values`): a value the case refuses is bad input
naming the axis, the key and the allowed range, before any point is computed.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from sso.batch.axes import Axis, point_document
from sso.validation import shown

MOST_CHECKED_VALUES = 20_000
"""Most axis values read beforehand; a sweep with more reports a refused value in the
point's row instead."""


def check_axis_values(document: Mapping[str, Any], axes: Sequence[Axis]) -> None:
    """Read the base case with each axis value set in turn; raise for a value it refuses.

    Raises
    ------
    ValueError
        Naming the axis, the value and the case's reason (key and allowed range).
    """
    from sso.cases.schema import CaseError, parse_case

    if sum(len(axis.values) for axis in axes) > MOST_CHECKED_VALUES:
        return
    for axis in axes:
        seen: list[Any] = []
        for value in axis.values:
            if value in seen:
                continue
            seen.append(value)
            try:
                parse_case(point_document(document, {axis.path: value}), "base case")
            except CaseError as error:
                raise ValueError(f"axis {shown(axis.path)} = {shown(value)}: {error.reason}"
                                 ) from None


def column_row(case: Any, action: str) -> dict[str, Any]:
    """The result cells of one column point (see the module notes)."""
    import numpy as np

    from sso.column.cancel import can_cancel
    from sso.column.chain_matrix import residual_error
    from sso.column.steering_range import steering_range

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
    figures = steering_range((geometry, yoke), **case.steering_options())
    for name in ("speed_fluctuation_percent", "torque_fluctuation_percent",
                 "largest_transmission_error_deg", "transmission_error_peak_to_peak_deg",
                 "on_centre_fluctuation_percent"):
        row[name] = getattr(figures, name)
    return row


def _optimised(case: Any, geometry: Any) -> dict[str, Any]:
    """The best continuous phasing, and on the splines when the case has teeth."""
    from sso.column.phasing import optimise_phasing

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
        from sso.column.splines import best_spline_teeth

        splines = best_spline_teeth(geometry, case.teeth)
        row["design_yoke_phase_deg"] = list(splines.yoke_phase_deg)
        row["tooth_offset"] = list(splines.tooth_offset)
    return row
