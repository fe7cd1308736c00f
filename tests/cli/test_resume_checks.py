"""``sso sweep --resume`` keeps no row whose figures cannot be true (issue 34 item 4).

Each test runs a real sweep (``sso sweep`` in a subprocess), edits its ``sweep.csv`` as
the issue did, resumes, and expects exit 2 naming the line and the field, with the
file left as it was (nothing of the user's lost). Reference values: the RE of each row
is what sso wrote; the re-evaluated RE is the closed form of the exact model
(sso.ShaftSeries.evaluate) and of a column's chain matrix.

The modules under test: sso/_studies/row_checks.py.
"""

from __future__ import annotations

import csv
import io
import json
import shutil
from pathlib import Path

import pytest
from test_cli import sso

from sso._studies.row_checks import RECHECKED_ROWS, cell_problem

ROOT = Path(__file__).resolve().parents[2]
SWEEP = f"""
case = "{ROOT / 'cases' / 'paper_option1_exact.toml'}"
name = "edited"
[axes]
"design.beta_deg[1]" = {{ start = 10, stop = 25, num = 6 }}
"solver.starts" = [1]
"""
COLUMN_SWEEP = f"""
case = "{ROOT / 'cases' / 'column_truck_three_joints.toml'}"
action = "evaluate"
name = "edited"
[axes]
"tilt.angle_deg" = [-4.0, 0.0, 4.0]
"""


@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sweep")
    (folder / "edited.toml").write_text(SWEEP, encoding="utf-8")
    completed = sso("sweep", "edited.toml", "--workers", "1", "--no-plots", "--quiet",
                    cwd=folder)
    assert completed.returncode == 0, completed.stderr
    return folder


@pytest.fixture
def copy(finished, tmp_path):
    shutil.copytree(finished, tmp_path / "run")
    return tmp_path / "run"


def _edit(csv_path: Path, point: int, **cells: str) -> None:
    with open(csv_path, newline="", encoding="utf-8") as handle:
        rows = list(csv.reader(handle))
    header = rows[0]
    for row in rows[1:]:
        if int(row[0]) == point:
            for column, text in cells.items():
                row[header.index(column)] = text
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="\n").writerows(rows)
    csv_path.write_text(buffer.getvalue(), encoding="utf-8")


def _line_of(csv_path: Path, point: int) -> int:
    lines = csv_path.read_text(encoding="utf-8").splitlines()
    return next(number for number, line in enumerate(lines, 1)
                if line.split(",", 1)[0] == str(point))


@pytest.mark.parametrize("cells, field", [
    ({"residual_error": "-5"}, "residual_error = '-5' is negative; it is >= 0"),
    ({"residual_error": "nan"}, "residual_error = 'nan' is not a finite number"),
    ({"residual_error": ""}, "residual_error is empty; a finished row holds it"),
    ({"success": "maybe"}, "success = 'maybe' is not true or false"),
    ({"ipopt_status": "0.5"}, "ipopt_status = '0.5' is not a whole number"),
    ({"design_phase_deg[1]": "inf"}, "design_phase_deg[1] = 'inf' is not a finite number"),
    ({"design_beta_deg[0]": ""}, "design_beta_deg[0] is empty; a finished row holds it"),
    ({"design_beta_deg[2]": "[1.0]"}, "design_beta_deg[2] = '[1.0]' is not a finite number"),
    ({"time_s": "-1e-3"}, "time_s = '-1e-3' is negative"),
])
def test_an_impossible_figure_is_refused_naming_line_and_field(copy, cells, field):
    csv_path = copy / "results" / "edited" / "sweep.csv"
    _edit(csv_path, 5, **cells)
    before = csv_path.read_bytes()
    resumed = sso("sweep", "edited.toml", "--resume", "--no-plots", cwd=copy)
    assert resumed.returncode == 2, resumed.stdout + resumed.stderr
    assert f"sweep.csv line {_line_of(csv_path, 5)} (point 5): {field}" in resumed.stderr
    assert "Traceback" not in resumed.stderr
    assert "lowest RE" not in resumed.stdout
    assert csv_path.read_bytes() == before  # nothing of the user's lost


def test_a_plausible_but_false_re_is_found_by_the_recomputed_sample(copy):
    # Every row's RE halved: each cell is a valid number, so only computing the RE
    # again from the row's design (design_beta_deg, design_phase_deg) finds it. With 6
    # rows and RECHECKED_ROWS = 8 every row is computed again; the first, point 0.
    assert RECHECKED_ROWS == 8  # as docs/guide/sweeps.md says
    csv_path = copy / "results" / "edited" / "sweep.csv"
    with open(csv_path, newline="", encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle))
    for row in rows:
        _edit(csv_path, int(row["point"]),
              residual_error=repr(float(row["residual_error"]) / 2 + 1e-6))
    resumed = sso("sweep", "edited.toml", "--resume", "--no-plots", cwd=copy)
    assert resumed.returncode == 2, resumed.stdout + resumed.stderr
    saved = float(rows[0]["residual_error"]) / 2 + 1e-6
    assert (f"sweep.csv line {_line_of(csv_path, 0)} (point 0): residual_error = {saved!r} "
            "is not the RE of the row's design, computed again: "
            f"{float(rows[0]['residual_error'])!r}") in resumed.stderr
    assert "Traceback" not in resumed.stderr


def test_the_rows_as_written_are_kept(copy):
    csv_path = copy / "results" / "edited" / "sweep.csv"
    before = csv_path.read_bytes()
    resumed = sso("sweep", "edited.toml", "--resume", "--no-plots", cwd=copy)
    assert resumed.returncode == 0, resumed.stderr
    assert "6 from an earlier run" in resumed.stdout
    assert csv_path.read_bytes() == before


def test_a_column_rows_re_is_computed_again_from_its_yoke_phasing(tmp_path):
    (tmp_path / "edited.toml").write_text(COLUMN_SWEEP, encoding="utf-8")
    completed = sso("sweep", "edited.toml", "--workers", "1", "--no-plots", "--quiet",
                    cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    csv_path = tmp_path / "results" / "edited" / "sweep.csv"
    assert sso("sweep", "edited.toml", "--resume", "--no-plots",
               cwd=tmp_path).returncode == 0
    _edit(csv_path, 1, **{"yoke_phase_deg[0]": "0.0", "yoke_phase_deg[1]": "0.0"})
    resumed = sso("sweep", "edited.toml", "--resume", "--no-plots", cwd=tmp_path)
    assert resumed.returncode == 2, resumed.stdout + resumed.stderr
    assert (f"sweep.csv line {_line_of(csv_path, 1)} (point 1): residual_error = "
            in resumed.stderr)
    assert "is not the RE of the row's design, computed again" in resumed.stderr


@pytest.mark.parametrize("column, text", [
    ("residual_error", "1e-3"), ("residual_error", "0.0"), ("success", "false"),
    ("ipopt_status", "-2"), ("joint_centres_points_mm[2][1]", "-1.5"), ("tooth_offset[0]", "-3"),
    ("joint_centres_margin_mm", "-0.5"), ("lm_residual_error", ""),
])
def test_values_sso_writes_pass(column, text):
    assert cell_problem(column, text, "ok") is None


def test_an_element_of_a_shorter_list_may_be_empty_and_a_tooth_offset_is_whole():
    assert cell_problem("design_beta_deg[3]", "", "ok") is None
    assert cell_problem("tooth_offset[1]", "2.5", "ok") == \
        "tooth_offset[1] = '2.5' is not a whole number"


def test_a_sweep_in_the_list_layout_of_an_older_sso_is_refused_with_exit_2(copy):
    # The folder as sso wrote it before each list element had a column: sweep.json of
    # schema 2, and each design's angles as one cell "[a, b, c]".
    folder = copy / "results" / "edited"
    identity = json.loads((folder / "sweep.json").read_text(encoding="utf-8"))
    (folder / "sweep.json").write_text(json.dumps({**identity, "schema_version": 2}),
                                       encoding="utf-8")
    with open(folder / "sweep.csv", newline="", encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle))
    older = [{**{name: value for name, value in row.items() if "_deg[" not in name},
              "design_beta_deg": json.dumps([float(row[f"design_beta_deg[{k}]"])
                                             for k in range(3)])} for row in rows]
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(older[0]), lineterminator="\n")
    writer.writeheader()
    writer.writerows(older)
    (folder / "sweep.csv").write_text(buffer.getvalue(), encoding="utf-8")
    assert buffer.getvalue().splitlines()[1].count('"[') == 1
    resumed = sso("sweep", "edited.toml", "--resume", "--no-plots", cwd=copy)
    assert resumed.returncode == 2, resumed.stdout + resumed.stderr
    assert "Traceback" not in resumed.stderr
    assert ("holds a sweep written by an older sso (sweep schema 2; this sso writes 3, each "
            "element of a list in a column of its own, design_beta_deg[0], ..., where schema 2 "
            "held the whole list in one cell); it cannot be resumed: run the sweep afresh in "
            "another out_dir") in resumed.stderr
