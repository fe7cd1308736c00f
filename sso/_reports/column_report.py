"""Report of a column case run: ``report.md``/``.html`` blocks and ``excitation.csv``.

Rendered from the run alone (:class:`sso._run.column.ColumnRun`), with the same
Markdown and HTML writers as every other report.
"""

from __future__ import annotations

import csv
import io
from collections.abc import Sequence
from typing import Any

from sso._column.geometry import shaft_name
from sso._column.joint_centres import JointCentresResult
from sso._limits import REPORT_DIGITS
from sso._reports.column_fitter_report import fitter_blocks
from sso._reports.column_robust_report import ROBUST_CAPTIONS, robust_blocks
from sso._reports.column_steering_report import STEERING_CAPTION, STEERING_PLOT, steering_blocks
from sso._reports.documents import report_files
from sso._reports.shaft_report import exact_optima_blocks
from sso._reports.summary import (
    NUMERICS_HEADING,
    Block,
    Heading,
    Image,
    Paragraph,
    Scene,
    Table,
    closing_blocks,
    number,
    opening_blocks,
)
from sso._run.column import ColumnRun
from sso._shafts.exact_optima import EXTENT_GRID

EXCITATION_FILE = "excitation.csv"
EXCITATION_COLUMNS = ("input_speed_rpm", "drive_rad_s2", "coast_rad_s2", "torsional_rad_s2",
                      "exact_torsional_rad_s2", "exact_output_accel_rad_s2",
                      "inertial_limit_rad_s2", "torsional_limit_rad_s2", "within_limits")
CAPTIONS = {
    "column_3d.png": "The column in vehicle coordinates: shafts, joints (dots), the end points "
                     "on the input and output axes (squares) and each joint's bend plane "
                     "(orange patch, spanned by the shafts before and after the joint); the "
                     "named tilt positions (dotted), the joint boxes and the moved column "
                     "(dashed) where the case has them. report.html has this view to turn.",
    "excitation.png": "SAE AE-7 small-angle excitations and the exact output acceleration over "
                      "the rpm range (solid: recommended assembly, dashed: as built), with the "
                      "published driveline limits where they apply.",
    STEERING_PLOT: STEERING_CAPTION,
    **ROBUST_CAPTIONS,
}
VIEW_CAPTION = ("The column in vehicle coordinates (mm), to turn: drag to rotate, the wheel to "
                "zoom, double-click for the first view; the pointer names each part. Shafts "
                "(blue), joints and end points, each joint's bend plane (orange), the named tilt "
                "positions (dashed), the joint boxes and the moved column (green).")
CONVENTION = ("Conventions: shaft k runs from P(k) to P(k+1): the input shaft (k = 0), the "
              "intermediate shafts 1 to n-1 and the output shaft (k = n); gamma_k is the angle "
              "about intermediate shaft k from bend plane k to bend plane k+1 (right-hand rule); "
              "the yoke phasing delta_k is the turn about shaft k from the pin axis of its yoke at "
              "joint k to that of its yoke at joint k+1, 0 = in phase (pin axes parallel); the "
              "model phase is phi_k = 90 + delta_k - gamma_k (mod 180). phi = 90 deg means yokes in"
              " phase only for a planar column (gamma = 0 or 180); here it means each yoke turned "
              "by its bend-plane angle (the textbook correction).")


def column_files(run: ColumnRun, formats: Sequence[str]) -> dict[str, bytes]:
    """Contents of every requested file of a column run's report but ``result.json``,
    keyed by file name (nothing is written).

    Parameters
    ----------
    run : ColumnRun
    formats : sequence of {"json", "csv", "md", "html", "png"}
        Files to render. Without ``"png"`` matplotlib is never imported and the
        reports carry no plots.
    """
    from sso._reports.column_plots import render_column_plots

    return report_files(formats, lambda: {EXCITATION_FILE: excitation_csv(run)},
                        lambda: render_column_plots(run),
                        lambda images: column_blocks(run, images))


def excitation_csv(run: ColumnRun) -> str:
    """``excitation.csv``: one row per speed and assembly (as built, recommended), six
    significant digits (``result.json`` keeps every digit)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(("assembly", *EXCITATION_COLUMNS))
    for role, table in run.excitation.items():
        for row in table:
            values = (getattr(row, name) for name in EXCITATION_COLUMNS)
            writer.writerow((role, *(f"{value:.{REPORT_DIGITS}g}" if isinstance(value, float)
                                     else value for value in values)))
    return buffer.getvalue()


def column_blocks(run: ColumnRun, image_files: Sequence[str]) -> list[Block]:
    """Blocks of the whole report of a column run."""
    yields = run.judged_yields
    figures, trade = run.headline
    compared = ("" if run.recommended == "as_built" else
                f" (as built to {run.assembly(run.recommended).label})")
    blocks = opening_blocks(
        run.case.name, run.case.description, _case_table(run),
        run.success and (yields is None or yields.signed_off),
        figures + compared if yields is None else
        f"{run.judged_columns.removeprefix('the ')}: {yields.sentence}; {figures}{compared}")
    if trade is not None:
        blocks.append(Paragraph(trade))
    blocks += [Heading(2, "Geometry from the hardpoints"), _geometry_table(run),
               _shaft_table(run), Paragraph(CONVENTION), _scene(run),
               Heading(2, "Can phasing cancel the fluctuation?"), _cancel_table(run),
               Heading(2, "Assemblies compared"), _assembly_table(run),
               Heading(2, "Yoke phasing for the fitter"), *fitter_blocks(run)]
    splines = run.splines
    if splines is not None:
        subject = ("the best continuous phasing" if splines.objective == "RE"
                   else "the continuous phasing of that objective")
        blocks += [Paragraph(f"Best on the splines for the {splines.objective}: "
                             f"{number(splines.residual_error, '.6g')} at the teeth, against "
                             f"{number(splines.continuous_residual_error, '.6g')} for "
                             f"{subject} (loss "
                             f"{number(splines.loss, '.3g')}; {splines.method}, "
                             f"{splines.assemblies_evaluated} assemblies evaluated, "
                             f"{len(splines.ties)} tied)."),
                   Heading(3, "Assembly instructions"),
                   *[Paragraph(item.text) for item in splines.instructions]]
    moved = run.joint_centres
    if moved is not None:
        blocks += [Heading(2, "Joint positions moved within their boxes"), *_joint_blocks(moved)]
    blocks += steering_blocks(run)
    blocks += robust_blocks(run)
    blocks += [Heading(2, "Excitation over rpm"), *_excitation_blocks(run),
               Heading(2, NUMERICS_HEADING), Paragraph(run.verdict), *_exact_set_blocks(run),
               *([] if moved is None or moved.exact_optima is None
                 else [Heading(3, "Joint positions: the set of exact optima"),
                       *exact_optima_blocks(moved.exact_optima)])]
    images = [Image(name, CAPTIONS[name]) for name in image_files]
    return blocks + closing_blocks(run.warnings, run.versions, images)


def _scene(run: ColumnRun) -> Scene:
    from sso._reports.column_scene import column_scene

    return Scene(column_scene(run), VIEW_CAPTION)


def _case_table(run: ColumnRun) -> Table:
    excitation = run.excitation["as_built"]
    rows = [("case file", run.case.source), ("kind", run.case.kind),
            ("run", {"optimise": "phasing, spline teeth and joint-position optimisation",
                     "evaluate": "analysis of the assembly as built"}[run.mode]),
            ("joints", str(run.geometry.joint_count)),
            ("application", excitation.application),
            ("vehicle (limits)", excitation.vehicle),
            ("spline teeth", ", ".join(str(t) for t in run.case.teeth or ()) or "not given")]
    return Table(("item", "value"), tuple(rows))


def _geometry_table(run: ColumnRun) -> Table:
    geometry = run.geometry
    points = geometry.points_mm
    rows = []
    for index, point in enumerate(points):
        coordinates = ", ".join(f"{value:.1f}" for value in point)
        if index in (0, len(points) - 1):
            role = "input shaft point" if index == 0 else "output shaft point"
            rows.append((f"P{index}", role, coordinates, "-"))
        else:
            straight = " (straight)" if geometry.straight_joints[index - 1] else ""
            rows.append((f"P{index}", f"joint {index}", coordinates,
                         number(geometry.beta_deg[index - 1], ".4f") + straight))
    return Table(("point", "role", "x, y, z (mm)", "operating angle beta (deg)"), tuple(rows))


def _shaft_table(run: ColumnRun) -> Table:
    lengths = run.geometry.shaft_length_mm
    gammas = run.geometry.plane_angle_deg
    rows = []
    for shaft, length in enumerate(lengths):
        gamma = number(gammas[shaft - 1], ".4f") if 1 <= shaft <= len(gammas) else "-"
        rows.append((shaft_name(shaft, len(lengths)), f"P{shaft} to P{shaft + 1}",
                     number(length, ".1f"), gamma))
    return Table(("shaft", "from, to", "length (mm)", "bend-plane angle gamma (deg)"),
                 tuple(rows))


def _cancel_table(run: ColumnRun) -> Table:
    verdict = run.cancel
    rows = (("rule", verdict.rule),
            ("RE = 0 reachable", "yes" if verdict.possible else "no"),
            ("margin cos(beta_max) - prod cos(beta_other)", number(verdict.margin, ".6g")),
            ("limiting joint", str(verdict.limiting_joint)),
            ("Spicer small-angle margin sum beta_other^2 - beta_max^2 (deg^2)",
             number(verdict.small_angle_margin_deg2, ".4g")),
            ("least RE any phasing reaches", number(verdict.minimum_residual_error, ".6g")))
    return Table(("criterion", "value"), rows)


def _assembly_table(run: ColumnRun) -> Table:
    rows = tuple((assembly.label, _angles(assembly.yoke_phase_deg), _angles(assembly.phase_deg),
                  number(assembly.residual_error, ".6g"))
                 for assembly in run.assemblies)
    return Table(("assembly", "yoke phasing delta (deg)", "model phase phi (deg)", "RE"), rows)


def _exact_set_blocks(run: ColumnRun) -> list[Block]:
    phasing = run.phasing
    extent = None if phasing is None else phasing.exact_optimum_extent_deg
    witnesses = None if phasing is None else phasing.exact_optimum_extent_witnesses_deg
    exact = None if phasing is None else phasing.optimisation.exact_optima
    if phasing is None or extent is None or witnesses is None or exact is None:
        return []
    ends = "; ".join(f"shaft {shaft + 1}: "
                     + ("every phasing" if high - low >= 180.0 else
                        f"a single value, {number(low, '.3f')} deg"
                        if number(low, ".3f") == number(high, ".3f") else
                        f"{number(low, '.3f')} to {number(high, '.3f')} deg")
                     for shaft, (low, high) in enumerate(extent))
    rows = tuple((str(shaft + 1), side, number(value, ".3f"), _angles(witness),
                  number(end.witness_residual_error, ".3g"))
                 for shaft, ((low, high), pair, found) in enumerate(
                     zip(extent, witnesses, exact.extent_search.ends, strict=True))
                 for side, value, witness, end in _sides((low, high), pair, found))
    text = (f"RE = 0 is reached on a set of exact optima of dimension "
            f"{exact.dimension}; the best continuous phasing is the one "
            f"{phasing.exact_optimum_criterion}. The set's extent in delta about "
            f"it, sought modulo 180 deg ({number(180.0 / EXTENT_GRID, '.3g')} deg "
            f"steps each way from the chosen phasing to the first where no exact "
            f"optimum is found, then "
            f"bisection; {exact.extent_search.solves} least-squares solves): "
            f"{ends}.")
    if all(side == "from = to" for _, side, *_ in rows):
        return [Paragraph(f"{text} Each shaft's delta is a single value: no other phasing "
                          "near the chosen one reaches RE = 0.")]
    return [Paragraph(f"{text} Each end is the furthest phasing at which an exact optimum "
                      "was found, a lower estimate; its witness below is that exact "
                      "optimum (every shaft's delta, deg)."),
            Table(("intermediate shaft", "end", "delta (deg)", "witness delta (deg)",
                   "witness RE"), rows)]


def _sides(ends: tuple[float, float], witnesses: Sequence[Sequence[float]],
           found: Sequence[Any]) -> list[tuple[str, float, Sequence[float], Any]]:
    """Each end of a set's extent in delta with its witness; one ("from = to") where
    the two read as a single value."""
    sides = list(zip(("from", "to"), ends, witnesses, found, strict=True))
    if number(ends[0], ".3f") == number(ends[1], ".3f"):
        return [("from = to", *sides[0][1:])]
    return sides


def _joint_blocks(moved: JointCentresResult) -> list[Block]:
    given = moved.initial.points_mm
    rows = []
    for joint in range(1, len(given) - 1):
        before, after = given[joint], moved.points_mm[joint]
        travel = sum((a - b) ** 2 for a, b in zip(after, before, strict=False)) ** 0.5
        rows.append((str(joint), ", ".join(f"{value:.2f}" for value in before),
                     ", ".join(f"{value:.2f}" for value in after), number(travel, ".3f"),
                     number(moved.initial.beta_deg[joint - 1], ".3f"),
                     number(moved.geometry.beta_deg[joint - 1], ".3f")))
    phasing = "free" if moved.phasing_free else "fixed"
    summary = (("yoke phasing", f"{phasing}: {_angles(moved.yoke_phase_deg)} deg"),
               ("RE at the given points (start phasing)", number(moved.initial_re, ".6g")),
               ("least RE over phasing at the given points",
                number(moved.fixed_points_re, ".6g")),
               ("RE with the joints moved", number(moved.fun, ".6g")),
               ("largest bound violation", number(moved.constraint_violation, ".3g")),
               ("cross-check", moved.crosscheck.message if moved.crosscheck else
                "one solver, no cross-check"))
    return [Table(("joint", "given x, y, z (mm)", "moved x, y, z (mm)", "travel (mm)",
                   "beta given (deg)", "beta moved (deg)"), tuple(rows)),
            Table(("item", "value"), summary)]


def _excitation_blocks(run: ColumnRun) -> list[Block]:
    labels = {assembly.role: assembly.label for assembly in run.assemblies}
    angle_rows = tuple((labels[role], number(table.angles.drive_deg, ".4f"),
                        number(table.angles.coast_deg, ".4f"),
                        number(table.angles.torsional_deg, ".4f"),
                        number(table.angles.exact_deg, ".4f"))
                       for role, table in run.excitation.items())
    first = run.excitation["as_built"]
    judged = first.application == "driveline"
    limits = (f"Limits ({first.vehicle}): inertial (drive, coast) and torsional, as "
              "used by driveline makers." if judged else
              "The SAE AE-7 limits (inertial 1000 / 2000, torsional 300 / 500 rad/s^2) are "
              "for propeller shafts at driveline speeds: they do not judge a steering column, "
              "so no row is marked within or outside them (excitation.application = "
              "'steering'); the steering criteria above judge it.")
    blocks: list[Block] = [
        Paragraph("Equivalent angles (deg): SAE AE-7 small-angle figures, and the exact chain "
                  "as one joint (beta_eq). Excitation = omega^2 sin^2(angle), rad/s^2; the "
                  "exact output acceleration is the largest |d w_out/dt| at constant input "
                  f"speed. {limits}"),
        Table(("assembly", "drive", "coast", "torsional", "exact beta_eq"), angle_rows)]
    for role, table in run.excitation.items():
        table_rows = tuple((number(row.input_speed_rpm, ".4g"),
                            number(row.drive_rad_s2, ".4g"), number(row.coast_rad_s2, ".4g"),
                            number(row.torsional_rad_s2, ".4g"),
                            number(row.exact_torsional_rad_s2, ".4g"),
                            number(row.exact_output_accel_rad_s2, ".4g"),
                            *((f"{row.inertial_limit_rad_s2:g} / "
                               f"{row.torsional_limit_rad_s2:g}",
                               "yes" if row.within_limits else "NO") if judged else ()))
                           for row in table)
        limit_header = ("limits inertial / torsional", "within") if judged else ()
        blocks += [Heading(3, labels[role]),
                   Table(("rpm", "drive", "coast", "torsional", "exact torsional",
                          "exact output accel", *limit_header), table_rows)]
    return blocks


def _angles(values: Sequence[float]) -> str:
    return ", ".join(number(value, ".3f") for value in values)
