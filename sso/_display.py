"""How numbers and short summaries of results are shown to people.

One rule for every number a person reads (summaries, ``repr``, report tables):
:data:`~sso._limits.REPORT_DIGITS` significant digits, and magnitudes at or below
:data:`~sso._limits.ROUND_OFF_FLOOR` printed as ``"< 1e-15"``. The result classes
build their ``summary()`` and ``_repr_html_`` from plain parts (:class:`TextTable`
and lines of text) rendered here, so no result imports the report writers above it.
"""

from __future__ import annotations

import dataclasses
import html
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from sso._limits import REPORT_DIGITS, ROUND_OFF_FLOOR

FLOOR_TEXT = f"< {ROUND_OFF_FLOOR:g}"
"""How a magnitude at or below the round-off floor is printed."""

NOT_AVAILABLE = "n/a"
REPR_LIMIT = 400
"""Longest ``repr`` of a public result, characters."""


def format_number(value: Any, digits: int = REPORT_DIGITS) -> str:
    """A number as a person should read it.

    Parameters
    ----------
    value : float, int, bool or None
        The number; None and non-finite floats print as ``"n/a"``.
    digits : int
        Significant digits (at most :data:`~sso._limits.REPORT_DIGITS` in reports).

    Returns
    -------
    str
        ``"0"`` for an exact zero, ``"< 1e-15"`` for a magnitude at or below the
        round-off floor, otherwise ``digits`` significant digits (``"%g"`` style).
        Integers and booleans print as themselves.
    """
    if isinstance(value, (bool, int)):
        return str(value)
    if value is None:
        return NOT_AVAILABLE
    number = float(value)
    if not math.isfinite(number):
        return NOT_AVAILABLE
    if number == 0.0:
        return "0"
    if abs(number) <= ROUND_OFF_FLOOR:
        return FLOOR_TEXT
    return f"{number:.{digits}g}"


def format_numbers(values: Sequence[Any], digits: int = REPORT_DIGITS) -> str:
    """Comma-separated numbers, e.g. a design's angles: ``"15, 20, 9"``."""
    return ", ".join(format_number(value, digits) for value in values)


def shorten(text: str, limit: int) -> str:
    """``text`` cut to at most ``limit`` characters, ending in ``"..."`` if cut."""
    return text if len(text) <= limit else text[:max(limit - 3, 0)] + "..."


@dataclass(frozen=True)
class TextTable:
    """A small table of plain-text cells for a summary."""

    header: tuple[str, ...]
    rows: tuple[tuple[str, ...], ...]


Part = str | TextTable
"""A summary is a sequence of parts: lines of text and tables."""


def render_text(parts: Sequence[Part]) -> str:
    """Plain text of a summary: tables with aligned columns, one line per text part."""
    lines: list[str] = []
    for part in parts:
        if isinstance(part, str):
            lines.append(part)
            continue
        cells = [part.header, *part.rows]
        widths = [max(len(row[column]) for row in cells) for column in range(len(part.header))]
        for index, row in enumerate(cells):
            padded = (cell.ljust(width) for cell, width in zip(row, widths, strict=True))
            lines.append("  ".join(padded).rstrip())
            if index == 0:
                lines.append("  ".join("-" * width for width in widths))
    return "\n".join(lines)


def render_html(parts: Sequence[Part]) -> str:
    """An HTML fragment of a summary (for notebooks); every string is escaped."""
    body: list[str] = []
    for part in parts:
        if isinstance(part, str):
            body.append(f"<p>{html.escape(part)}</p>")
            continue
        header = "".join(f"<th>{html.escape(cell)}</th>" for cell in part.header)
        rows = "".join("<tr>" + "".join(f"<td>{html.escape(cell)}</td>" for cell in row)
                       + "</tr>" for row in part.rows)
        body.append('<div style="overflow-x: auto"><table><thead><tr>' + header
                    + f"</tr></thead><tbody>{rows}</tbody></table></div>")
    return "<div>" + "".join(body) + "</div>"


class Readable:
    """``summary()``, ``_repr_html_`` and a short ``repr`` from two methods.

    A result class lists its summary in :meth:`_summary_parts` and its one-line
    description in :meth:`_repr_text`; the text and HTML are rendered here. A
    dataclass that defines neither gets both from its plain fields (numbers,
    text, flags and short tuples of numbers; arrays and nested objects are
    left out). Dataclasses using it must pass ``repr=False`` so their generated
    ``repr`` does not replace this one.
    """

    def _summary_parts(self) -> list[Part]:
        rows = tuple((name, text) for name, text in _plain_fields(self))
        return [type(self).__name__, TextTable(("field", "value"), rows)]

    def _repr_text(self) -> str:
        return ", ".join(f"{name}={text}" for name, text in _plain_fields(self))

    def summary(self) -> str:
        """A short plain-text table of what the result says."""
        return render_text(self._summary_parts())

    def _repr_html_(self) -> str:
        return render_html(self._summary_parts())

    def __repr__(self) -> str:
        return shorten(f"{type(self).__name__}({self._repr_text()})", REPR_LIMIT)


PLAIN_TUPLE_LIMIT = 8
"""Longest tuple of numbers a default summary shows."""


def _plain_fields(result: Any) -> list[tuple[str, str]]:
    """``(name, text)`` of a dataclass's fields that read as plain values."""
    if not dataclasses.is_dataclass(result):
        return []
    shown = []
    for field in dataclasses.fields(result):
        value = getattr(result, field.name)
        if isinstance(value, str):
            shown.append((field.name, shorten(value, 80)))
        elif isinstance(value, (bool, int, float)):
            shown.append((field.name, format_number(value)))
        elif (isinstance(value, tuple) and len(value) <= PLAIN_TUPLE_LIMIT
              and all(isinstance(item, (int, float)) for item in value)):
            shown.append((field.name, f"[{format_numbers(value)}]"))
    return shown
