"""The result-file round trip, without the command line."""

import json
import math

import pytest
from paper_trials import paper_trial_case

from sso.cases.schema import load_case
from sso.reports.writer import (
    ResultFileError,
    read_result,
    render,
    result_json,
    write_report,
)
from sso.run.document import evaluate_case


def test_result_json_is_strict_json():
    text = result_json({"finite": 1.5, "nested": [math.inf, {"value": math.nan}]})
    assert json.loads(text) == {"finite": 1.5, "nested": [None, {"value": None}]}


def test_evaluation_document_round_trips_through_result_json(tmp_path):
    document = evaluate_case(load_case(paper_trial_case(2, "paper", tmp_path)))
    write_report(document, tmp_path, ["json", "csv"])
    assert read_result(tmp_path / "result.json") == json.loads(result_json(document))
    evaluation = document["designs"]["initial"]["evaluation"]
    # docs/model.md: paper model, option 2 trial design at 25 rpm: 22.07 .. 28.31 rpm.
    assert evaluation["speed_min_rpm"] == pytest.approx(22.07, abs=5e-3)
    assert evaluation["speed_max_rpm"] == pytest.approx(28.31, abs=5e-3)
    assert render(document, ["csv"]) == {"speeds.csv": (tmp_path / "speeds.csv").read_bytes()}


@pytest.mark.parametrize("content, message", [
    ("[1, 2]", "not a result document"),
    ('{"schema_version": 1}', "result document lacks kind, mode, case"),
    ("\u00ff", "not a JSON result file"),
])
def test_read_result_refuses_what_it_cannot_render(tmp_path, content, message):
    path = tmp_path / "result.json"
    path.write_text(content, encoding="latin-1")
    with pytest.raises(ResultFileError, match=message):
        read_result(path)
