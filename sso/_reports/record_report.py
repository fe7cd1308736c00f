"""The report of a result that has no report kind of its own: its summary, written out.

``report.md`` and ``report.html`` render the result's summary (the parts its
``summary()`` and ``_repr_html_`` show: lines of text and tables) as report
blocks; ``result.json`` is added by :func:`sso._reports.kinds.render_report` for
every result. Nothing is recomputed: the report says what the result holds.
"""

from __future__ import annotations

from typing import Any

from sso._display import TextTable
from sso._reports.documents import render_documents
from sso._reports.summary import Block, Heading, Paragraph, Table


def record_blocks(result: Any) -> list[Block]:
    """The report blocks of a result's summary: its title, then its text and tables."""
    parts = result._summary_parts()
    title = parts[0] if parts and isinstance(parts[0], str) else type(result).__name__
    blocks: list[Block] = [Heading(1, title)]
    for part in parts[1:] if parts and isinstance(parts[0], str) else parts:
        if isinstance(part, TextTable):
            blocks.append(Table(part.header, part.rows))
        else:
            blocks.append(Paragraph(part))
    return blocks


def render_record(result: Any, formats: tuple[str, ...]) -> dict[str, bytes]:
    """``report.md`` and ``report.html`` of ``result``, as asked for in ``formats``."""
    return render_documents(record_blocks(result), {}, formats)
