"""``report.md``: the report blocks as Markdown.

Strings are HTML-escaped (Markdown passes inline HTML through) and table cells
have their pipes escaped and line breaks folded.
"""

from __future__ import annotations

import html
from collections.abc import Sequence

from sso.reports.summary import Block, Heading, Image, Paragraph, Table


def render_markdown(blocks: Sequence[Block]) -> str:
    """Markdown text of the report."""
    parts = []
    for block in blocks:
        if isinstance(block, Heading):
            parts.append(f"{'#' * block.level} {_escape(block.text)}")
        elif isinstance(block, Paragraph):
            parts.append(_escape(block.text))
        elif isinstance(block, Table):
            lines = [_row(block.header), _row(tuple("---" for _ in block.header))]
            lines += [_row(row) for row in block.rows]
            parts.append("\n".join(lines))
        elif isinstance(block, Image):
            parts.append(f"![{_escape(block.caption)}]({block.file_name})")
    return "\n\n".join(parts) + "\n"


def _escape(text: str) -> str:
    return html.escape(text, quote=False)


def _row(cells: Sequence[str]) -> str:
    escaped = [_escape(" ".join(cell.split())).replace("|", "\\|") for cell in cells]
    return "| " + " | ".join(escaped) + " |"
