"""``sso report`` reads a saved result back with ``from_dict`` and checks it as strictly
as a case file (issue 23 item 9): exit 2 and the field named, never a report of nonsense."""

from __future__ import annotations

import json
import re
import subprocess
import sys

import pytest

import sso
from sso._cli.saved_results import read_saved_result, result_classes
from sso._record import RecordError

GEOMETRY = sso.ColumnGeometry([[0.0, 0.0, 0.0], [0.0, 0.0, 300.0], [50.0, 30.0, 600.0],
                               [120.0, 60.0, 800.0], [200.0, 60.0, 1000.0]])


def sso_report(*arguments):
    return subprocess.run([sys.executable, "-m", "sso", "report", *map(str, arguments)],
                          capture_output=True, text=True, timeout=300)


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    folder = tmp_path_factory.mktemp("saved") / "phasing"
    result = sso.optimise(GEOMETRY, starts=2)
    sso.write_report(result, folder, formats=("json",))
    return result, json.loads((folder / "result.json").read_text())


def test_every_public_result_class_can_be_named():
    assert {"PhasingResult", "OptimisationResult", "SweepResult",
            "ExcitationTable"} <= set(result_classes())


def test_report_reads_the_result_back_and_writes_its_reports(saved, tmp_path):
    result, data = saved
    path = tmp_path / "result.json"
    path.write_text(json.dumps(data))
    completed = sso_report(path)
    assert completed.returncode == 0, completed.stderr
    assert read_saved_result(path) == result
    assert {item.name for item in tmp_path.iterdir()} == {"result.json", "report.md",
                                                          "report.html", "sso-files.json"}
    assert (tmp_path / "report.md").read_text().startswith("# Phasing: ")


@pytest.mark.parametrize(("edit", "message"), [
    (lambda data: data.update(fun=-5.0), "fun = -5.0; allowed: a finite number >= 0"),
    (lambda data: data.update(fun={"float": "nan"}), "fun = nan"),
    (lambda data: data["optimisation"].update(input_speed_rpm=-25.0),
     "optimisation.input_speed_rpm = -25.0; allowed: a finite number > 0"),
    (lambda data: data["optimisation"].update(option=99),
     "optimisation.option = 99; allowed: 1, 2 or 3"),
    (lambda data: data.update(type="bogus"), "type = 'bogus'; allowed: BatchResult"),
    (lambda data: data.update(version=7), "version = 7; this sso reads version 1"),
    (lambda data: data["verdict"].update(margin="wide"),
     "verdict.margin = 'wide'; allowed: a number"),
    (lambda data: data["geometry"].update(points_mm=[[0, 0, 0]]),
     "geometry \\(ColumnGeometry\\)"),
])
def test_report_refuses_nonsense_with_exit_2_naming_the_field(saved, tmp_path, edit, message):
    _, data = saved
    edited = json.loads(json.dumps(data))
    edit(edited)
    path = tmp_path / "result.json"
    path.write_text(json.dumps(edited))
    with pytest.raises(RecordError, match=message):
        read_saved_result(path)
    completed = sso_report(path, "--quiet")
    assert completed.returncode == 2
    assert completed.stderr.startswith("error: ") and "Traceback" not in completed.stderr
    assert sorted(item.name for item in tmp_path.iterdir()) == ["result.json"]


@pytest.mark.parametrize("content", ["[]", "{", "\"text\"", "{\"type\": 3}"])
def test_report_refuses_what_is_no_saved_result(tmp_path, content):
    path = tmp_path / "result.json"
    path.write_text(content)
    completed = sso_report(path)
    assert completed.returncode == 2 and "Traceback" not in completed.stderr


@pytest.fixture(scope="module")
def case_run(tmp_path_factory):
    """The result.json of ``sso run`` on a shipped shaft-series case."""
    folder = tmp_path_factory.mktemp("run")
    completed = subprocess.run(
        [sys.executable, "-m", "sso", "run", "cases/paper_option1_exact.toml", "--out",
         str(folder), "--formats", "json", "--quiet"], capture_output=True, text=True,
        timeout=300)
    assert completed.returncode == 0, completed.stderr
    return json.loads((folder / "paper_option1_exact" / "result.json").read_text())


def _set(path):
    def edit(data, value):
        for key in path[:-1]:
            data = data[key]
        data[path[-1]] = value
    return edit


@pytest.mark.parametrize(("path", "value", "message"), [
    # issue 23, item 9: each of these rendered with exit 0 before
    (("optimisation", "compared", 1, "evaluation", "residual_error"), -5.0,
     "optimisation.compared\\[1\\].evaluation.residual_error = -5.0; allowed: a finite "
     "number >= 0"),
    (("optimisation", "best", "fun"), {"float": "nan"},
     "optimisation.best.fun = nan with success = true"),
    (("optimisation", "input_speed_rpm"), -25.0,
     "optimisation.input_speed_rpm = -25.0; allowed: a finite number > 0"),
    (("case", "case", "input_speed_rpm"), -25.0,
     "case \\(Case\\): .*input_speed_rpm = -25 is outside the allowed range"),
    (("optimisation", "option"), 99, "optimisation.option = 99; allowed: 1, 2 or 3"),
    (("case", "case", "option"), 99, "option = 99 is not one of 1, 2, 3"),
    (("case", "case", "kind"), "bogus", "kind = 'bogus' is not one of"),
    (("type",), "bogus", "type = 'bogus'; allowed: "),
])
def test_report_of_a_case_run_refuses_nonsense_naming_the_field(case_run, tmp_path, path,
                                                                 value, message):
    edited = json.loads(json.dumps(case_run))
    _set(path)(edited, value)
    saved = tmp_path / "result.json"
    saved.write_text(json.dumps(edited))
    completed = sso_report(saved, "--quiet")
    assert completed.returncode == 2, completed.stdout
    assert re.search(message, completed.stderr), completed.stderr
    assert "Traceback" not in completed.stderr
    assert sorted(item.name for item in tmp_path.iterdir()) == ["result.json"]
