"""The report's content as plain blocks (headings, text, tables, images).

The Markdown and HTML writers render the same blocks, so both reports always say
the same thing. Every string is kept raw here; each writer escapes for its format.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from sso.display import NOT_AVAILABLE, format_number
from sso.limits import REPORT_DIGITS, ROUND_OFF_FLOOR
from sso.run.document import DESIGN_ROLES


@dataclass(frozen=True)
class Heading:
    """A section heading (level 1 or 2)."""

    level: int
    text: str


@dataclass(frozen=True)
class Paragraph:
    """A paragraph of plain text."""

    text: str


@dataclass(frozen=True)
class Table:
    """A table of plain-text cells."""

    header: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]


@dataclass(frozen=True)
class Image:
    """A plot, by file name in the report folder."""

    file_name: str
    caption: str


@dataclass(frozen=True)
class Scene:
    """An interactive 3D view (:mod:`sso.reports.view3d`): drawn in HTML, named in Markdown."""

    scene: Mapping[str, Any]
    caption: str


Block = Heading | Paragraph | Table | Image | Scene

# (evaluation field, row label with unit, format)
FIGURES = (
    ("residual_error", "residual error RE (dimensionless)", ".4g"),
    ("residual_error_rpm2", "residual error U = w_in^2 RE (rpm^2)", ".4g"),
    ("speed_min_rpm", "output speed min (rpm)", ".6g"),
    ("speed_max_rpm", "output speed max (rpm)", ".6g"),
    ("fluctuation_rpm", "fluctuation, peak to peak (rpm)", ".4g"),
    ("fluctuation", "fluctuation / input speed (dimensionless)", ".4g"),
    ("mean_speed_ratio", "mean output / input speed", ".6g"),
    ("transmission_error_deg", "transmission error, max |out - in| (deg)", ".4g"),
    ("max_output_accel_rad_s2", "output acceleration, max |dw/dt| (rad/s^2)", ".4g"),
    ("torque_ratio_min", "torque ratio T_out/T_in min", ".6g"),
    ("torque_ratio_max", "torque ratio T_out/T_in max", ".6g"),
    ("samples", "quadrature angles in [0, 180) deg", "d"),
    ("quadrature_error", "quadrature error estimate of RE", ".2g"),
)


def number(value: Any, spec: str = ".6g") -> str:
    """Format a number for a report cell.

    ``"n/a"`` for missing or non-finite values, ``"< 1e-15"`` for magnitudes at or
    below :data:`sso.limits.ROUND_OFF_FLOOR`; ``spec`` otherwise, with at most
    :data:`sso.limits.REPORT_DIGITS` significant digits (a ``"g"`` spec asking
    for more, or none, gets that many).
    """
    if value is None or isinstance(value, float) and not math.isfinite(value):
        return NOT_AVAILABLE
    if isinstance(value, float) and abs(value) <= ROUND_OFF_FLOOR:
        return format_number(value)
    if spec.endswith("g"):
        digits = int(spec[1:-1]) if spec[1:-1] else REPORT_DIGITS
        return format_number(value, min(digits, REPORT_DIGITS))
    return format(value, spec)


def report_blocks(document: Mapping[str, Any], image_files: Sequence[str]) -> list[Block]:
    """Blocks of the whole report.

    Parameters
    ----------
    document : mapping
        A result document (:mod:`sso.run.document`).
    image_files : sequence of str
        Plot files written beside the report (empty when plots are off).

    Returns
    -------
    list of Heading, Paragraph, Table, Image
    """
    case = document["case"]
    roles = [role for role in DESIGN_ROLES if role in document["designs"]]
    blocks: list[Block] = [Heading(1, f"SSO report: {case['name']}")]
    if case.get("description"):
        blocks.append(Paragraph(case["description"]))
    blocks += [_case_table(document), Heading(2, "Verdict"), Paragraph(_verdict(document)),
               Heading(2, "Designs"), _design_table(document, roles),
               Heading(2, "Figures of merit"), _figure_table(document, roles)]
    if document["mode"] == "optimise":
        blocks += [Heading(2, "Solvers"), _solver_table(document),
                   Heading(2, "Cross-check"), Paragraph(_crosscheck_text(document)),
                   Heading(2, "Every run"), _runs_table(document)]
    return blocks + closing_blocks(document, [Image(name, _caption(name))
                                              for name in image_files])


def closing_blocks(document: Mapping[str, Any], images: Sequence[Image]) -> list[Block]:
    """The end every report shares: warnings, plots (or why there are none), versions.

    Parameters
    ----------
    document : mapping
        A result document, with ``warnings`` and ``versions``.
    images : sequence of Image
        The plots written beside the report, captioned (empty when plots are off).

    Returns
    -------
    list of Heading, Paragraph, Table, Image
    """
    blocks: list[Block] = []
    if document["warnings"]:
        blocks += [Heading(2, "Warnings"), *[Paragraph(text) for text in document["warnings"]]]
    blocks.append(Heading(2, "Plots"))
    if images:
        blocks += images
    else:
        blocks.append(Paragraph("Plots were not written (png not among the formats)."))
    blocks += [Heading(2, "Versions"),
               Table(("package", "version"), tuple((name, str(version)) for name, version
                                                   in document["versions"].items()))]
    return blocks


def _case_table(document: Mapping[str, Any]) -> Table:
    case = document["case"]
    rows = [("case file", str(document["case_file"])),
            ("kind", document["kind"]),
            ("run", "optimisation" if document["mode"] == "optimise" else "evaluation only"),
            ("model", document["model"]),
            ("option", f"{document['option']} ({document['option_name']})"),
            ("input speed (rpm)", number(document["input_speed_rpm"])),
            ("operating-angle bounds (deg)", _bounds_text(case["bounds"]["beta_deg"])),
            ("phase bounds (deg)", _bounds_text(case["bounds"]["phase_deg"]))]
    if document["mode"] == "optimise":
        rows += [("solvers", ", ".join(case["solver"]["solvers"])),
                 ("starts per solver", str(document["starts"])),
                 ("solver tolerance", number(case["solver"]["solver_tol"], "g"))]
    quadrature = document["quadrature"]
    rows += [("quadrature angles (objective)", str(quadrature["samples"])),
             ("quadrature error estimate", number(quadrature["error_estimate"], ".2g")),
             ("created (UTC)", document["created_utc"])]
    return Table(("item", "value"), tuple(rows))


def _bounds_text(bounds: Any) -> str:
    if bounds and isinstance(bounds[0], list):
        return "; ".join(f"[{number(low, 'g')}, {number(high, 'g')}]" for low, high in bounds)
    return f"[{number(bounds[0], 'g')}, {number(bounds[1], 'g')}] each"


def _verdict(document: Mapping[str, Any]) -> str:
    status = "OK" if document["success"] else "FAILED"
    return f"{status}: {document['verdict']}"


def _design_table(document: Mapping[str, Any], roles: list[str]) -> Table:
    designs = document["designs"]
    joints = len(designs["initial"]["beta_deg"])
    rows = [(f"beta_{index + 1} (deg)",
             *[number(designs[role]["beta_deg"][index]) for role in roles])
            for index in range(joints)]
    rows += [(f"phi_{index + 1} (deg)",
              *[number(designs[role]["phase_deg"][index]) for role in roles])
             for index in range(joints - 1)]
    return Table(("angle", *[designs[role]["label"] for role in roles]), tuple(rows))


def _figure_table(document: Mapping[str, Any], roles: list[str]) -> Table:
    designs = document["designs"]
    rows = tuple((label, *[number(designs[role]["evaluation"][field], spec) for role in roles])
                 for field, label, spec in FIGURES)
    return Table(("figure", *[designs[role]["label"] for role in roles]), rows)


def _solver_table(document: Mapping[str, Any]) -> Table:
    rows = tuple((name, "yes" if solution["success"] else "no", str(solution["status"]),
                  solution["message"], number(solution["fun"], ".4g"),
                  number(solution["kkt"], ".2g"), str(solution["nit"]), str(solution["nfev"]),
                  str(solution["total_nfev"]), number(solution["time_s"], ".3f"),
                  str(solution["start_index"]))
                 for name, solution in document["solutions"].items())
    return Table(("solver", "success", "status", "message", "RE", "KKT residual (1/rad)",
                  "iterations", "evaluations", "evaluations, all starts", "time (s)", "start"),
                 rows)


def _runs_table(document: Mapping[str, Any]) -> Table:
    rows = tuple((run["solver"], str(run["start_index"]), "yes" if run["success"] else "no",
                  number(run["fun"], ".4g"), number(run["kkt"], ".2g"), str(run["nit"]),
                  number(run["time_s"], ".3f"))
                 for run in document["runs"])
    return Table(("solver", "start", "success", "RE", "KKT residual (1/rad)",
                  "iterations", "time (s)"), rows)


def _crosscheck_text(document: Mapping[str, Any]) -> str:
    check = document["crosscheck"]
    verdict = "one solver: no cross-check" if check is None else check["message"]
    minima = ", ".join(number(value, ".4g") for value in document["local_minima"])
    return f"{verdict}. Distinct RE values the successful runs stopped at: {minima or 'none'}."


def _caption(file_name: str) -> str:
    if file_name.startswith("polar"):
        return ("Input and output speed (rpm, radius from 0 at the centre) against input shaft "
                "angle (deg), polar.")
    return "Input and output speed (rpm) against input shaft angle (deg)."
