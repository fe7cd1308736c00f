"""Sweeps of a column case, through the sweep engine, against the independent 3D
cross-and-yoke simulation (tests/column/cross_and_yoke.py: pin axes turned in space,
never the chain matrix nor the joint law)."""

from __future__ import annotations

import itertools
import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from column.cross_and_yoke import residual_error as simulated_re
from scipy.spatial.transform import Rotation

import sso
from sso._cases.schema import load_case
from sso._studies.element_columns import gathered
from sso._studies.table import TIME_COLUMNS, read_rows

ROOT = Path(__file__).resolve().parents[2]
TRUCK = ROOT / "cases" / "column_truck_three_joints.toml"
SHIPPED_SWEEP = ROOT / "sweeps" / "column_truck_upper_joint_height.toml"
POINTS = np.asarray(load_case(TRUCK).values["hardpoints.points_mm"])
BOX_LOWER = np.asarray(load_case(TRUCK).values["joint_boxes.min_mm"])
BOX_UPPER = np.asarray(load_case(TRUCK).values["joint_boxes.max_mm"])


def _sso(*arguments, cwd):
    return subprocess.run([sys.executable, "-m", "sso", *map(str, arguments)], cwd=cwd,
                          capture_output=True, text=True, timeout=600)


def test_the_shipped_sweep_over_p1_height_exits_0_with_its_reports(tmp_path):
    done = _sso("sweep", SHIPPED_SWEEP, "--out", tmp_path, "--quiet", "--workers", "2",
                cwd=ROOT)
    assert done.returncode == 0, done.stderr
    folder = tmp_path / "column_truck_upper_joint_height"
    assert {"sweep.csv", "sweep.json", "report.md", "report.html", "sweep_re.png"} <= {
        path.name for path in folder.iterdir()}
    rows = sorted(read_rows(folder / "sweep.csv"), key=lambda row: int(row["point"]))
    margins = []
    assert [float(row["hardpoints.points_mm[1][2]"]) for row in rows] == pytest.approx(
        [1234.3, 1236.8, 1239.3, 1241.8, 1244.3], abs=1e-12)
    for row in rows:
        assert row["status"] == "ok" and row["success"] == "true", row["error"]
        points = POINTS.copy()
        points[1, 2] = float(row["hardpoints.points_mm[1][2]"])
        yoke = np.array([float(row[f"yoke_phase_deg[{k}]"]) for k in range(2)])
        # The row's design is the best 36-tooth assembly: RE as the 3D simulation has it.
        assert float(row["residual_error"]) == pytest.approx(simulated_re(points, yoke),
                                                             rel=1e-9)
        assert all(int(row[f"tooth_offset[{k}]"]) == float(row[f"tooth_offset[{k}]"])
                   for k in range(2))
        assert float(row["residual_error"]) >= float(row["continuous_residual_error"])
        # The case's [joint_boxes] runs at each point: the moved joint centres cancel
        # (3D simulation, the case's phasing held) and lie in their boxes, at least the
        # reported margin inside them (docs/column.md states the range).
        moved = points.copy()
        moved[1:-1] = [[float(row[f"joint_centres_points_mm[{i}][{j}]"]) for j in range(3)]
                       for i in range(3)]
        assert row["joint_centres_success"] == "true"
        assert simulated_re(moved, [10.0, -80.0]) <= 1e-12
        assert float(row["joint_centres_residual_error"]) <= 1e-20
        margin = np.min(np.minimum(moved[1:-1] - BOX_LOWER, BOX_UPPER - moved[1:-1]))
        assert float(row["joint_centres_margin_mm"]) == pytest.approx(margin, abs=1e-6)
        assert margin >= 2.0
        margins.append(margin)
        assert row["tolerance_p95_residual_error"] == ""  # the case has no [tolerances]
    assert "speed fluctuation, lock to lock (%)" in (folder / "report.md").read_text()
    page = " ".join((ROOT / "docs" / "column.md").read_text(encoding="utf-8").split())
    assert (f"ends at the same moved column, {min(margins):.2f} to {max(margins):.2f} mm "
            "inside its boxes, from every height") in page


def test_each_point_runs_the_cases_tolerances(tmp_path):
    # The truck case with [tolerances] (1 mm, 1 deg, 50 columns, seed 3): each point's row
    # holds the p95 RE of its design over the built columns (numpy.percentile of the
    # sample's RE, each the 3D simulation of a built column: tests/column/
    # test_column_robust.py) and the tolerance-aware phasing's p95 on the same sample.
    case = tmp_path / "case.toml"
    without_boxes = re.sub(r"\[joint_boxes\]\nmin_mm = .*\nmax_mm = .*\n", "",
                           TRUCK.read_text())
    assert "[joint_boxes]" not in without_boxes  # this test is about the tolerances
    case.write_text(without_boxes + "\n[tolerances]\nhardpoint_mm = 1.0\n"
                    "yoke_phase_deg = 1.0\nsamples = 50\nseed = 3\n")
    heights = [1236.8, 1241.8]
    result = sso.sweep(case, {"hardpoints.points_mm[1][2]": heights}, action="optimise",
                       workers=1, progress=False)
    tolerances = sso.Tolerances(hardpoint_mm=1.0, yoke_phase_deg=1.0, samples=50, seed=3)
    for row, height in zip(sorted(result.rows, key=lambda row: row["point"]), heights,
                           strict=True):
        assert row["status"] == "ok", row["error"]
        points = POINTS.copy()
        points[1, 2] = height
        geometry = sso.ColumnGeometry(points)
        sample = tolerances.sample(geometry)
        p95 = np.percentile(sample.residual_error(gathered(row, "yoke_phase_deg")), 95.0)
        assert row["tolerance_p95_residual_error"] == pytest.approx(p95, rel=1e-12)
        robust = np.percentile(sample.residual_error(gathered(row, "robust_yoke_phase_deg")), 95.0)
        assert row["robust_p95_residual_error"] == pytest.approx(robust, rel=1e-12)
        # the truck cannot cancel: the CVaR95 phasing over all phasings, whose p95 is
        # near that of the best continuous phasing (measured within 5 %)
        continuous = gathered(row, "continuous_yoke_phase_deg")
        best = np.percentile(sample.residual_error(continuous), 95.0)
        assert robust == pytest.approx(best, rel=0.05)


@pytest.mark.parametrize(("table", "text"), [
    ("[hardpoints.positions]\nup = POINTS\ndown = POINTS\n", "[hardpoints.positions]"),
    ("[band]\nre_limit = 1e-3\n", "[band]"),
    ("[feel]\nstraight_ahead_deg = 45.0\nlock_deg = 600.0\n", "[feel]"),
])
def test_a_table_a_sweep_point_does_not_run_exits_2_naming_it(tmp_path, table, text):
    case = tmp_path / "case.toml"
    case.write_text(TRUCK.read_text() + "\n"
                    + table.replace("POINTS", json.dumps(POINTS.tolist())))
    sweep = tmp_path / "sweep.toml"
    sweep.write_text('case = "case.toml"\naction = "optimise"\n[axes]\n'
                     '"hardpoints.points_mm[1][2]" = [1236.8, 1241.8]\n')
    done = _sso("sweep", sweep, "--out", tmp_path / "out", "--quiet", cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    assert "Traceback" not in done.stderr
    assert f"a sweep of a column case does not run {text}" in done.stderr
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").rglob("sweep.csv"))


def test_a_tilt_sweep_turns_p0_about_the_lateral_axis_through_p1():
    result = sso.sweep(TRUCK, {"tilt.angle_deg": [-8.0, 0.0, 6.5]}, action="evaluate",
                       workers=1, progress=False)
    as_built = np.array(load_case(TRUCK).values["phasing.yoke_phase_deg"])
    for row in result.rows:
        rotation = Rotation.from_rotvec(np.radians(row["tilt.angle_deg"]) * np.array([0, 1, 0]))
        points = POINTS.copy()
        points[0] = POINTS[1] + rotation.apply(POINTS[0] - POINTS[1])
        first = points[1] - points[0]
        second = points[2] - points[1]
        beta_1 = np.degrees(np.arccos(first @ second / np.linalg.norm(first)
                                      / np.linalg.norm(second)))
        assert gathered(row, "design_beta_deg")[0] == pytest.approx(beta_1, abs=1e-9)
        assert row["residual_error"] == pytest.approx(simulated_re(points, as_built), rel=1e-9)
        assert gathered(row, "yoke_phase_deg") == pytest.approx(list(as_built), abs=0)


def test_a_yoke_phasing_sweep_evaluates_each_assembly():
    values = [-60.0, 10.0, 45.0]
    result = sso.sweep(TRUCK, {"phasing.yoke_phase_deg[0]": values}, action="evaluate",
                       workers=1, progress=False)
    for row, value in zip(result.rows, values, strict=True):
        yoke = np.array([value, -80.0])
        assert gathered(row, "yoke_phase_deg") == [value, -80.0]
        assert row["residual_error"] == pytest.approx(simulated_re(POINTS, yoke), rel=1e-9)


def test_a_teeth_sweep_finds_the_best_whole_teeth_the_3d_simulation_finds_by_brute_force():
    result = sso.sweep(TRUCK, {"splines.teeth[0]": [4, 6]}, workers=1, progress=False)
    for row in result.rows:
        teeth = (row["splines.teeth[0]"], 36)
        offsets = itertools.product(range(teeth[0] // 2), range(teeth[1] // 2))
        best = min(simulated_re(POINTS, np.array([first * 360.0 / teeth[0],
                                                  second * 360.0 / teeth[1]]))
                   for first, second in offsets)
        assert row["status"] == "ok" and row["success"] is True
        assert row["residual_error"] == pytest.approx(best, rel=1e-9)


@pytest.mark.parametrize("axes, match", [
    ({"phasing.yoke_phase_deg[0]": [10.0, 200.0]},
     r"axis 'phasing.yoke_phase_deg\[0\]' = 200.0: phasing.yoke_phase_deg\[0\] = 200 is outside "
     r"the allowed range \[-180, 180\]"),
    ({"splines.teeth[1]": [0]}, r"splines.teeth\[1\] = 0 is outside the allowed range "
                                r"\[1, 1000\]"),
    ({"tilt.angle_deg": [100.0]}, r"tilt.angle_deg = 100 is outside the allowed range "
                                  r"\[-90, 90\]"),
    ({"hardpoints.points_mm[1][2]": ["high"]},
     r"hardpoints.points_mm\[1\]\[2\] = 'high' must be a number \(mm\)"),
    ({"hardpoints.points_mm[9][2]": [1.0]},
     r"index 9 of hardpoints.points_mm is outside the allowed range \[0, 4\]"),
])
def test_a_bad_axis_value_names_the_key_and_its_range_before_any_point_runs(axes, match):
    with pytest.raises(ValueError, match=match):
        sso.sweep(TRUCK, axes, workers=1, progress=False)


def test_an_axis_too_long_to_read_whole_is_refused_by_its_ends():
    # Above MOST_CHECKED_VALUES values only each axis's ends are read beforehand: a
    # value of the wrong kind, or a range reaching past its key's limits, is refused
    # before any of the 30,001 points runs.
    with pytest.raises(ValueError, match=r"axis 'tilt.axis' = 0.0: tilt.angle_deg is missing"):
        sso.sweep(TRUCK, {"tilt.axis": {"start": 0.0, "stop": 30.0, "num": 30_001}},
                  workers=1, progress=False)
    with pytest.raises(ValueError, match=r"axis 'tilt.angle_deg' = 95.0: tilt.angle_deg = 95 "
                                         r"is outside the allowed range \[-90, 90\]"):
        sso.sweep(TRUCK, {"tilt.angle_deg": {"start": -5.0, "stop": 95.0, "num": 30_001}},
                  workers=1, progress=False)


def test_a_bad_column_sweep_exits_2_naming_the_key(tmp_path):
    sweep_file = tmp_path / "bad.toml"
    sweep_file.write_text(f'case = "{TRUCK}"\n[axes]\n"tilt.angle_deg" = [0, 95]\n')
    done = _sso("sweep", sweep_file, "--out", tmp_path / "out", "--quiet", cwd=tmp_path)
    assert done.returncode == 2
    assert "tilt.angle_deg = 95 is outside the allowed range [-90, 90]" in done.stderr
    assert "Traceback" not in done.stderr
    assert not (tmp_path / "out").exists()


def test_a_column_sweep_resumes_and_runs_on_dask_with_the_local_numbers(tmp_path):
    distributed = pytest.importorskip("distributed")
    axes = {"hardpoints.points_mm[2][0]": [-1614.9, -1612.9, -1610.9], "tilt.angle_deg": [0, 3]}
    local = sso.sweep(TRUCK, axes, action="evaluate", out_dir=tmp_path / "local", workers=1,
                      plots=False, progress=False)
    resumed = sso.sweep(TRUCK, axes, action="evaluate", out_dir=tmp_path / "local",
                        resume=True, workers=1, plots=False, progress=False)
    assert (resumed.computed, resumed.resumed) == (0, 6)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=":0") as cluster:
        with distributed.Client(cluster) as client:
            on_dask = sso.sweep(TRUCK, axes, action="evaluate", client=client, chunk_size=2,
                                progress=False)
    def without_times(rows):
        return [{key: value for key, value in row.items() if key not in TIME_COLUMNS}
                for row in rows]
    assert without_times(on_dask.rows) == without_times(local.rows)
    assert without_times(resumed.rows) == without_times(local.rows)


def test_a_column_sweep_writes_its_figures_as_typed_parquet_columns(tmp_path):
    pytest.importorskip("pyarrow")
    result = sso.sweep(TRUCK, {"tilt.angle_deg": [0.0, 4.0]}, action="evaluate",
                       out_dir=tmp_path / "out", workers=1, plots=False, progress=False,
                       parquet=True)
    frame = result.frame()
    assert frame["residual_error"].tolist() == [row["residual_error"] for row in result.rows]
    assert frame["speed_fluctuation_percent"].dtype == float
    assert frame["can_cancel"].tolist() == [False, False]
    assert frame[["yoke_phase_deg[0]", "yoke_phase_deg[1]"]].to_numpy().tolist() == \
        [[10.0, -80.0]] * 2
