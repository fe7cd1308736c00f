"""Report files of a mechanism result: ``table.csv``, ``report.md``/``.html`` and plots.

Rendered from the run alone (:class:`sso._run.mechanism_run.MechanismRun`), with
the same Markdown and HTML writers as the shaft series, so both reports say the
same thing and every string is escaped for its format.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from sso._cases.mechanism import DESIGN_KIND, DESIGN_LINKS
from sso._limits import REPORT_DIGITS
from sso._linkages.fourbar_swing import FourBarDesignResult
from sso._linkages.registry import linkage_of
from sso._linkages.table import MechanismTable
from sso._reports.documents import report_files
from sso._reports.html import render_html
from sso._reports.markdown import render_markdown
from sso._reports.mechanism_plots import render_mechanism_plots
from sso._reports.summary import (
    Block,
    Heading,
    Image,
    Paragraph,
    Table,
    closing_blocks,
    number,
    opening_blocks,
)
from sso._run.mechanism_run import LinkageCurves, MechanismRun

TABLE_FILE = "table.csv"
DESIGN_DESCRIPTION = (
    "A four-bar design made in Python: the crank-rocker of the largest rocker swing within "
    "the link and transmission-angle bounds. Its tables over crank angle and its plots are "
    "in the report of a case of kind fourbar_design (sso run), which holds the drive and "
    "plot settings.")
CAPTIONS = {
    "linkage.png": "Link positions at the case's plot angles (plots.crank_angles_deg), with "
                   "the paths of the joints and, for a four-bar, the coupler curve.",
    "angular_motion.png": "Angular velocities and accelerations of the links against crank "
                          "angle.",
    "transmission_angle.png": "Transmission angle against crank angle; the shaded band is the "
                              "recommended (or, for a design, the imposed) range.",
    "piston_motion.png": "Piston velocity and acceleration against crank angle: exact and the "
                         "two-term series approximation.",
    "rod_motion.png": "Connecting-rod angle, angular velocity and angular acceleration against "
                      "crank angle.",
    "slider_motion.png": "Slider C position, velocity and acceleration, and the speed and "
                         "acceleration magnitude of joint B, against crank angle.",
}


def mechanism_files(run: MechanismRun, formats: tuple[str, ...]) -> dict[str, bytes]:
    """The files of a mechanism run's report in ``formats`` (``result.json`` excepted)."""
    return report_files(formats, lambda: table_files(run), lambda: render_mechanism_plots(run),
                        lambda images: mechanism_blocks(run, images))


def design_files(design: FourBarDesignResult, formats: tuple[str, ...]) -> dict[str, bytes]:
    """The files of the report of a four-bar design made in Python (``result.json``
    excepted): ``report.md`` and ``report.html`` from the result alone.

    A design result holds the start and optimum linkages, their swings, the optimum's
    transmission angles, the bounds and the solvers; it holds no drive or plot
    settings, so its report has no tables over crank angle and no plots (a case of
    kind ``fourbar_design`` run with ``sso run`` has them).
    """
    return report_files(formats, dict, dict, lambda images: design_blocks(design))


def design_blocks(design: FourBarDesignResult) -> list[Block]:
    """Blocks of the report of a four-bar design result."""
    low, high = design.optimum_transmission_angle_deg
    allowed_low, allowed_high = design.transmission_angle_bounds_deg
    linkages = Table(("linkage", *DESIGN_LINKS, "rocker swing (deg)"), (
        ("initial", *(number(getattr(design.initial, name), ".6g") for name in DESIGN_LINKS),
         number(design.initial_swing_deg, ".6g")),
        (f"optimum ({design.best.solver})",
         *(number(getattr(design.optimum, name), ".6g") for name in DESIGN_LINKS),
         number(design.optimum_swing_deg, ".6g"))))
    bounds = Table(("quantity", "lower", "upper", "optimum"), (
        *((f"{name} length", number(lower, ".6g"), number(upper, ".6g"),
           number(getattr(design.optimum, name), ".6g"))
          for name, (lower, upper) in design.link_bounds.items()),
        ("transmission angle over a revolution (deg)", number(allowed_low, ".6g"),
         number(allowed_high, ".6g"), f"{number(low, '.6g')} to {number(high, '.6g')}")))
    return [*opening_blocks("four-bar design", DESIGN_DESCRIPTION,
                            Table(("item", "value"), (("made with", "sso.optimise in Python"),
                                                      ("problem", "largest rocker swing"))),
                            design.success, design.verdict),
            Heading(2, "Linkages"), linkages, Heading(2, "Bounds"), bounds,
            Heading(2, "Solvers"), _solver_table(design), Heading(2, "Cross-check"),
            Paragraph(_crosscheck_text(design))]


def table_files(run: MechanismRun) -> dict[str, str]:
    """CSV text of each table: ``table.csv`` for the main linkage (the optimum of a
    design), ``table_<role>.csv`` for the others.

    Six significant digits (``result.json`` keeps every digit); each column name
    ends in its unit, lengths in the case's (``joint_a_x_mm``).
    """
    main = run.main.role
    return {(TABLE_FILE if linkage.role == main else f"table_{linkage.role}.csv"):
            linkage.table.csv_text(run.case.length_unit, REPORT_DIGITS)
            for linkage in run.linkages}


def unit_text(unit: str, length_unit: str) -> str:
    """A table unit with ``length`` replaced by the case's length unit."""
    return unit.replace("length", length_unit)


def mechanism_blocks(run: MechanismRun, image_files: Sequence[str]) -> list[Block]:
    """Blocks of the whole report of a mechanism run.

    Parameters
    ----------
    run : MechanismRun
    image_files : sequence of str
        Plot files written beside the report (empty when plots are off).
    """
    case = run.case
    blocks = opening_blocks(case.name, case.description, _case_table(run), run.success,
                            run.verdict)
    blocks += [Heading(2, "Linkage"), _linkage_table(run)]
    for linkage in run.linkages:
        blocks += [Heading(2, f"Extremes over the crank revolution ({linkage.label})"),
                   Paragraph("Sampled every 0.1 deg of crank angle over a whole revolution "
                             "from the case's start, so these are the true extremes, not the "
                             "table's grid values."),
                   _extremes_table(linkage, case.length_unit)]
    if run.method_difference is not None:
        blocks += [Heading(2, "Exact vs series piston motion (the paper's Tabel 2)"),
                   Paragraph("Mean over the table's crank angles of |exact - series| / |exact| "
                             "* 100, rows where both are zero counted as 0, with the correct "
                             "formulas. The paper's Tabel 2 prints 8.25/12.76/17.78 % (velocity) "
                             "and 0.50/2.34/19.91 % (acceleration) for r2 = 0.05/0.075/0.10 m: "
                             "those follow from its defective trig velocity and complex alpha3."),
                   _method_difference_table(run.method_difference, case.length_unit)]
    if run.design is not None:
        blocks += [Heading(2, "Solvers"), _solver_table(run.design), Heading(2, "Cross-check"),
                   Paragraph(_crosscheck_text(run.design))]
    for linkage in run.linkages:
        blocks += [Heading(2, f"Table ({linkage.label}; every column is in the CSV)"),
                   _rows_table(linkage, case.length_unit)]
    images = [Image(name, CAPTIONS[name]) for name in image_files]
    return blocks + closing_blocks(run.warnings, run.versions, images)


def _case_table(run: MechanismRun) -> Table:
    case = run.case
    values = case.values
    rows = [("case file", case.source), ("kind", case.kind),
            ("run", {"analyse": "analysis", "optimise": "design optimisation",
                     "evaluate": "analysis of the start linkage only"}[run.mode]),
            ("length unit", case.length_unit),
            ("crank speed (rad/s)", number(case.crank_speed_rad_s)),
            ("crank acceleration (rad/s^2)", number(case.crank_accel_rad_s2)),
            ("crank angles (deg)", f"{number(values['drive.start_deg'])} to "
                                   f"{number(values['drive.stop_deg'])} step "
                                   f"{number(values['drive.step_deg'])}"),
            ("unassembled angles", values["drive.on_unassembled"])]
    if "plots.coupler_point" in values:
        along, across = values["plots.coupler_point"]
        rows.append(("coupler point P (coupler lengths along A->B, left of it)",
                     f"{number(along)}, {number(across)}"))
    if case.kind == DESIGN_KIND:
        unit = case.length_unit
        rows += [(f"{name} bounds ({unit})", f"[{number(low)}, {number(high)}]")
                 for name, (low, high) in ((name, values[f"bounds.{name}"])
                                           for name in DESIGN_LINKS)]
        low, high = values["bounds.transmission_angle_deg"]
        rows += [("transmission angle bounds (deg)", f"[{number(low)}, {number(high)}]"),
                 ("solvers", ", ".join(values["solver.solvers"])),
                 ("starts per solver", str(values["solver.starts"])),
                 ("solver tolerance", number(values["solver.solver_tol"], "g"))]
    rows.append(("created (UTC)", run.created_utc))
    return Table(("item", "value"), tuple(rows))


def _linkage_table(run: MechanismRun) -> Table:
    unit = run.case.length_unit
    parameters = [vars(linkage.mechanism) for linkage in run.linkages]
    rows = []
    for name, value in parameters[0].items():
        suffix = "" if isinstance(value, str) else f" ({unit})"
        rows.append((f"{name}{suffix}", *[_cell(each[name]) for each in parameters]))
    if run.linkages[0].grashof is not None:
        rows.append(("Grashof class", *[str(linkage.grashof) for linkage in run.linkages]))
        rows.append(("rocker swing (deg)", *[number(linkage.swing_deg, ".6g")
                                             for linkage in run.linkages]))
    return Table(("parameter", *[linkage.label for linkage in run.linkages]), tuple(rows))


def _cell(value: Any) -> str:
    return value if isinstance(value, str) else number(value, ".8g")


def _extremes_table(linkage: LinkageCurves, length_unit: str) -> Table:
    rows = tuple((f"{row.column} ({unit_text(row.unit, length_unit)})",
                  number(row.min, ".6g"), number(row.min_at_deg, ".4g"),
                  number(row.max, ".6g"), number(row.max_at_deg, ".4g"))
                 for row in linkage.extremes)
    return Table(("quantity", "min", "at crank angle (deg)", "max", "at crank angle (deg)"),
                 rows)


def _method_difference_table(difference: MechanismTable, unit: str) -> Table:
    rows = tuple((number(crank, ".6g"), number(rod, ".6g"), number(velocity, ".2f"),
                  number(accel, ".2f"))
                 for crank, rod, velocity, accel in zip(
                     difference["crank"], difference["rod"],
                     difference["velocity_difference_pct"],
                     difference["acceleration_difference_pct"], strict=True))
    return Table((f"crank ({unit})", f"rod ({unit})", "velocity difference (%)",
                  "acceleration difference (%)"), rows)


def _solver_table(design: FourBarDesignResult) -> Table:
    rows = tuple((name, "yes" if solution.success else "no", solution.message,
                  number(-math.degrees(solution.fun), ".8g"),
                  number(solution.kkt, ".2g"), number(solution.constraint_violation, ".2g"),
                  str(solution.nit), number(solution.time_s, ".3f"),
                  str(solution.start_index))
                 for name, solution in design.solutions.items())
    return Table(("solver", "success", "message", "rocker swing (deg)", "KKT residual",
                  "constraint violation", "iterations", "time (s)", "start"), rows)


def _crosscheck_text(design: FourBarDesignResult) -> str:
    check = design.crosscheck
    verdict = "one solver: no cross-check" if check is None else check.message
    swings = ", ".join(number(-math.degrees(value), ".6g") for value in design.local_minima)
    return (f"{verdict}. Objective: minus the rocker swing (rad). Distinct swings (deg) the "
            f"successful runs stopped at: {swings or 'none'}.")


def _rows_table(linkage: LinkageCurves, length_unit: str) -> Table:
    table = linkage.table
    columns = [name for name in linkage_of(linkage.mechanism).report_columns
               if name in table.columns]
    if "assembled" in table.columns:
        columns.append("assembled")
    header = tuple(f"{name} ({unit_text(table.units[name], length_unit)})"
                   if table.units[name] in ("length", "length/s", "length/s^2") else name
                   for name in columns)
    rows = tuple(tuple(_table_cell(_plain_cell(table[name][index])) for name in columns)
                 for index in range(len(table)))
    return Table(header, rows)


def table_report(table: MechanismTable, formats: tuple[str, ...]) -> dict[str, bytes]:
    """Report files of a :class:`sso.MechanismTable` made in Python.

    ``table.csv`` (six digits, names ending in their units, lengths in the unit
    the links were given in, written ``length``), ``result.json`` (every digit),
    and ``report.md``/``report.html`` with each column's range and the rows. The
    table does not know its linkage, so there are no plots: a case file run with
    ``sso run`` draws them.
    """
    files: dict[str, bytes] = {}
    if "csv" in formats:
        files[TABLE_FILE] = table.csv_text("length", REPORT_DIGITS).encode("utf-8")
    names = table.unit_names("length")
    summary = next(part for part in table._summary_parts() if not isinstance(part, str))
    blocks: list[Block] = [
        Heading(1, f"Mechanism analysis: {table.name}"),
        Paragraph(f"{len(table)} rows. Lengths are in the unit the links were given in "
                  "(written 'length'); angles in deg, angular rates in rad/s and rad/s^2."),
        Heading(2, "Columns"), Table(summary.header, summary.rows),
        Heading(2, "Rows"),
        Table(tuple(names), tuple(tuple(_table_cell(_plain_cell(values[index]))
                                        for values in table.columns.values())
                                  for index in range(len(table)))),
    ]
    if "md" in formats:
        files["report.md"] = render_markdown(blocks).encode("utf-8")
    if "html" in formats:
        files["report.html"] = render_html(blocks, {}).encode("utf-8")
    return files


def _plain_cell(value: Any) -> Any:
    return bool(value) if isinstance(value, np.bool_) else float(value)


def _table_cell(value: Any) -> str:
    if isinstance(value, bool):
        return "yes" if value else "no"
    return number(value, ".6g")
