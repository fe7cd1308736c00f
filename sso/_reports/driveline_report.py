"""The report of a driveline, in the trade's words: gearbox, propshafts, centre bearings,
pinion; yokes in or out of phase; side and plan view; the rules with pass/fail and source;
excitations against their limits; bearing loads; critical speeds; the phasing advice.

Rendered from the result alone (:class:`sso.DrivelineResult`, or the
:class:`sso._run.driveline.DrivelineRun` of a case).
"""

from __future__ import annotations

from typing import Any

from sso._driveline.figures import DrivelineResult, joint_name, verdict_word, yoke_words
from sso._driveline.layout_advice import LayoutAdvice
from sso._driveline.phasing import PhasingAdvice
from sso._reports.documents import report_files
from sso._reports.summary import (
    Block,
    Heading,
    Image,
    Paragraph,
    Scene,
    Table,
    closing_blocks,
    number,
)

LOAD_MODEL_WORDS = (
    "Bearing loads: quasi-static, torque only (no gravity, inertia or friction); a cross "
    "carries moment only along its normal; the rearmost propshaft holds the slip spline (no "
    "axial force); a centre bearing is radial only, at its stated distance ahead of its "
    "shaft's rear joint; gearbox bearings at b and a + b ahead of the first joint, pinion "
    "bearings at e and e + f behind the last (Dana's notation; checked against Dana's closed "
    "forms for Z and W layouts).")
EFFECTIVE_WORDS = (
    "Effective angle: theta_e = sqrt(|sum_k beta_k^2 exp(2 i Phi_k)|), Phi_k each joint's "
    "accumulated phase (second order in the angles, any phasing and compound angles); for a "
    "planar shaft phased 0 or 90 deg it is the signed-square rule sqrt(|b1^2 - b2^2 + "
    "b3^2 ...|), shown beside it where it applies. Excitations are exact: the peak angular "
    "acceleration of each shaft over one revolution from the 3D chain.")


def _component_names(joints: int) -> list[str]:
    return ["gearbox", *[f"propshaft {k}" for k in range(1, joints)], "pinion"]


def driveline_blocks(result: DrivelineResult, name: str, description: str,
                     images: tuple[str, ...], warnings: tuple[str, ...] = (),
                     versions: dict[str, str] | None = None) -> list[Block]:
    """The report's blocks."""
    from sso._reports.driveline_plots import CAPTIONS

    driveline = result.driveline
    joints = driveline.joint_count
    blocks: list[Block] = [Heading(1, f"Driveline report: {name}")]
    if description:
        blocks.append(Paragraph(description))
    blocks += [
        Heading(2, "Verdict"),
        Paragraph(("Every rule passes." if result.passed else "A rule FAILS: see the rules.")
                  + f" Yokes: {yoke_words(driveline.phasing_deg)}."),
        Heading(2, "Layout"),
        Paragraph(f"{joints} joints, {joints - 1} propshafts; maximum shaft speed "
                  f"{number(driveline.max_shaft_speed_rpm)} rpm; torque "
                  f"{number(driveline.torque_n_m)} N m. Slopes as an inclinometer reads them, "
                  "front higher positive; plan angles rear end to the left positive."),
    ]
    for figures in result.positions:
        blocks += [
            Heading(2, f"Position: {figures.name}"),
            Table(("component", "side-view slope (deg)", "plan-view angle (deg)"),
                  tuple((component, number(slope), number(plan)) for component, slope, plan
                        in zip(_component_names(joints), figures.slope_deg, figures.plan_deg,
                               strict=True))),
            Table(("joint", "true angle (deg)", "side view (deg)", "plan view (deg)",
                   "sqrt(side^2 + plan^2) (deg)"),
                  tuple((joint_name(k, joints), number(figures.joint_angle_deg[k]),
                         number(figures.side_view_deg[k]), number(figures.plan_view_deg[k]),
                         number(figures.compound_estimate_deg[k])) for k in range(joints))),
            Paragraph(f"Effective angle {number(figures.effective_angle_deg)} deg"
                      + ("" if figures.signed_square_deg is None else
                         f" (signed-square rule {number(figures.signed_square_deg)} deg)")
                      + f". Excitation at {number(driveline.max_shaft_speed_rpm)} rpm: "
                      f"inertia drive {number(figures.inertia_drive_rad_s2)}, coast "
                      f"{number(figures.inertia_coast_rad_s2)} rad/s^2 (limit "
                      f"{number(driveline.inertia_limit_rad_s2)}); torsional "
                      f"{number(figures.torsional_rad_s2)} rad/s^2 (limit "
                      f"{number(driveline.torsional_limit_rad_s2)})."),
            Table(("shaft", "peak acceleration, gearbox steady (rad/s^2)",
                   "peak acceleration, pinion steady (rad/s^2)"),
                  tuple((component,
                         "-" if index == 0 else number(figures.drive_peak_rad_s2[index - 1]),
                         "-" if index == joints else number(figures.coast_peak_rad_s2[index]))
                        for index, component in enumerate(_component_names(joints)))),
        ]
    blocks += [Paragraph(EFFECTIVE_WORDS), Heading(2, "Rules"),
               Table(("rule", "where", "value", "limit", "verdict", "source"),
                     tuple((rule.rule, rule.where, f"{number(rule.value)} {rule.unit}",
                            "-" if rule.limit is None else f"{number(rule.limit)} {rule.unit}",
                            verdict_word(rule.passed), rule.source) for rule in result.rules))]
    if result.tubes:
        blocks += [Heading(2, "Critical speed"), Table(
            ("propshaft", "tube (mm)", "length (mm)", "critical (rpm)", "safe (rpm)",
             "split above (mm)"),
            tuple((f"propshaft {k}", f"{number(tube.outside_diameter_mm)} x "
                   f"{number(tube.wall_mm)}", number(figures.length_mm),
                   number(figures.critical_speed_rpm), number(figures.safe_speed_rpm),
                   number(figures.split_length_mm))
                  for k, (tube, figures) in enumerate(zip(driveline.tubes, result.tubes,
                                                          strict=True), start=1))),
            Paragraph(f"Uniform tube simply supported at its joint centres: n_c = (30/pi) "
                      f"(pi/L)^2 sqrt(E I / (rho A)); safe speed {number(driveline.safe_fraction)}"
                      " of critical (IMS Ltd: 0.70 automotive, 0.65 industrial).")]
    blocks += [Heading(2, "Secondary couples and bearing loads"), Paragraph(LOAD_MODEL_WORDS),
               Table(("joint", "peak couple on the shaft ahead (N m)",
                      "peak couple on the shaft behind (N m)"),
                     tuple((joint_name(couple.joint - 1, joints), number(max(couple.ahead_n_m)),
                            number(max(couple.behind_n_m))) for couple in result.loads.couples)),
               Table(("bearing", "peak radial load (N)"),
                     tuple((curve.name, number(curve.peak_n)) for curve in result.loads.bearings))]
    if result.phasing is not None:
        advice = result.phasing
        blocks += [Heading(2, "Yoke phasing for the excitation limits"),
                   Paragraph(f"Recommended: {yoke_words(advice.yoke_phase_deg)} "
                             f"(given: {yoke_words(advice.given_yoke_phase_deg)}). Largest "
                             f"excitation over its limit {number(advice.worst_ratio_given)} to "
                             f"{number(advice.worst_ratio_recommended)} (the least any "
                             f"phasing{' and layout' if advice.box else ''} reaches: "
                             f"{number(advice.least_worst_ratio)}). Criterion: "
                             f"{advice.criterion}."),
                   Table(("position", "excitation", "given (rad/s^2)", "recommended (rad/s^2)",
                          "limit (rad/s^2)"),
                         tuple((row.position, row.figure, number(row.given_rad_s2),
                                number(row.recommended_rad_s2), number(row.limit_rad_s2))
                               for row in advice.rows)),
                   Paragraph("Trade: " + ("; ".join(
                       f"{row.position} {row.figure} rises from {number(row.given_rad_s2)} to "
                       f"{number(row.recommended_rad_s2)} rad/s^2" for row in advice.trades)
                       if advice.trades else "no excitation gets worse."))]
        if result.layout is not None:
            blocks += layout_blocks(advice, result.layout)
    blocks += [Heading(2, "Joint life"), Paragraph(result.joint_life),
               Heading(2, "3D view"),
               Scene(driveline_scene(result), "The driveline in 3D (vehicle axes, mm): shafts, "
                     "joints with their true angles, named positions dashed")]
    return [*blocks, *closing_blocks(warnings, versions,
                                     [Image(image, CAPTIONS[image]) for image in images])]


SHAFT_COLOUR = "#1f77b4"
POSITION_COLOURS = ("#d62728", "#2ca02c", "#9467bd", "#8c564b", "#e377c2")


def driveline_scene(result: DrivelineResult) -> dict[str, Any]:
    """The interactive 3D view's scene (:mod:`sso._reports.view3d`): each component as a
    line, each joint as a point with its true angle, each named position dashed."""
    import numpy as np

    geometries = result.driveline.named_geometries()
    names = _component_names(result.driveline.joint_count)
    items: list[dict[str, Any]] = []
    for index, (position, geometry) in enumerate(geometries.items()):
        points = np.asarray(geometry.points_mm, dtype=float)
        design = index == 0
        colour = SHAFT_COLOUR if design else POSITION_COLOURS[(index - 1) % len(POSITION_COLOURS)]
        for shaft, name in enumerate(names):
            items.append({"kind": "line", "points": points[[shaft, shaft + 1]].tolist(),
                          "colour": colour, "width": 4.0 if design else 2.0,
                          "dash": not design, "name": f"{name} ({position})"})
        if design:
            for joint, beta in enumerate(geometry.beta_deg):
                label = joint_name(joint, len(geometry.beta_deg))
                items.append({"kind": "point", "at": points[joint + 1].tolist(),
                              "colour": SHAFT_COLOUR, "size": 6.0,
                              "name": f"{label}: true angle {beta:.3f} deg",
                              "label": f"joint {joint + 1}"})
    stacked = np.array([point for item in items
                        for point in (item["points"] if "points" in item else [item["at"]])])
    centre = (stacked.max(axis=0) + stacked.min(axis=0)) / 2.0
    radius = float(np.linalg.norm(stacked - centre, axis=1).max())
    return {"items": items, "centre": centre.tolist(), "radius": max(radius, 1e-9),
            "yaw_deg": 20.0, "pitch_deg": 15.0}


def _files(result: DrivelineResult, name: str, description: str, formats: tuple[str, ...],
           warnings: tuple[str, ...], versions: dict[str, str] | None) -> dict[str, bytes]:
    from sso._reports.driveline_plots import driveline_plots

    return report_files(formats, lambda: {"rules.csv": rules_csv(result)},
                        lambda: driveline_plots(result),
                        lambda images: driveline_blocks(result, name, description,
                                                        tuple(images), warnings, versions))


def layout_blocks(advice: PhasingAdvice, layout: LayoutAdvice) -> list[Block]:
    """The layout chosen within its box, its verdict and every rule it makes worse."""
    blocks: list[Block] = [
        Heading(2, "Layout within its box"),
        Paragraph(f"Recommended with the phasing above: {advice.layout_words()}. On the "
                  "driveline so laid out and phased "
                  + ("every rule passes." if layout.passed else "a rule FAILS.")
                  + " Rules whose margin to the limit shrinks against the layout as given: "
                  + ("none." if not layout.trades else "the table."))]
    if layout.trades:
        blocks.append(Table(
            ("rule", "where", "given", "recommended", "limit", "verdict"),
            tuple((change.rule, change.where, f"{number(change.given_value)} {change.unit}",
                   f"{number(change.recommended_value)} {change.unit}",
                   f"{number(change.limit)} {change.unit}",
                   verdict_word(change.recommended_passed)) for change in layout.trades)))
    return blocks


def rules_csv(result: DrivelineResult) -> str:
    """The rules table as CSV text."""
    import csv
    import io

    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(("rule", "where", "value", "limit", "unit", "verdict", "source"))
    for rule in result.rules:
        writer.writerow((rule.rule, rule.where, repr(rule.value),
                         "" if rule.limit is None else repr(rule.limit), rule.unit,
                         verdict_word(rule.passed), rule.source))
    return buffer.getvalue()


def render_driveline_result(result: Any, formats: tuple[str, ...]) -> dict[str, bytes]:
    """The report files of a :class:`sso.DrivelineResult` made in Python."""
    return _files(result, "driveline", "", formats, (), None)


def render_driveline_run(run: Any, formats: tuple[str, ...]) -> dict[str, bytes]:
    """The report files of a driveline case run."""
    return _files(run.result, run.case.name, run.case.description, formats, run.warnings,
                  run.versions)

