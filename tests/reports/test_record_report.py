"""The report of a result without a report kind of its own: its summary, as blocks."""

from __future__ import annotations

import sso
from sso._reports.record_report import record_blocks, render_record
from sso._reports.summary import Heading, Paragraph, Table


def test_the_blocks_are_the_summary_parts():
    verdict = sso.can_cancel([10.0, 12.0, 5.0])
    blocks = record_blocks(verdict)
    assert blocks[0] == Heading(1, "Can the fluctuation cancel? no: no yoke phasing cancels "
                                   "the fluctuation")
    tables = [block for block in blocks if isinstance(block, Table)]
    assert dict(tables[0].rows)["limiting joint (largest angle)"] == "P2"
    assert blocks[-1] == Paragraph(f"rule: {verdict.rule}")


def test_markdown_and_html_say_the_same():
    verdict = sso.can_cancel([10.0, 12.0, 5.0])
    files = render_record(verdict, ("md", "html"))
    markdown = files["report.md"].decode()
    html = files["report.html"].decode()
    assert "| limiting joint (largest angle) | P2 |" in markdown
    assert "<td>limiting joint (largest angle)</td><td>P2</td>" in html
    assert not any(isinstance(block, Paragraph) and not block.text
                   for block in record_blocks(verdict))
