"""The ``sso`` command on the planar-mechanism cases, run for real in a subprocess.

Reference values: tests/data/reference/*.csv and the README beside them (cited per test).
"""

import csv
import json
import re
from pathlib import Path

import pytest
from reference_tables import REFERENCE
from test_cli import png_size, sso, sso_loading, write_case

from sso._cases.schema import load_case
from sso._record import RECORD_VERSION
from sso._run.mechanism_run import MechanismRun


def read_run(folder: Path) -> MechanismRun:
    """The mechanism run saved in ``folder/result.json``, read back with ``from_dict``."""
    return MechanismRun.from_dict(json.loads((folder / "result.json").read_text()))

ROOT = Path(__file__).resolve().parents[2]
CASES = ROOT / "cases" / "mechanisms"
ANALYSIS_CASES = ("fourbar_crank2", "fourbar_crank3", "fourbar_crank4", "fourbar_crank5",
                  "slidercrank_r2_0p050m", "slidercrank_r2_0p075m", "slidercrank_r2_0p100m",
                  "quickreturn")
PLOTS = {
    "fourbar": ("linkage.png", "angular_motion.png", "transmission_angle.png"),
    "slidercrank": ("linkage.png", "piston_motion.png", "rod_motion.png"),
    "quickreturn": ("linkage.png", "angular_motion.png", "slider_motion.png",
                    "transmission_angle.png"),
}
FOURBAR = '''kind = "fourbar"
[linkage]
ground = 12.0
crank = {crank}
coupler = 15.0
rocker = 9.0
[drive]
crank_speed_rad_s = 5.0
step_deg = 20.0
'''


def table_rows(path: Path) -> dict[float, dict[str, str]]:
    with path.open(newline="") as handle:
        rows = list(csv.DictReader(handle))
    key = next(name for name in rows[0] if name.startswith("crank_angle"))
    return {float(row[key]): row for row in rows}


@pytest.fixture(scope="module")
def analysis_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("mechanisms")
    completed = sso("run", *[CASES / f"{name}.toml" for name in ANALYSIS_CASES],
                    "--out", folder, cwd=folder)
    return completed, folder


@pytest.fixture(scope="module")
def design_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("design")
    completed = sso("run", CASES / "fourbar_swing_design.toml", "--out", folder, cwd=folder)
    return completed, folder / "fourbar_swing_design"


def test_every_analysis_case_exits_0_and_writes_its_files(analysis_run):
    completed, folder = analysis_run
    assert completed.returncode == 0, completed.stderr
    assert "Traceback" not in completed.stderr
    for name in ANALYSIS_CASES:
        files = {path.name for path in (folder / name).iterdir()}
        plots = PLOTS[re.sub(r"_.*", "", name)]
        assert files == {"result.json", "table.csv", "report.md", "report.html", "sso-files.json",
                         *plots}, name
        for plot in plots:
            width, height = png_size(folder / name / plot)
            assert width == 1000 and height in (700, 900), (name, plot)
            assert (folder / name / plot).stat().st_size > 20_000, (name, plot)
    assert re.search(r"^quickreturn\s+analysed\s", completed.stdout, re.MULTILINE)


def test_fourbar_csv_matches_the_paper_at_60_deg(analysis_run):
    _, folder = analysis_run
    ours = table_rows(folder / "fourbar_crank2" / "table.csv")[60.0]
    # fourbar_crank2.csv, row 60 (OK rows 0-180): angles printed as int() truncations.
    paper = table_rows(REFERENCE / "fourbar_crank2.csv")[60.0]
    for column, printed in (("coupler_angle_deg", "coupler_angle_deg"),
                            ("rocker_angle_deg", "rocker_angle_deg"),
                            ("transmission_angle_deg", "transmission_angle_deg")):
        assert int(float(ours[column])) == float(paper[printed]), column
    # Each column name ends in its unit; the case gives none, so lengths are "length units".
    for column, printed in (("joint_a_x_length_units", "xA"), ("joint_a_y_length_units", "yA"),
                            ("joint_b_x_length_units", "xB"), ("joint_b_y_length_units", "yB")):
        assert float(ours[column]) == pytest.approx(float(paper[printed]), abs=0.05), column
    assert float(ours["coupler_angular_velocity_rad_s"]) == pytest.approx(
        float(paper["omega_coupler_rad_s"]), abs=5e-5)
    assert float(ours["rocker_angular_velocity_rad_s"]) == pytest.approx(
        float(paper["omega_rocker_rad_s"]), abs=5e-5)
    # The coupler midpoint (plots.coupler_point = [0.5, 0]) is tabulated too.
    assert float(ours["coupler_point_x_length_units"]) == pytest.approx(
        (float(ours["joint_a_x_length_units"]) + float(ours["joint_b_x_length_units"])) / 2,
        rel=1e-5)  # six significant digits in the CSV


def test_slider_crank_csv_matches_the_papers_ok_columns(analysis_run):
    _, folder = analysis_run
    ours = table_rows(folder / "slidercrank_r2_0p100m" / "table.csv")
    # slidercrank_r2_0p100m.csv: theta3, r1, omega3, VB (complex), AB (trig) are OK.
    for angle, paper in table_rows(REFERENCE / "slidercrank_r2_0p100m.csv").items():
        row = ours[angle]
        # README: theta3 is printed as 360.00 at 0 and 180 deg but 0.00 at 360; compare mod 360.
        difference = float(row["rod_angle_deg"]) - float(paper["rod_angle_theta3_deg"])
        assert abs((difference + 180.0) % 360.0 - 180.0) <= 0.005 + 1e-9
        assert float(row["piston_position_m"]) == pytest.approx(
            float(paper["piston_position_r1_m"]), abs=0.005)
        assert float(row["rod_angular_velocity_rad_s"]) == pytest.approx(
            float(paper["rod_angular_velocity_omega3_rad_s"]), abs=0.005)
        assert float(row["piston_velocity_m_s"]) == pytest.approx(
            float(paper["piston_velocity_complex_m_s"]), abs=0.005)
        assert float(row["piston_accel_approximate_m_s2"]) == pytest.approx(
            float(paper["piston_accel_trig_m_s2"]), abs=0.005)
    # README: at 75 deg with r2 = 0.10 the paper prints AB = 33.05; the true value is 153.92.
    assert float(ours[75.0]["piston_accel_m_s2"]) == pytest.approx(153.92, abs=0.005)


def test_quick_return_csv_matches_table_2(analysis_run):
    _, folder = analysis_run
    ours = table_rows(folder / "quickreturn" / "table.csv")
    # quickreturn_table2_positions.csv, numerical columns; within one unit of the 3rd
    # decimal (README note 4), plus half a unit of the 6th significant digit our CSV
    # keeps (5e-4 at 411 mm); A_y at 240 deg is printed with the wrong sign (note 1).
    for angle, paper in table_rows(REFERENCE / "quickreturn_table2_positions.csv").items():
        row = ours[angle]
        printed_a_y = -float(paper["A_y_mm"]) if angle == 240.0 else float(paper["A_y_mm"])
        assert float(row["joint_a_y_mm"]) == pytest.approx(printed_a_y, abs=1.5e-3)
        for ours_column, printed in (("joint_b_x_mm", "B_x_numerical_mm"),
                                     ("joint_b_y_mm", "B_y_numerical_mm"),
                                     ("joint_c_x_mm", "C_x_numerical_mm")):
            assert float(row[ours_column]) == pytest.approx(float(paper[printed]), abs=1.5e-3)


def test_result_json_holds_case_tables_and_true_extremes(analysis_run):
    _, folder = analysis_run
    saved = json.loads((folder / "fourbar_crank5" / "result.json").read_text())
    assert saved["version"] == RECORD_VERSION and saved["type"] == "MechanismRun"
    run = read_run(folder / "fourbar_crank5")
    assert run.case == load_case(CASES / "fourbar_crank5.toml")
    assert run.case.kind == "fourbar" and run.mode == "analyse"
    (given,) = run.linkages
    assert given.role == "given" and given.grashof == "crank-rocker"
    assert len(given.table["crank_angle_deg"]) == 19
    # the curves the plots draw are in the result: every 1 deg over a revolution
    assert len(given.curve["crank_angle_deg"]) == 361
    extremes = {row.column: row for row in given.extremes}
    # README defect 6: the true extremes for crank 5 are -4.5155 @346 and -6.3573 @339 deg.
    assert extremes["coupler_angular_velocity_rad_s"].min == pytest.approx(-4.5155, abs=1e-4)
    assert extremes["coupler_angular_velocity_rad_s"].min_at_deg == pytest.approx(346, abs=0.5)
    assert extremes["rocker_angular_velocity_rad_s"].min == pytest.approx(-6.3573, abs=1e-4)
    assert extremes["rocker_angular_velocity_rad_s"].min_at_deg == pytest.approx(339, abs=0.5)
    extremes = {row.column: row for row in read_run(folder / "quickreturn").linkages[0].extremes}
    # README note 7: max return speed 123.14 @35.9, forward 101.64 @275.5, slider
    # 406.851-505.863 mm, theta4 232.64-295.05 deg (the case tabulates only 0..330).
    assert extremes["joint_c_velocity_x"].min == pytest.approx(-123.14, abs=0.01)
    assert extremes["joint_c_velocity_x"].min_at_deg == pytest.approx(35.9, abs=0.1)
    assert extremes["joint_c_velocity_x"].max == pytest.approx(101.64, abs=0.01)
    assert extremes["joint_c_x"].min == pytest.approx(406.851, abs=1e-3)
    assert extremes["joint_c_x"].max == pytest.approx(505.863, abs=2e-3)
    assert extremes["rocker_angle_deg"].min == pytest.approx(232.64, abs=0.01)
    assert extremes["rocker_angle_deg"].max == pytest.approx(295.05, abs=0.01)


@pytest.mark.parametrize("name, velocity_pct, accel_pct", [
    # README, Tabel 2: the recipe on the correct formulas gives 0.05/0.17/0.41 % and
    # 0.31/1.75/3.64 % (the paper prints 8.25/12.76/17.78 and 0.50/2.34/19.91).
    ("slidercrank_r2_0p050m", 0.05, 0.31),
    ("slidercrank_r2_0p075m", 0.17, 1.75),
    ("slidercrank_r2_0p100m", 0.41, 3.64),
])
def test_reports_regenerate_tabel_2_with_correct_formulas(analysis_run, name, velocity_pct,
                                                          accel_pct):
    _, folder = analysis_run
    columns = read_run(folder / name).method_difference
    assert columns is not None
    assert columns["velocity_difference_pct"][0] == pytest.approx(velocity_pct, abs=0.005)
    assert columns["acceleration_difference_pct"][0] == pytest.approx(accel_pct, abs=0.005)
    report = (folder / name / "report.md").read_text()
    assert f"| {velocity_pct:.2f} | {accel_pct:.2f} |" in report


def test_html_is_self_contained(analysis_run):
    _, folder = analysis_run
    page = (folder / "quickreturn" / "report.html").read_text()
    assert page.count('src="data:image/png;base64,') == 4
    assert "linkage.png" not in re.sub(r'alt="[^"]*"', "", page).replace(
        "plots.crank_angles_deg", "")


def test_report_rerenders_from_result_json_alone(analysis_run, tmp_path):
    _, folder = analysis_run
    source = folder / "slidercrank_r2_0p050m"
    completed = sso("report", source / "result.json", "--out", tmp_path, cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    for name in ("table.csv", "report.md"):
        assert (tmp_path / name).read_bytes() == (source / name).read_bytes(), name
    assert png_size(tmp_path / "piston_motion.png") == (1000, 900)


def test_design_case_solves_and_cross_checks(design_run):
    completed, folder = design_run
    assert completed.returncode == 0, completed.stderr
    run = read_run(folder)
    assert run.mode == "optimise" and run.success is True
    design = run.design
    assert design is not None
    # tests/linkages/test_fourbar_swing.py: 32.3 -> 80.4 deg, IPOPT and SLSQP agree.
    assert design.initial_swing_deg == pytest.approx(32.26, abs=0.01)
    assert design.optimum_swing_deg == pytest.approx(80.37, abs=0.01)
    assert set(design.solutions) == {"ipopt", "slsqp"}
    assert design.crosscheck is not None and design.crosscheck.agree is True
    assert [linkage.mechanism for linkage in run.linkages] == [design.initial, design.optimum]
    low, high = design.optimum_transmission_angle_deg
    assert 40.0 - 1e-6 <= low and high <= 120.0 + 1e-6
    assert {path.name for path in folder.iterdir()} >= {"table.csv", "table_initial.csv",
                                                        "linkage.png", "transmission_angle.png"}
    assert "solver" in (folder / "report.md").read_text()


def test_design_case_with_too_few_iterations_exits_1(tmp_path):
    text = (CASES / "fourbar_swing_design.toml").read_text().replace(
        "starts = 8", "starts = 1\nmax_iterations = 1")
    completed = sso("run", write_case(tmp_path, text), "--out", tmp_path, "--formats", "json",
                    cwd=tmp_path)
    assert completed.returncode == 1, completed.stderr
    assert "error: fourbar_swing_design: solver failed" in completed.stderr


def test_evaluate_and_no_plots_import_neither_casadi_nor_matplotlib(tmp_path):
    completed, loaded = sso_loading("evaluate", CASES / "fourbar_swing_design.toml",
                                    CASES / "quickreturn.toml", "--out", tmp_path, "--no-plots",
                                    cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    assert loaded == []
    assert not list(tmp_path.glob("*/*.png"))


@pytest.mark.parametrize("text, message", [
    (FOURBAR.format(crank=2.0) + "spede = 1\n",
     r"line 10: unknown key drive\.spede"),
    (FOURBAR.format(crank=2.0).replace("rocker = 9.0", "rocker = -9.0"),
     r"line 6: linkage\.rocker = -9 is outside the allowed range \(0, inf\) length units"),
    (FOURBAR.format(crank=2.0).replace("coupler = 15.0", "couplr = 15.0"),
     r"unknown key linkage\.couplr; did you mean linkage\.coupler\?"),
    (FOURBAR.format(crank=8.0),
     r"line 3: linkage\.ground = 12, linkage\.crank = 8, linkage\.coupler = 15, "
     r"linkage\.rocker = 9: the linkage cannot be assembled at crank angle\(s\) "
     r"\[0, 20, 340, 360\] deg"),
])
def test_broken_mechanism_case_exits_2_naming_key_and_angles(tmp_path, text, message):
    path = write_case(tmp_path, text)
    for command in ("run", "validate"):
        completed = sso(command, path, "--out", tmp_path, cwd=tmp_path) if command == "run" \
            else sso(command, path, cwd=tmp_path)
        assert completed.returncode == 2, (command, completed.stderr)
        assert re.search(message, completed.stderr), completed.stderr
        assert "Traceback" not in completed.stderr


def test_escaping_in_reports(tmp_path):
    text = 'description = "<script>alert(1)</script> & co"\n' + FOURBAR.format(crank=2.0)
    completed = sso("run", write_case(tmp_path, text), "--out", tmp_path, "--formats",
                    "md,html", cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    for name, ampersand in (("report.md", "&"), ("report.html", "&amp;")):
        report = (tmp_path / "case" / name).read_text()
        assert "<script>" not in report
        assert f"&lt;script&gt;alert(1)&lt;/script&gt; {ampersand} co" in report


def test_design_from_a_start_that_cannot_assemble(tmp_path):
    # The start linkage is tabulated too: a start that folds at some angles is refused
    # by name unless drive.on_unassembled = "mark"; then the design runs from it.
    text = (CASES / "fourbar_swing_design.toml").read_text()
    text = re.sub(r"(?m)^crank = 2.0$", "crank = 6.0", text)
    text = re.sub(r"(?m)^coupler = 15.0$", "coupler = 5.0", text)
    text = re.sub(r"(?m)^rocker = 9.0$", "rocker = 5.0", text)
    refused = write_case(tmp_path, text, "folding_start.toml")
    completed = sso("validate", refused, cwd=tmp_path)
    assert completed.returncode == 2
    assert "cannot be assembled at crank angle(s) [60, 80" in completed.stderr
    assert "drive.on_unassembled = 'mark'" in completed.stderr
    marked = write_case(tmp_path, text.replace(
        "step_deg = 20.0", "step_deg = 20.0\non_unassembled = \"mark\""), "marked_start.toml")
    completed = sso("run", marked, "--out", tmp_path / "out", "--no-plots", cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    run = read_run(tmp_path / "out" / "fourbar_swing_design")
    assert run.design is not None
    assert run.design.optimum_swing_deg == pytest.approx(80.374, abs=1e-3)
    assert run.main.role == "optimum" and run.main.grashof == "crank-rocker"
