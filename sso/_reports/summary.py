"""The report's content as plain blocks (headings, text, tables, images).

The Markdown and HTML writers render the same blocks, so both reports always say
the same thing. Every string is kept raw here; each writer escapes for its format.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from sso._display import NOT_AVAILABLE, format_number
from sso._limits import REPORT_DIGITS, ROUND_OFF_FLOOR


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
    """An interactive 3D view (:mod:`sso._reports.view3d`): drawn in HTML, named in Markdown."""

    scene: Mapping[str, Any]
    caption: str


Block = Heading | Paragraph | Table | Image | Scene

def number(value: Any, spec: str = ".6g") -> str:
    """Format a number for a report cell.

    ``"n/a"`` for missing or non-finite values, ``"< 1e-15"`` for magnitudes at or
    below :data:`sso._limits.ROUND_OFF_FLOOR`; ``spec`` otherwise, with at most
    :data:`sso._limits.REPORT_DIGITS` significant digits (a ``"g"`` spec asking
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


NUMERICS_HEADING = "Numerics, for whoever checks them"
"""The section of a report that holds the solvers' own account (stationarity, sets of
exact optima, cross-checks): after the figures an engineer signs."""


def opening_blocks(name: str, description: str, case_table: Table, success: bool,
                   verdict: str) -> list[Block]:
    """The start every case report shares: title, description, case table, verdict."""
    blocks: list[Block] = [Heading(1, f"SSO report: {name}")]
    if description:
        blocks.append(Paragraph(description))
    return [*blocks, case_table, Heading(2, "Verdict"),
            Paragraph(f"{'OK' if success else 'FAILED'}: {verdict}")]


def closing_blocks(warnings: Sequence[str], versions: Mapping[str, str] | None,
                   images: Sequence[Image]) -> list[Block]:
    """The end every report shares: warnings, plots (or why there are none), versions.

    Parameters
    ----------
    warnings : sequence of str
        The run's warnings.
    versions : mapping of str to str, or None
        The package versions a run recorded (None: a result made in Python
        records none).
    images : sequence of Image
        The plots written beside the report, captioned (empty when plots are off).

    Returns
    -------
    list of Heading, Paragraph, Table, Image
    """
    blocks: list[Block] = []
    if warnings:
        blocks += [Heading(2, "Warnings"), *[Paragraph(text) for text in warnings]]
    blocks.append(Heading(2, "Plots"))
    if images:
        blocks += images
    else:
        blocks.append(Paragraph("Plots were not written (png not among the formats)."))
    if versions is not None:
        blocks += [Heading(2, "Versions"),
                   Table(("package", "version"), tuple((name, str(version)) for name, version
                                                       in versions.items()))]
    return blocks
