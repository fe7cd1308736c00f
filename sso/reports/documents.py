"""``report.md`` and ``report.html`` of one report's blocks, as its formats ask."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from sso.reports.summary import Block


def render_documents(blocks: Sequence[Block], images: Mapping[str, bytes],
                     formats: Sequence[str]) -> dict[str, bytes]:
    """The Markdown and HTML reports of ``blocks`` that ``formats`` name, by file name.

    Parameters
    ----------
    blocks : sequence of Block
        The report's content.
    images : mapping of str to bytes
        PNG bytes of each image block's file (embedded in the HTML).
    formats : sequence of str
        ``"md"`` and ``"html"`` are rendered if named; other formats are ignored.
    """
    files: dict[str, bytes] = {}
    if "md" in formats:
        from sso.reports.markdown import render_markdown

        files["report.md"] = render_markdown(blocks).encode("utf-8")
    if "html" in formats:
        from sso.reports.html import render_html

        files["report.html"] = render_html(blocks, images).encode("utf-8")
    return files
