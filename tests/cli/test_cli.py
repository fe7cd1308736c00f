"""The ``sso`` command, run for real in a subprocess on shipped and broken case files."""

import json
import re
import shutil
import struct
import subprocess
import sys
from pathlib import Path

import pytest
from paper_trials import paper_trial_case

from sso._cases.schema import load_case
from sso._run.shaft_series import ShaftSeriesRun

ROOT = Path(__file__).resolve().parents[2]
CASES = ROOT / "cases"
HEAVY = ("casadi", "scipy", "matplotlib")
# Runs the real command in-process and reports which heavy modules it loaded.
WRAPPER = f"""
import json, sys
from sso._cli import main
try:
    code = main(sys.argv[1:])
except SystemExit as stop:
    code = stop.code
print("LOADED=" + json.dumps(sorted(name for name in {HEAVY!r} if name in sys.modules)))
sys.exit(code)
"""
# docs/model.md, "The paper's three cases".
PAPER_REFERENCE_BETA_DEG = {3: [15.8362, 10.0, 15.8387]}
MINIMAL = '[design]\nbeta_deg = [20.0, 30.0]\n[solver]\nstarts = 1\n'


def sso(*arguments: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "sso._cli", *map(str, arguments)], cwd=cwd,
                          capture_output=True, text=True, timeout=300)


def sso_loading(*arguments: str, cwd: Path) -> tuple[subprocess.CompletedProcess, list[str]]:
    completed = subprocess.run([sys.executable, "-c", WRAPPER, *map(str, arguments)], cwd=cwd,
                               capture_output=True, text=True, timeout=300)
    loaded = re.search(r"^LOADED=(.*)$", completed.stdout, re.MULTILINE)
    assert loaded, completed.stdout + completed.stderr
    return completed, json.loads(loaded.group(1))


def png_size(path: Path) -> tuple[int, int]:
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert data[12:16] == b"IHDR"
    return struct.unpack(">II", data[16:24])


def write_case(folder: Path, text: str, name: str = "case.toml") -> Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def option3_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("run")
    completed = sso("run", paper_trial_case(3, "exact", folder), "--out", folder / "out",
                    cwd=folder)
    return completed, folder / "out" / "paper_option3_exact"


def test_run_writes_every_file_and_exits_0(option3_run):
    completed, report = option3_run
    assert completed.returncode == 0, completed.stderr
    assert sorted(path.name for path in report.iterdir()) == [
        "cartesian.png", "polar.png", "report.html", "report.md", "result.json", "speeds.csv",
        "sso-files.json"]
    assert "Traceback" not in completed.stderr
    # The paper's start outside its bounds is a warning, not an error.
    assert "warning: paper_option3_exact: start beta_deg[2] = 50 deg" in completed.stderr
    summary = completed.stdout.splitlines()[-2:]
    assert summary[0].startswith("--------")
    assert re.match(r"paper_option3_exact\s+solved\s+0\.0514\s+< 1e-15\s+0\.00193\s", summary[1])


def test_result_json_holds_the_whole_story(option3_run):
    _, report = option3_run
    saved = json.loads((report / "result.json").read_text())
    assert saved["version"] == 1 and saved["type"] == "ShaftSeriesRun"
    run = ShaftSeriesRun.from_dict(saved)
    result = run.optimisation
    assert result is not None
    assert result.model == "exact" and (result.option, result.option_name) == (3, "both")
    shipped = load_case(report.parent.parent / "paper_option3_exact.toml")
    assert run.case == shipped and saved["case"]["case"] == shipped.to_dict()
    initial, optimum, reference = (run.design(role).evaluation.residual_error
                                   for role in ("initial", "optimum", "reference"))
    # The exact model cancels the fluctuation: RE reaches round-off, far below the paper's.
    assert optimum < 1e-18
    assert reference == pytest.approx(1.928e-3, rel=1e-3)
    assert initial == pytest.approx(0.05140006, rel=1e-6)
    assert list(run.design("reference").series.beta_deg) == PAPER_REFERENCE_BETA_DEG[3]
    for name in ("ipopt", "slsqp"):
        solution = result.solutions[name]
        assert solution.success is True
        assert solution.kkt <= 1e-6
    assert result.crosscheck is not None and result.crosscheck.agree is True
    # Screening: the least-squares solver reaches RE = 0 (a global minimum) from the
    # first start, so the other starts are skipped; each solver then solves from the
    # given start with its own iterations, and the design is chosen within the set of
    # exact optima (largest margin to the bounds).
    assert [(item.solver, item.role) for item in result.runs] == [
        ("lm", "screen"), ("ipopt", "solve"), ("slsqp", "solve"), ("lm", "selection")]
    assert all(result.solutions[name].nit > 0 for name in ("ipopt", "slsqp"))
    assert result.found_by == "lm choosing within the exact optima"
    assert result.exact_optima is not None
    assert result.exact_optima.criterion == "largest margin to the bounds"
    # The exact model's RE is the closed form of the chain matrix: no quadrature angles.
    assert result.samples == 0 and result.quadrature_error == 0.0
    assert run.success is True
    assert set(run.versions) >= {"sso", "casadi", "ipopt", "scipy", "numpy"}
    assert run.versions["sso"] == "0.1.0"
    assert re.fullmatch(r"\d+\.\d+\.\d+", run.versions["ipopt"])
    # The curves the plots draw are in the result: the optimum's output speed is the
    # input speed (RE at round-off), 361 angles from 0 to 360 deg.
    curve = run.design("optimum")
    assert curve.input_angle_deg.shape == (361,)
    assert abs(curve.output_speed_rpm - result.input_speed_rpm).max() < 1e-6


def test_plots_are_valid_pngs_of_the_stated_size(option3_run):
    _, report = option3_run
    for name in ("polar.png", "cartesian.png"):
        assert png_size(report / name) == (1000, 700)


def test_speeds_csv_columns_and_values(option3_run):
    _, report = option3_run
    lines = (report / "speeds.csv").read_text().splitlines()
    assert lines[0] == ("input_angle_deg,input_speed_rpm,output_speed_initial_rpm,"
                        "output_speed_optimum_rpm,output_speed_reference_rpm")
    assert len(lines) == 1 + 361
    rows = [[float(cell) for cell in line.split(",")] for line in lines[1:]]
    assert rows[0][0] == 0.0 and rows[-1][0] == 360.0
    initial = [row[2] for row in rows]
    # Trial design 30, 40, 50 (50 kept as given) at 25 rpm: 18.17 .. 34.40 rpm (docs/model.md).
    assert min(initial) == pytest.approx(18.167, abs=2e-3)
    assert max(initial) == pytest.approx(34.403, abs=2e-3)
    assert max(abs(row[3] - 25.0) for row in rows) < 1e-6


def test_html_is_self_contained(option3_run):
    _, report = option3_run
    page = (report / "report.html").read_text()
    assert page.count('src="data:image/png;base64,') == 2
    assert 'src="polar.png"' not in page and 'src="cartesian.png"' not in page
    assert "solvers agree" in page


def test_report_rerenders_the_same_files_from_result_json(option3_run, tmp_path):
    _, report = option3_run
    completed = sso("report", report / "result.json", "--out", tmp_path, cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    for name in ("speeds.csv", "report.md"):
        assert (tmp_path / name).read_bytes() == (report / name).read_bytes(), name
    without_images = [re.sub(r"base64,[A-Za-z0-9+/=]+", "", (folder / "report.html").read_text())
                      for folder in (tmp_path, report)]
    assert without_images[0] == without_images[1]
    assert png_size(tmp_path / "polar.png") == (1000, 700)
    # The folder is written afresh, so the result it was rendered from goes into it too.
    assert (tmp_path / "result.json").read_bytes() == (report / "result.json").read_bytes()


def test_report_in_place_keeps_result_json_and_drops_files_of_the_earlier_run(option3_run,
                                                                              tmp_path):
    _, report = option3_run
    folder = tmp_path / "copy"
    shutil.copytree(report, folder)
    completed = sso("report", folder / "result.json", "--no-plots", cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    assert (folder / "result.json").read_bytes() == (report / "result.json").read_bytes()
    assert not list(folder.glob("*.png"))  # the earlier run's plots are gone
    assert sorted(path.name for path in tmp_path.iterdir()) == ["copy"]  # no temporary left


def test_a_folder_with_files_that_are_not_a_report_is_refused(option3_run, tmp_path):
    _, report = option3_run
    (tmp_path / "notes.txt").write_text("mine")
    completed = sso("report", report / "result.json", "--out", tmp_path, cwd=tmp_path)
    assert completed.returncode == 2
    assert "holds notes.txt, which sso did not write" in completed.stderr
    assert (tmp_path / "notes.txt").read_text() == "mine"


@pytest.mark.parametrize("model, low_rpm, high_rpm", [("paper", 18.17, 34.40)])
def test_evaluate_builds_no_nlp(tmp_path, model, low_rpm, high_rpm):
    completed, loaded = sso_loading("evaluate", paper_trial_case(3, model, tmp_path),
                                    "--out", tmp_path, "--no-plots", cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    assert loaded == []
    run = ShaftSeriesRun.from_dict(json.loads(
        (tmp_path / f"paper_option3_{model}" / "result.json").read_text()))
    assert run.mode == "evaluate" and run.optimisation is None
    assert [design.role for design in run.designs] == ["initial", "reference"]
    evaluation = run.designs[0].evaluation
    # docs/model.md: paper model, option 3 trial design, 25 rpm: output 18.17 .. 34.40 rpm.
    assert evaluation.speed_min_rpm == pytest.approx(low_rpm, abs=5e-3)
    assert evaluation.speed_max_rpm == pytest.approx(high_rpm, abs=5e-3)
    assert "solvers" not in (tmp_path / f"paper_option3_{model}" / "report.md").read_text()


def test_every_shipped_case_solves_below_its_reference(tmp_path):
    # The shaft-series cases; the column and driveline cases have no reference
    # (tests/cli/test_cli_column.py, tests/driveline/test_driveline_cli.py).
    shipped = sorted(path for path in CASES.glob("*.toml")
                     if load_case(path).kind == "shaft_series")
    completed = sso("run", *shipped, "--out", tmp_path, "--formats", "json", "--quiet",
                    cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    headlines, table = completed.stdout.strip().split("\n\n")
    assert len(table.splitlines()) == 2 + len(shipped)
    # each case's signed figures lead, before the table
    assert [line.split(":")[0] for line in headlines.splitlines()] == [
        path.stem for path in shipped]
    for path in shipped:
        run = ShaftSeriesRun.from_dict(json.loads(
            (tmp_path / path.stem / "result.json").read_text()))
        errors = {design.role: design.evaluation.residual_error for design in run.designs}
        assert run.success is True, path.stem
        assert errors["optimum"] <= min(errors["initial"], errors["reference"]) + 1e-20, path.stem
        if path.stem.startswith("paper_"):
            # docs/model.md: the paper's optima are not stationary; a correct solver does better.
            assert errors["optimum"] < 0.2 * errors["reference"], path.stem


def test_validate_and_help_import_neither_casadi_nor_scipy(tmp_path):
    completed, loaded = sso_loading("validate", *sorted(CASES.glob("*.toml")), cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    assert loaded == []
    assert completed.stdout.count("ok: ") == len(list(CASES.glob("*.toml")))
    for arguments in (["--help"], ["run", "--help"], ["evaluate", "--help"],
                      ["validate", "--help"], ["report", "--help"]):
        completed, loaded = sso_loading(*arguments, cwd=tmp_path)
        assert completed.returncode == 0
        assert loaded == []
        assert "usage: sso" in completed.stdout


def test_no_plots_never_imports_matplotlib(tmp_path):
    completed, loaded = sso_loading("run", CASES / "steering_column.toml", "--out", tmp_path,
                                    "--no-plots", cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    assert "matplotlib" not in loaded
    folder = tmp_path / "steering_column"
    assert not list(folder.glob("*.png"))
    assert "data:image/png" not in (folder / "report.html").read_text()


def test_case_without_png_never_imports_matplotlib(tmp_path):
    case = write_case(tmp_path, 'name = "quiet"\n' + MINIMAL
                      + '[output]\nformats = ["json", "md", "html"]\n')
    completed, loaded = sso_loading("run", case, "--out", tmp_path, cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    assert "matplotlib" not in loaded
    assert sorted(path.name for path in (tmp_path / "quiet").iterdir()) == [
        "report.html", "report.md", "result.json", "sso-files.json"]


def test_version(tmp_path):
    completed = sso("--version", cwd=tmp_path)
    assert completed.returncode == 0
    assert completed.stdout.strip() == "sso 0.1.0"


@pytest.mark.parametrize("arguments, message", [
    ([], "the following arguments are required"),
    (["run"], "the following arguments are required: CASE.toml"),
    (["run", "x.toml", "--solvers", "ipopt,cobyla"], "give a comma-separated list of ipopt, slsqp"),
    (["run", "x.toml", "--formats", "pdf"], "give a comma-separated list of json, csv"),
    (["fly"], "invalid choice: 'fly'"),
])
def test_bad_arguments_exit_2(tmp_path, arguments, message):
    completed = sso(*arguments, cwd=tmp_path)
    assert completed.returncode == 2
    assert message in completed.stderr
    assert "Traceback" not in completed.stderr


@pytest.mark.parametrize("text, message", [
    ('name = "x"\n[design]\nbeta_deg = [10, 20]\nmodel = exact\n', "line 4: TOML syntax error"),
    ('name = "x"\n[design]\nbeta_deg = [10, 20\n', "line 3: TOML syntax error: Unclosed array"),
    ('name = "x"\n' + MINIMAL.replace("starts", "strats"),
     "line 5: unknown key solver.strats; did you mean solver.starts?"),
    ('name = "x"\ninput_speed_rpm = "fast"\n' + MINIMAL,
     "line 2: input_speed_rpm = 'fast' must be a number in (0, 1e+06] rpm"),
    ('name = "x"\n[design]\nbeta_deg = [20.0, 95.0]\n',
     "line 3: design.beta_deg[1] = 95 is outside the allowed range [0, 90) deg"),
])
@pytest.mark.parametrize("command", ["run", "evaluate", "validate"])
def test_broken_case_exits_2_without_traceback(tmp_path, text, message, command):
    case = write_case(tmp_path, text)
    completed = sso(command, case, "--out", tmp_path / "out", cwd=tmp_path) \
        if command != "validate" else sso(command, case, cwd=tmp_path)
    assert completed.returncode == 2
    assert f"error: {case}, {message}" in completed.stderr
    assert "Traceback" not in completed.stderr
    assert not (tmp_path / "out" / "x").exists()


def test_one_broken_case_does_not_stop_the_others(tmp_path):
    broken = write_case(tmp_path, 'name = "broken"\n[design]\nbeta_deg = "steep"\n', "broken.toml")
    good = write_case(tmp_path, 'name = "good"\n' + MINIMAL, "good.toml")
    missing = tmp_path / "missing.toml"
    completed = sso("run", broken, good, missing, "--out", tmp_path / "out", "--no-plots",
                    cwd=tmp_path)
    assert completed.returncode == 2
    assert (tmp_path / "out" / "good" / "result.json").is_file()
    assert (f"error: {missing}: cannot read the case file: No such file or directory"
            in completed.stderr)
    table = completed.stdout.splitlines()[-4:]
    assert re.match(rf"{re.escape(str(broken))}\s+bad input", table[1])
    assert re.match(r"good\s+solved\s", table[2])
    assert re.match(rf"{re.escape(str(missing))}\s+bad input", table[3])


def test_solver_failure_exits_1_and_the_report_says_so(tmp_path):
    case = write_case(tmp_path, 'name = "starved"\noption = 3\n[design]\n'
                      'beta_deg = [30.0, 40.0, 35.0]\n[solver]\nstarts = 1\nmax_iterations = 1\n')
    completed = sso("run", case, "--out", tmp_path, "--formats", "json,md", cwd=tmp_path)
    assert completed.returncode == 1, completed.stdout + completed.stderr
    run = ShaftSeriesRun.from_dict(json.loads((tmp_path / "starved" / "result.json").read_text()))
    assert run.success is False and run.optimisation is not None
    assert run.optimisation.solutions["ipopt"].success is False
    assert run.optimisation.solutions["ipopt"].nit <= 1
    assert "error: starved: " in completed.stderr
    assert "FAILED: " in (tmp_path / "starved" / "report.md").read_text()
    assert "Traceback" not in completed.stderr


def test_failing_case_keeps_earlier_results_and_leaves_no_temporary_files(tmp_path):
    out = tmp_path / "out"
    case = write_case(tmp_path, 'name = "kept"\n' + MINIMAL)
    assert sso("run", case, "--out", out, "--no-plots", cwd=tmp_path).returncode == 0
    earlier = (out / "kept" / "result.json").read_bytes()
    notes = out / "kept" / "notes.txt"
    notes.write_text("my own notes")
    case.write_text('name = "kept"\n' + MINIMAL.replace("starts = 1", "starts = 0"))
    completed = sso("run", case, "--out", out, cwd=tmp_path)
    assert completed.returncode == 2
    assert (out / "kept" / "result.json").read_bytes() == earlier
    assert notes.read_text() == "my own notes"
    assert [path.name for path in out.rglob(".sso-tmp-*")] == []


def test_case_strings_are_escaped_in_html_and_markdown(tmp_path):
    case = write_case(tmp_path, 'name = "escaped"\n'
                      'description = "<script>alert(1)</script> & more"\n'
                      + MINIMAL + '[reference]\nlabel = "<img src=x onerror=alert(2)>"\n'
                      'beta_deg = [25.0, 25.0]\n')
    completed = sso("run", case, "--out", tmp_path, "--formats", "html,md", cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    # Markdown keeps an "&" that cannot start an entity as it is.
    for name, ampersand in (("report.html", "&amp;"), ("report.md", "&")):
        page = (tmp_path / "escaped" / name).read_text()
        assert "<script>" not in page
        assert "<img src=x" not in page
        assert f"&lt;script&gt;alert(1)&lt;/script&gt; {ampersand} more" in page
        assert "&lt;img src=x onerror=alert(2)&gt;" in page


def test_duplicate_names_in_one_run_are_refused(tmp_path):
    first = write_case(tmp_path, 'name = "twin"\n' + MINIMAL, "first.toml")
    second = write_case(tmp_path, 'name = "twin"\n' + MINIMAL, "second.toml")
    completed = sso("run", first, second, "--out", tmp_path, "--formats", "json", cwd=tmp_path)
    assert completed.returncode == 2
    assert f"error: {second}: name = 'twin' is already used by {first}" in completed.stderr


def test_report_refuses_a_bad_result_file(tmp_path):
    bad = tmp_path / "result.json"
    # the dict form a column case's result.json had before it became a saved ColumnRun
    bad.write_text('{"schema_version": 1, "kind": "column", "mode": "optimise", '
                   '"assemblies": []}')
    completed = sso("report", bad, cwd=tmp_path)
    assert completed.returncode == 2
    assert (f"error: {bad}: a result document of an earlier sso (schema_version = 1): this sso "
            'reads saved results ("type" and "version" 1) only; write it again with sso run '
            "or sso evaluate of its case") in completed.stderr
    assert "Traceback" not in completed.stderr
    bad.write_text("{not json")
    completed = sso("report", bad, cwd=tmp_path)
    assert completed.returncode == 2
    assert "not a JSON result file" in completed.stderr
    assert "Traceback" not in completed.stderr


def test_a_rerun_without_plots_leaves_no_plot_of_the_earlier_run(tmp_path):
    case = CASES / "steering_column.toml"
    first = sso("evaluate", case, "--out", tmp_path / "out", cwd=tmp_path)
    assert first.returncode == 0, first.stderr
    folder = tmp_path / "out" / "steering_column"
    assert (folder / "polar.png").exists()
    again = sso("evaluate", case, "--out", tmp_path / "out", "--no-plots", cwd=tmp_path)
    assert again.returncode == 0, again.stderr
    assert not list(folder.glob("*.png"))
    assert sorted(path.name for path in (tmp_path / "out").iterdir()) == ["steering_column"]


def test_a_tolerance_study_of_a_mechanism_case_is_refused_naming_the_kind(tmp_path):
    completed = sso("tolerance", CASES / "mechanisms" / "fourbar_crank2.toml", cwd=tmp_path)
    assert completed.returncode == 2
    assert ("kind = 'fourbar': sso sweep and sso tolerance work on shaft_series and column cases"
            in completed.stderr)
    assert "Traceback" not in completed.stderr
