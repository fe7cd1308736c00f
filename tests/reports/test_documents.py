"""One function renders report.md and report.html from the same blocks."""

from __future__ import annotations

from sso._reports.documents import render_documents
from sso._reports.summary import Heading, Paragraph


def test_only_the_formats_asked_for():
    blocks = [Heading(1, "Title"), Paragraph("a < b")]
    assert set(render_documents(blocks, {}, ("md", "csv"))) == {"report.md"}
    files = render_documents(blocks, {}, ("md", "html"))
    assert files["report.md"].decode() == "# Title\n\na < b\n"
    assert "<p>a &lt; b</p>" in files["report.html"].decode()
    assert render_documents(blocks, {}, ("json",)) == {}
