"""The files of one report, as its formats ask: its tables, plots, ``report.md`` and
``report.html``."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

from sso._reports.html import render_html
from sso._reports.markdown import render_markdown
from sso._reports.summary import Block


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
        files["report.md"] = render_markdown(blocks).encode("utf-8")
    if "html" in formats:
        files["report.html"] = render_html(blocks, images).encode("utf-8")
    return files


def report_files(formats: Sequence[str], tables: Callable[[], Mapping[str, str]],
                 plots: Callable[[], Mapping[str, bytes]],
                 blocks: Callable[[Sequence[str]], Sequence[Block]]) -> dict[str, bytes]:
    """Every file of one report that ``formats`` name (``result.json`` excepted).

    Parameters
    ----------
    formats : sequence of str
        ``"csv"``, ``"png"``, ``"md"``, ``"html"`` (others are ignored).
    tables : callable
        ``() -> {file name: CSV text}``, called only for ``"csv"``.
    plots : callable
        ``() -> {file name: PNG bytes}``, called only for ``"png"`` (so a report
        without plots never imports matplotlib).
    blocks : callable
        ``(plot file names) -> blocks`` of the Markdown and HTML reports.
    """
    files: dict[str, bytes] = {}
    if "csv" in formats:
        files.update({name: text.encode("utf-8") for name, text in tables().items()})
    images: dict[str, bytes] = dict(plots()) if "png" in formats else {}
    files.update(images)
    if "md" in formats or "html" in formats:
        files.update(render_documents(blocks(tuple(images)), images, formats))
    return files
