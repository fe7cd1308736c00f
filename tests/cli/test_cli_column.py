"""The ``sso`` command on the 3D-column cases, run for real in a subprocess.

Reference values: the truck column of tests/data/columns/truck_three_joints.json (in
phase 4.9e-3, textbook correction 1.1e-3, best 2.27e-4, from the independent 3D simulation in
tests/column/test_column_phasing.py) and the closed-form least RE of ``sso.can_cancel``.
"""

import csv
import json
from pathlib import Path

import pytest
from test_cli import png_size, sso, sso_loading, write_case

from sso import ColumnRun

ROOT = Path(__file__).resolve().parents[2]
CASES = [ROOT / "cases" / "column_car_intermediate_shaft.toml",
         ROOT / "cases" / "column_truck_three_joints.toml"]
FILES = ("result.json", "excitation.csv", "column_3d.png", "excitation.png", "steering.png",
         "report.md", "report.html")


def saved_run(folder: Path) -> ColumnRun:
    """The column run saved in ``folder/result.json``, read back."""
    return ColumnRun.from_dict(json.loads((folder / "result.json").read_text()))


@pytest.fixture(scope="module")
def column_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("columns")
    completed = sso("run", *CASES, "--out", folder, cwd=folder)
    return completed, folder


def test_run_writes_every_file_without_a_warning(column_run):
    completed, folder = column_run
    assert completed.returncode == 0, completed.stderr
    assert completed.stderr == ""
    for case in ("column_car_intermediate_shaft", "column_truck_three_joints"):
        for name in FILES:
            assert (folder / case / name).is_file(), (case, name)
        assert png_size(folder / case / "column_3d.png") == (1000, 700)
        assert png_size(folder / case / "excitation.png") == (1000, 700)


def test_truck_report_compares_in_phase_textbook_and_best(column_run):
    _, folder = column_run
    run = saved_run(folder / "column_truck_three_joints")
    assert run.success
    by_role = {assembly.role: assembly.residual_error for assembly in run.assemblies}
    assert by_role["in_phase"] == pytest.approx(4.86e-3, rel=1e-2)
    assert by_role["textbook"] == pytest.approx(1.11e-3, rel=1e-2)
    assert by_role["best"] == pytest.approx(2.268e-4, rel=1e-3)
    assert by_role["best"] == pytest.approx(run.cancel.minimum_residual_error, rel=1e-9)
    assert not run.cancel.possible
    # 36 teeth come within 2e-6 relative of the continuous optimum (about 10 and -80
    # deg, whole teeth; the hardpoints are rounded to 0.1 mm).
    assert run.splines is not None and run.splines.tooth_offset == (1, -8)
    assert run.splines.loss < 1e-5 * by_role["best"]
    moved = run.joint_centres
    assert moved is not None
    assert moved.fun < moved.initial_re and moved.constraint_violation <= 1e-8
    assert moved.yoke_phase_deg == (10.0, -80.0)  # phasing.mode = "fixed"
    report = (folder / "column_truck_three_joints" / "report.md").read_text()
    for text in ("phi_k = 90 + delta_k - gamma_k", "margin cos(beta_max)",
                 "yoke at joint 3: 8 teeth (80.0 deg) anticlockwise",
                 "Joint positions moved within their boxes", "Steering from lock to lock",
                 "do not judge a steering column"):
        assert text in report, text
    assert "limits inertial / torsional" not in report


def test_truck_steering_figures_of_every_assembly(column_run):
    # Reference figures: tests/column/test_column_steering_range.py checks the same
    # function against the 3D simulation; here the case's lock (900 deg, whole
    # periods) gives the chain's s_max / s_min, and every excitation row is unjudged.
    _, folder = column_run
    run = saved_run(folder / "column_truck_three_joints")
    steering = run.steering
    assert steering.lock_deg == 900.0 and steering.straight_ahead_deg == 0.0
    by_role = {design.role: design for design in steering.designs}
    assert set(by_role) == {"as_built", "in_phase", "textbook", "best", "splines"}
    assert by_role["splines"].range.speed_fluctuation_percent == pytest.approx(4.26, abs=0.01)
    assert by_role["in_phase"].range.speed_fluctuation_percent == pytest.approx(19.73, abs=0.01)
    criteria = {item.name: item for item in by_role["best"].criteria}
    assert criteria["speed-ratio fluctuation, lock to lock (peak to peak)"].within is None
    assert criteria["largest operating angle"].within is True
    assert all(row.within_limits is None and row.inertial_limit_rad_s2 is None
               for table in run.excitation.values() for row in table)


def test_excitation_csv_has_both_assemblies_over_the_rpm_range(column_run):
    _, folder = column_run
    with (folder / "column_car_intermediate_shaft" / "excitation.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert {row["assembly"] for row in rows} == {"as_built", "splines"}
    speeds = sorted({float(row["input_speed_rpm"]) for row in rows})
    assert speeds[0] == 20.0 and speeds[-1] == 120.0 and len(speeds) == 11
    # A steering column: the driveline limits judge no row.
    assert all(row["inertial_limit_rad_s2"] == "" and row["within_limits"] == ""
               for row in rows)


def test_report_renders_again_from_result_json(column_run, tmp_path):
    _, folder = column_run
    source = folder / "column_car_intermediate_shaft"
    completed = sso("report", source / "result.json", "--out", tmp_path, "--no-plots",
                    cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    original = (source / "report.md").read_text()
    again = (tmp_path / "report.md").read_text()
    assert again.split("## Plots")[0] == original.split("## Plots")[0]


def test_evaluate_loads_no_casadi(tmp_path):
    completed, loaded = sso_loading("evaluate", CASES[1], "--out", tmp_path, "--no-plots",
                                    cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    assert "casadi" not in loaded
    run = saved_run(tmp_path / "column_truck_three_joints")
    assert run.mode == "evaluate" and run.phasing is None and run.joint_centres is None
    assert run.assemblies[0].residual_error == pytest.approx(2.268e-4, rel=1e-3)


def test_bad_column_case_exits_2_naming_the_key(tmp_path):
    path = write_case(tmp_path, 'kind = "column"\n[hardpoints]\npoints_mm = [[0, 0, 0], '
                      '[100, 0, 0], [200, 30, 0], [300, 30, 40]]\n[splines]\nteeth = [36, 36]\n')
    completed = sso("run", path, "--out", tmp_path, cwd=tmp_path)
    assert completed.returncode == 2
    assert "splines.teeth has 2 entries; the column has 1 intermediate shaft" in completed.stderr
    assert "Traceback" not in completed.stderr


def test_a_driveline_column_is_judged_by_the_driveline_limits(tmp_path):
    # The truck column's points as a driveline at 2000 to 3000 rpm (truck limits):
    # every row carries the published limits and a verdict, and the report says so.
    truck = json.loads((ROOT / "tests" / "data" / "columns" / "truck_three_joints.json")
                       .read_text())["points_mm"]
    path = write_case(tmp_path, 'kind = "column"\nname = "driveline"\n[hardpoints]\n'
                      f"points_mm = {truck}\n[excitation]\nrpm = [2000.0, 3000.0]\nrows = 3\n"
                      'vehicle = "truck"\napplication = "driveline"\n')
    completed = sso("evaluate", path, "--out", tmp_path, "--no-plots", cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    rows = saved_run(tmp_path / "driveline").excitation["as_built"].rows
    assert [row.inertial_limit_rad_s2 for row in rows] == [2000.0] * 3
    assert all(isinstance(row.within_limits, bool) for row in rows)
    report = (tmp_path / "driveline" / "report.md").read_text()
    assert "limits inertial / torsional" in report
    assert "the SAE AE-7 driveline limits judge the excitation rows" in report


def test_validate_warns_of_hardpoints_in_metres_and_of_a_joint_under_half_a_degree(tmp_path):
    # The truck's points divided by 1000 (shortest shaft 0.15 mm), and a column whose
    # first joint bends by atan(2.0944 / 400) = 0.300 deg.
    truck = json.loads((ROOT / "tests" / "data" / "columns" / "truck_three_joints.json")
                       .read_text())["points_mm"]
    metres = [[coordinate / 1000.0 for coordinate in point] for point in truck]
    first = write_case(tmp_path, f'kind = "column"\n[hardpoints]\npoints_mm = {metres}\n',
                       "metres.toml")
    second = write_case(tmp_path, 'kind = "column"\n[hardpoints]\npoints_mm = [[0, 0, 0], '
                        "[400, 0, 0], [800, 2.0944, 0], [1200, 100, 30]]\n", "small.toml")
    completed = sso("validate", first, second, cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    assert ("warning: metres: hardpoints.points_mm = points 0.15 mm apart (output shaft, P3 to "
            "P4) looks like metres (0.15 m = 149.9 mm)" in completed.stderr)
    assert ("warning: small: hardpoints.points_mm[1]: joint 1 runs at 0.3 deg, below about "
            "0.5 deg (needle bearings that hardly roll brinell the trunnions" in completed.stderr)


def test_extreme_column_at_the_closed_form_optimum_is_solved(tmp_path):
    # Issue 34 item 9: joints at 89.999 and 20 deg (planar; the points of
    # tests/column/column_cases.planar_points([89.999, 20.0])). Both solvers stop at the
    # closed-form optimum, RE 26,919.2, 1.04e-7 (3.9e-12 relative) from sso.can_cancel's
    # least RE: sso run exits 0 and the saved run succeeds (it exited 1, "solvers
    # disagree", while the test of that gap was absolute).
    case = write_case(tmp_path, """kind = "column"
name = "extreme"

[hardpoints]
points_mm = [[0.0, 0.0, 0.0], [400.0, 0.0, 0.0], [400.0069813170076, 399.99999993907653, 0.0],
             [263.2054842996526, 775.879435947234, 0.0]]

[phasing]
yoke_phase_deg = [0.0]
mode = "free"
""")
    completed = sso("run", case, "--out", tmp_path / "out", "--formats", "json", cwd=tmp_path)
    assert completed.returncode == 0, completed.stdout + completed.stderr
    run = saved_run(tmp_path / "out" / "extreme")
    assert run.success
    assert run.phasing is not None and run.phasing.success, run.phasing
    assert run.phasing.fun == pytest.approx(26919.2, abs=0.05)
