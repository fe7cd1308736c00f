"""``report.md``: the report blocks as Markdown.

Every text is the user's or the result's, never Markdown: a case's description or
a reference's label must not become a link, an image, emphasis or a heading.
Markdown passes inline HTML through, so every ``<`` or ``&`` that could start a tag
or an entity (``<`` before a letter, ``/``, ``!`` or ``?``; ``&`` before a letter or
``#``) and every ``>`` is written as an entity; a ``<`` or ``&`` that cannot start
markup stays as it is, so ``< 1e-15`` reads as itself in the file too. The
characters that make links, images, emphasis and code (backslash, backtick, ``*``,
``[``, which opens every link, image and link definition, and ``_`` outside a word)
are escaped with a backslash; line breaks
are folded into spaces, and a paragraph that would start a heading, a list or a
quote has that character escaped. Table cells also have their pipes escaped.
"""

from __future__ import annotations

import re
from collections.abc import Sequence

from sso._reports.summary import Block, Heading, Image, Paragraph, Scene, Table


def render_markdown(blocks: Sequence[Block]) -> str:
    """Markdown text of the report."""
    parts = []
    for block in blocks:
        if isinstance(block, Heading):
            parts.append(f"{'#' * block.level} {_escape(block.text)}")
        elif isinstance(block, Paragraph):
            parts.append(_escape_block(block.text))
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


INLINE = re.compile(r"[\\`*\[]|(?<![A-Za-z0-9])_|_(?![A-Za-z0-9])")
BLOCK_START = re.compile(r"^(\s*)(?:([#+\-=|~])|(\d+)([.)]))")


def _escape(text: str) -> str:
    """``text`` as literal Markdown on one line: no link, image, emphasis or code."""
    folded = " ".join(text.split())
    escaped = MARKUP.sub(lambda match: ENTITIES[match.group()], folded)
    return INLINE.sub(lambda match: "\\" + match.group(), escaped)


def _escape_block(text: str) -> str:
    """``text`` as a literal paragraph or heading: also no list, quote or heading of its own."""
    return BLOCK_START.sub(lambda match: (match.group(1) + "\\" + match.group(2)
                                          if match.group(2) else
                                          match.group(1) + match.group(3) + "\\"
                                          + match.group(4)), _escape(text))


def _row(cells: Sequence[str]) -> str:
    escaped = [_escape(cell).replace("|", "\\|") for cell in cells]
    return "| " + " | ".join(escaped) + " |"
