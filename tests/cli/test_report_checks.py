"""``sso report`` certifies no figure it did not check (issue 34 item 3).

Each test edits a real ``result.json`` (written by ``sso run`` in a subprocess) as the
issue did, then runs ``sso report`` on it: exit 2, naming the field, no report
written. Reference values: the figures are recomputed by sso.ShaftSeries.evaluate
(the exact model's closed form) and by the column's chain matrix and sso.can_cancel;
the tolerance is the solvers' agreement rule, 1e-14 + 1e-6 * |RE|
(sso._reports.figure_checks).

The modules under test: sso/_reports/figure_checks.py and sso/_studies/saved_rows.py.
"""

from __future__ import annotations

import copy
import json
import shutil
from pathlib import Path

import pytest
from test_cli import sso

ROOT = Path(__file__).resolve().parents[2]
SERIES_CASE = ROOT / "cases" / "paper_option1_exact.toml"
COLUMN_CASE = ROOT / "cases" / "column_truck_three_joints.toml"


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    folder = tmp_path_factory.mktemp("runs")
    for case in (SERIES_CASE, COLUMN_CASE):
        completed = sso("run", case, "--out", folder, "--formats", "json", "--quiet",
                        cwd=folder)
        assert completed.returncode == 0, completed.stderr
    return {"series": json.loads((folder / SERIES_CASE.stem / "result.json").read_text()),
            "column": json.loads((folder / COLUMN_CASE.stem / "result.json").read_text())}


def _report(tmp_path, document):
    path = tmp_path / "edited" / "result.json"
    path.parent.mkdir()
    path.write_text(json.dumps(document), encoding="utf-8")
    completed = sso("report", path, "--out", tmp_path / "report", "--formats", "md",
                    cwd=tmp_path)
    assert "Traceback" not in completed.stderr
    return completed


def _edited(document, path, value):
    document = copy.deepcopy(document)
    *parents, last = path
    node = document
    for key in parents:
        node = node[key]
    node[last] = value
    return document


def test_the_reports_as_written_are_rendered(saved, tmp_path):
    for kind, document in saved.items():
        folder = tmp_path / kind
        folder.mkdir()
        completed = _report(folder, document)
        assert completed.returncode == 0, completed.stderr
        assert (folder / "report" / "report.md").is_file()


# The edits: best.series set to another design (the paper's reported optimum,
# RE 1.0e-3, beside the saved "RE 1.15e-4"); fun = -1 with success = true; then the
# other figures a report shows.
@pytest.mark.parametrize("path, value, message", [
    (("optimisation", "best", "series", "phase_deg"), [57.4233, 73.2749],
     "optimisation.best.fun = 0.00011470510032229902 is not the figure of "
     "optimisation.best.series, computed again: 0.00099961166257"),
    (("optimisation", "best", "fun"), -1, "optimisation.best.fun = -1.0; allowed: a finite "
                                          "number >= 0"),
    (("optimisation", "best", "fun"), {"float": "nan"}, "optimisation.best.fun = nan with "
                                                        "success = true"),
    (("optimisation", "solutions", "slsqp", "fun"), 1e-20,
     "optimisation.solutions.slsqp.fun = 1e-20 is not the figure of "
     "optimisation.solutions.slsqp.series"),
    (("optimisation", "optimum", "fluctuation"), 0.01,
     "optimisation.optimum.fluctuation = 0.01 is not the figure of optimisation.best.series, "
     "computed again: 0.0302934"),
    (("optimisation", "initial", "residual_error"), 1.0,
     "optimisation.initial.residual_error = 1.0 is not the figure of "
     "optimisation.initial_series"),
    (("compared", 0, "evaluation", "residual_error"), 1e-20,
     "compared[0].evaluation.residual_error = 1e-20 is not the figure of compared[0].series"),
])
def test_an_edited_shaft_series_figure_is_refused_naming_the_field(saved, tmp_path, path,
                                                                   value, message):
    completed = _report(tmp_path, _edited(saved["series"], path, value))
    assert completed.returncode == 2, completed.stdout
    assert message in completed.stderr
    assert not (tmp_path / "report").exists()


def test_an_edited_speed_curve_is_refused(saved, tmp_path):
    document = copy.deepcopy(saved["series"])
    document["compared"][0]["output_speed_rpm"]["data"][5] = 25.0
    completed = _report(tmp_path, document)
    assert completed.returncode == 2
    assert ("compared[0].output_speed_rpm[5] = 25.0 is not the figure of the speed curve of "
            "compared[0].series" in completed.stderr)


@pytest.mark.parametrize("path, value, message", [
    (("assemblies", 0, "residual_error"), 1e-9,
     "assemblies[0].residual_error = 1e-09 is not the figure of assemblies[0].yoke_phase_deg"),
    (("phasing", "x"), [0.0, 0.0], "phasing.fun = 0.0002268227882296"),
    (("cancel", "minimum_residual_error"), 0.0,
     "cancel.minimum_residual_error = 0.0 is not the figure of the column's operating angles"),
    (("phasing", "fun"), -5.0, "phasing.fun = -5.0; allowed: a finite number >= 0"),
])
def test_an_edited_column_figure_is_refused_naming_the_field(saved, tmp_path, path, value,
                                                             message):
    completed = _report(tmp_path, _edited(saved["column"], path, value))
    assert completed.returncode == 2, completed.stdout
    assert message in completed.stderr


def test_every_shipped_case_reads_back(tmp_path):
    # Every figure sso writes passes its own check: the shipped cases of each kind
    # (shaft series exact and paper, columns with positions, mechanisms) run and
    # reported again.
    names = ["paper_option2_paper.toml", "column_truck_three_positions.toml",
             "mechanisms/fourbar_swing_design.toml", "steering_column.toml"]
    for name in names:
        shutil.copy(ROOT / "cases" / name, tmp_path / Path(name).name)
        completed = sso("run", Path(name).name, "--out", "out", "--formats", "json",
                        "--quiet", cwd=tmp_path)
        assert completed.returncode == 0, completed.stderr
        stem = Path(name).stem
        again = sso("report", f"out/{stem}/result.json", "--out", f"again/{stem}",
                    "--formats", "md", cwd=tmp_path)
        assert again.returncode == 0, again.stderr


@pytest.fixture(scope="module")
def saved_sweep(tmp_path_factory):
    import sso

    folder = tmp_path_factory.mktemp("sweep")
    result = sso.sweep(SERIES_CASE, {"design.beta_deg[1]": [10.0, 15.0, 20.0]},
                       action="evaluate", workers=1, plots=False, progress=False)
    sso.write_report(result, folder / "report", formats=("json", "md"))
    return json.loads((folder / "report" / "result.json").read_text())


@pytest.mark.parametrize("cells, message", [
    ({"residual_error": -5.0}, "rows[1] (point 1): residual_error = '-5.0' is negative"),
    ({"success": "maybe"}, "rows[1] (point 1): success = 'maybe' is not true or false"),
    ({"residual_error": 1e-3}, "rows[1] (point 1): residual_error = 0.001 is not the RE of "
                               "the row's design, computed again: 0.00162601519694"),
    ({"design_beta_deg[1]": 12.0}, "rows[1] (point 1): residual_error = "),
    # a row as sso saved sweeps before each list element had a column of its own
    ({"design_beta_deg": [30.0, 15.0, 9.0]}, "rows[1].design_beta_deg holds a list; a "
                                             "sweep's rows hold each element in a column of "
                                             "its own (design_beta_deg[0], design_beta_deg[1], "
                                             "...), so this sweep was saved by an older sso: "
                                             "run it again"),
])
def test_a_saved_sweeps_edited_row_is_refused(saved_sweep, tmp_path, cells, message):
    # The same for a sweep's rows (issue 34 item 3): a SweepResult saved by
    # sso.write_report and read back by sso report. 3 rows < RECHECKED_ROWS: every
    # finished row is computed again.
    document = copy.deepcopy(saved_sweep)
    document["rows"][1].update(cells)
    completed = _report(tmp_path, document)
    assert completed.returncode == 2, completed.stdout
    assert message in completed.stderr


def test_a_saved_sweep_as_written_is_rendered(saved_sweep, tmp_path):
    completed = _report(tmp_path, saved_sweep)
    assert completed.returncode == 0, completed.stderr


def test_an_edited_mechanism_table_is_refused(tmp_path):
    # Mechanism tables, cheap to analyse again (issue 34 item 3): a four-bar's coupler
    # angle at its second crank angle edited by 1 deg.
    completed = sso("run", ROOT / "cases" / "mechanisms" / "fourbar_crank2.toml", "--out",
                    tmp_path / "run", "--formats", "json", "--quiet", cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    document = json.loads((tmp_path / "run" / "fourbar_crank2" / "result.json").read_text())
    data = document["linkages"][0]["table"]["columns"]["coupler_angle_deg"]["data"]
    data[1] += 1.0
    refused = _report(tmp_path, document)
    assert refused.returncode == 2, refused.stdout
    assert (f"linkages[0].table.columns.coupler_angle_deg[1] = {data[1]!r} is not the figure "
            "of the table of linkages[0].mechanism, computed again") in refused.stderr
