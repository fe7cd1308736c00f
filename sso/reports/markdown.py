"""``report.md``: the report blocks as Markdown.

Markdown passes inline HTML through, so every ``<`` or ``&`` that could start a tag
or an entity (``<`` before a letter, ``/``, ``!`` or ``?``; ``&`` before a letter or
``#``) and every ``>`` is written as an entity; a ``<`` or ``&`` that cannot start
markup stays as it is, so ``< 1e-15`` reads as itself in the file too. Table
cells have their pipes escaped and line breaks folded.
"""

from __future__ import annotations

import re
from collections.abc import Sequence

from sso.reports.summary import Block, Heading, Image, Paragraph, Scene, Table


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
        elif isinstance(block, Scene):
            parts.append(f"{_escape(block.caption)} (an interactive 3D view: open report.html)")
    return "\n\n".join(parts) + "\n"


MARKUP = re.compile(r"<(?=[A-Za-z/!?])|&(?=[A-Za-z#])|>")
ENTITIES = {"<": "&lt;", "&": "&amp;", ">": "&gt;"}


def _escape(text: str) -> str:
    return MARKUP.sub(lambda match: ENTITIES[match.group()], text)


def _row(cells: Sequence[str]) -> str:
    escaped = [_escape(" ".join(cell.split())).replace("|", "\\|") for cell in cells]
    return "| " + " | ".join(escaped) + " |"
