"""The result-file round trip, without the command line."""

import json
import math

import pytest
from paper_trials import paper_trial_case

from sso._cases.schema import load_case
from sso._reports.kinds import write_report
from sso._reports.writer import ResultFileError, read_result, result_json
from sso._run.shaft_series import ShaftSeriesRun, run_shaft_series


def test_result_json_is_strict_json():
    text = result_json({"finite": 1.5, "nested": [math.inf, {"value": math.nan}]})
    assert json.loads(text) == {"finite": 1.5, "nested": [None, {"value": None}]}


def test_evaluation_round_trips_through_result_json(tmp_path):
    run = run_shaft_series(load_case(paper_trial_case(2, "paper", tmp_path)), optimising=False)
    write_report(run, tmp_path / "report", ["json", "csv"])
    saved = json.loads((tmp_path / "report" / "result.json").read_text())
    again = ShaftSeriesRun.from_dict(saved)
    assert again == run
    evaluation = again.designs[0].evaluation
    # docs/model.md: paper model, option 2 trial design at 25 rpm: 22.07 .. 28.31 rpm.
    assert evaluation.speed_min_rpm == pytest.approx(22.07, abs=5e-3)
    assert evaluation.speed_max_rpm == pytest.approx(28.31, abs=5e-3)
    write_report(again, tmp_path / "again", ["csv"])
    assert ((tmp_path / "again" / "speeds.csv").read_bytes()
            == (tmp_path / "report" / "speeds.csv").read_bytes())


@pytest.mark.parametrize("content, message", [
    ("[1, 2]", "not a result document"),
    ('{"schema_version": 1}', "kind = None is no result document this sso reads"),
    ('{"schema_version": 1, "kind": "column"}', "result document lacks mode, case"),
    ("\u00ff", "not a JSON result file"),
])
def test_read_result_refuses_what_it_cannot_render(tmp_path, content, message):
    path = tmp_path / "result.json"
    path.write_text(content, encoding="latin-1")
    with pytest.raises(ResultFileError, match=message):
        read_result(path)


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


@pytest.fixture(scope="module")
def column_result(tmp_path_factory):
    """The result document of ``sso run`` of a shipped column case, as saved."""
    from pathlib import Path

    from sso._run.column_document import column_document

    root = Path(__file__).resolve().parents[2]
    case = load_case(root / "cases" / "column_truck_three_joints.toml")
    folder = tmp_path_factory.mktemp("column")
    write_report(column_document(case, optimising=True), folder, ["json"])
    return json.loads((folder / "result.json").read_text())


@pytest.mark.parametrize(("edit", "message"), [
    # issue 23, item 9, for a column's result document
    (lambda data: data["assemblies"][0].update(residual_error=-5.0),
     r"assemblies\[0\]\.residual_error = -5\.0; allowed: a finite number >= 0"),
    (lambda data: data["designs"]["optimum"]["evaluation"].update(residual_error=-5.0),
     r"designs\.optimum\.evaluation\.residual_error = -5\.0"),
    (lambda data: data["phasing"].update(fun=None, success=True),
     r"phasing\.fun = null with success = true"),
    (lambda data: data["phasing"].update(in_phase_re=-1),
     r"phasing\.in_phase_re = -1\.0; allowed: a finite number >= 0"),
])
def test_a_column_result_with_values_out_of_range_is_refused(column_result, tmp_path, edit,
                                                              message):
    read_back = tmp_path / "as_saved.json"
    read_back.write_text(json.dumps(column_result))
    assert read_result(read_back) == column_result
    edited = json.loads(json.dumps(column_result))
    edit(edited)
    path = tmp_path / "result.json"
    path.write_text(json.dumps(edited))
    with pytest.raises(ResultFileError, match=message):
        read_result(path)
