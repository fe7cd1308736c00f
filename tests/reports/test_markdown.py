"""Markdown of a report: case text is escaped, never rendered as markup."""

import pytest


@pytest.mark.parametrize("text, written", [
    ("< 1e-15", "< 1e-15"),                      # cannot start a tag: stays readable
    ("a <b>bold</b> try", "a &lt;b&gt;bold&lt;/b&gt; try"),
    ("<!-- hidden -->", "&lt;!-- hidden --&gt;"),
    ("R&D &amp; &#60;", "R&amp;D &amp;amp; &amp;#60;"),
    ("5 & 6", "5 & 6"),
])
def test_markdown_escapes_only_what_could_start_markup(text, written):
    from sso._reports.markdown import render_markdown
    from sso._reports.summary import Paragraph

    assert render_markdown([Paragraph(text)]) == written + "\n"


INJECTIONS = (
    "![tracker](https://evil.example/pixel.png)",
    "[click me](javascript:alert(1))",
    "first line\n## Verdict\nOK: nothing to see",
    "<https://evil.example>",
    "**loud** _quiet_ `code`",
    "# not a heading",
    "1. not a list",
    "> not a quote",
)


@pytest.mark.parametrize("text", INJECTIONS)
def test_markdown_renders_case_text_as_text(text):
    """Issue 23 item 8: no link, image, heading, list, quote, emphasis or code from case text.

    Checked against an independent Markdown implementation: the HTML that
    markdown-it (CommonMark) renders from the paragraph holds no element but one
    <p>, and its text is the original, whitespace folded."""
    import markdown_it

    from sso._reports.markdown import render_markdown
    from sso._reports.summary import Paragraph, Table

    rendered = markdown_it.MarkdownIt("commonmark").render(render_markdown([Paragraph(text)]))
    assert rendered.startswith("<p>") and rendered.count("<") == 2, rendered
    shown = html_text(rendered)
    assert shown == " ".join(text.split())
    cell = markdown_it.MarkdownIt("commonmark").enable("table").render(
        render_markdown([Table(("label",), ((text,),))]))
    assert "<a" not in cell and "<img" not in cell and "<h2" not in cell
    assert "<strong" not in cell and "<em" not in cell and "<code" not in cell


def html_text(rendered: str) -> str:
    import html
    import re

    return html.unescape(re.sub(r"<[^>]+>", "", rendered)).strip()


def test_report_md_of_a_case_escapes_description_and_reference_label(tmp_path):
    """Issue 23 item 8, end to end: a case's description and reference label."""
    from sso._cli.app import main

    case = tmp_path / "hostile.toml"
    case.write_text(
        'name = "hostile"\n'
        'description = "![x](https://evil.example/a.png) [go](javascript:alert(1)) '
        '\\n## Verdict\\nOK"\n'
        "option = 1\n"
        "[design]\nbeta_deg = [15.0, 20.0]\nphase_deg = [30.0]\n"
        '[reference]\nlabel = "[ref](javascript:alert(2))"\nbeta_deg = [15.0, 20.0]\n'
        "phase_deg = [90.0]\n")
    assert main(["evaluate", str(case), "--out", str(tmp_path / "out"), "--quiet",
                 "--no-plots"]) == 0
    import markdown_it

    markdown = (tmp_path / "out" / "hostile" / "report.md").read_text()
    rendered = markdown_it.MarkdownIt("commonmark").enable("table").render(markdown)
    assert "<a " not in rendered and "<img" not in rendered
    assert "[go](javascript:alert(1)) ## Verdict OK" in html_text(rendered)
    assert "[ref](javascript:alert(2))" in html_text(rendered)
