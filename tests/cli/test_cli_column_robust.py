"""Robust phasing in a column case, through the ``sso`` command run for real in a subprocess.

Reference values: the shipped case cases/column_truck_three_positions.toml (positions
from tests/data/columns/truck_three_positions.json); the robust-phasing acceptance is
checked on the result the run saves (each single-position optimum's worst RE,
the tolerance study of both designs on one sample), and the band edges against the
independent 3D cross-and-yoke simulation (tests/column/cross_and_yoke.py).
"""

import json
from pathlib import Path

import numpy as np
import pytest
from column.cross_and_yoke import residual_error as simulated_re
from test_cli import png_size, sso, sso_loading, write_case

from sso import ColumnRun

ROOT = Path(__file__).resolve().parents[2]

CASE = ROOT / "cases" / "column_truck_three_positions.toml"
NAME = "column_truck_three_positions"
IMAGES = ("positions.png", "tolerance_study.png", "phase_error.png", "steering_feel.png")
MID = json.loads((ROOT / "tests" / "data" / "columns" / "truck_three_positions.json")
                 .read_text())["positions"]["mid"]["points_mm"]


@pytest.fixture(scope="module")
def robust_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("robust")
    completed = sso("run", CASE, "--out", folder, cwd=folder)
    return completed, folder / NAME, saved_run(folder / NAME)


def saved_run(folder: Path) -> ColumnRun:
    """The column run saved in ``folder/result.json``, read back."""
    return ColumnRun.from_dict(json.loads((folder / "result.json").read_text()))


def test_run_solves_without_a_warning_and_writes_every_plot(robust_run):
    completed, folder, run = robust_run
    assert completed.returncode == 0, completed.stderr
    assert completed.stderr == ""
    assert run.success and run.warnings == ()
    for name in IMAGES:
        assert png_size(folder / name) == (1000, 700), name


def test_shared_phasing_beats_every_single_position_optimum(robust_run):
    _, _, run = robust_run
    result = run.robust.positions.result
    assert result.crosscheck.agree
    objectives = result.crosscheck.objective
    assert objectives["ipopt"] == pytest.approx(objectives["slsqp"], rel=1e-9)
    for single in result.single_position.values():
        assert result.worst_re <= single.worst_re
    # docs/robust.md: the worst case binds at both tilt ends, 6.50e-4.
    assert result.worst_re == pytest.approx(6.4988e-4, rel=1e-4)
    assert set(result.active_positions) == {"tilt_up", "tilt_down"}


def test_tolerance_aware_p95_at_or_below_the_nominal_on_the_same_sample(robust_run):
    _, folder, run = robust_run
    tolerances = run.robust.tolerances
    result = tolerances.result
    assert result.crosscheck.agree
    assert result.robust_study.p95 <= result.nominal_study.p95
    # Below every equivalent nominal optimum too (mirror solutions, equal nominal RE).
    assert tolerances.nominal_equivalents
    for equivalent in tolerances.nominal_equivalents:
        assert result.robust_study.p95 <= equivalent.study.p95
    by_role = {design.role: design for design in run.robust.designs}
    for figure in ("nominal_re", "mean", "p50", "p95", "max", "cvar95"):
        assert getattr(by_role["robust"].study, figure) == pytest.approx(
            getattr(result.robust_study, figure), rel=1e-12)
    assert 0.0 < result.nominal_re_given_up < 1e-6
    # The stored sample gives the same p95 (the plot's data).
    assert np.percentile(tolerances.samples_re["robust"], 95.0) == pytest.approx(
        result.robust_study.p95, rel=1e-12)
    report = (folder / "report.md").read_text()
    for text in ("### Tolerance study on one sample", "nominal RE given up",
                 "at or below: yes; against every equivalent nominal optimum: yes",
                 "At or below every single-position optimum's worst: yes",
                 "### Tolerance bands", "### Steering feel"):
        assert text in report, text


def test_band_edges_meet_the_limit_in_the_3d_simulation(robust_run):
    _, _, run = robust_run
    limit = run.robust.band_re_limit
    points = np.asarray(run.geometry.points_mm)
    edges = 0
    for design in run.robust.designs:
        if design.band is None:
            assert "above band.re_limit" in design.band_note
            continue
        for index, interval in enumerate(design.band.yoke_phase):
            for edge, at_limit in ((interval.lower_deg, interval.lower_at_limit),
                                   (interval.upper_deg, interval.upper_at_limit)):
                if not at_limit:
                    continue
                yoke = list(design.yoke_phase_deg)
                yoke[index] = edge
                assert simulated_re(points, yoke) == pytest.approx(limit, rel=1e-6)
                edges += 1
    assert edges > 0


def test_evaluate_reports_the_assembly_as_built_at_every_position(tmp_path):
    completed, loaded = sso_loading("evaluate", CASE, "--out", tmp_path, "--no-plots",
                                    cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    assert "casadi" not in loaded
    robust = saved_run(tmp_path / NAME).robust
    (as_built,) = robust.designs
    assert as_built.role == "as_built" and robust.positions.result is None
    # docs/robust.md: mid's optimum (10.0, -80.0) gives 7.61e-4, 2.27e-4, 1.18e-4.
    assert as_built.positions.position_re["tilt_up"] == pytest.approx(7.61e-4, rel=2e-3)
    assert as_built.positions.position_re["mid"] == pytest.approx(2.27e-4, rel=2e-3)
    assert as_built.positions.position_re["tilt_down"] == pytest.approx(1.18e-4, rel=3e-3)


def test_on_centre_phasing_moves_the_fluctuation_off_centre(tmp_path):
    # The mid position cannot cancel, so the on-centre objective has something to trade.
    path = write_case(tmp_path, f'kind = "column"\nname = "feel"\n[hardpoints]\n'
                      f'points_mm = {MID}\n[feel]\nstraight_ahead_deg = 45.0\n'
                      'lock_deg = 600.0\n[output]\nformats = ["json", "md"]\n')
    completed = sso("run", path, "--out", tmp_path, cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    robust = saved_run(tmp_path / "feel").robust
    by_role = {design.role: design for design in robust.designs}
    assert robust.feel.result.crosscheck.agree
    centred, nominal = by_role["on_centre"].feel, by_role["nominal"].feel
    assert centred.on_centre_fluctuation < nominal.on_centre_fluctuation
    assert centred.re >= nominal.re * (1.0 - 1e-9)
    assert "On-centre phasing (RE + 10 x on-centre variance)" in \
        (tmp_path / "feel" / "report.md").read_text()


POSITION = "[[-1850.0, 420.0, 1650.0], [-1690.3, 328.7, 1239.3], [-1612.9, 259.6, 873.8], " \
           "[-1468.3, 279.1, 374.6], [-1385.7, 260.3, 250.9]]"


@pytest.mark.parametrize("tables, message", [
    ("[hardpoints.positions]\nup = " + POSITION + "\ndown = [[0, 0, 0], [100, 0, 0], "
     "[200, 30, 0], [300, 30, 40]]\n",
     "hardpoints.positions.down has 2 joints (4 points) but hardpoints.points_mm has 3"),
    ("[tolerances]\nhardpoint_mm = -0.5\nyoke_phase_deg = 1.0\n",
     "tolerances.hardpoint_mm = -0.5 is outside the allowed range [0, 100] mm"),
    ("[band]\nre_limit = 1e-4\n",
     "band.re_limit = 0.0001 is below the least RE any yoke phasing of the column at "
     "hardpoints.points_mm reaches (0.000226"),
])
def test_bad_robust_input_exits_2_naming_the_field(tmp_path, tables, message):
    path = write_case(tmp_path, f'kind = "column"\n[hardpoints]\npoints_mm = {POSITION}\n'
                      + tables)
    completed = sso("run", path, "--out", tmp_path, cwd=tmp_path)
    assert completed.returncode == 2, completed.stderr
    assert message in completed.stderr
    assert "Traceback" not in completed.stderr
    assert not (tmp_path / "case").exists()


def test_sso_tolerance_studies_a_column_case_with_its_tolerances_table(tmp_path):
    # The case's [tolerances]: 1 mm and 1 deg, normal, 200 samples, seed 1; its [feel]
    # lock of 600 deg is the steering range's default.
    completed = sso("tolerance", CASE, "--at", "start", "--out", tmp_path, "--workers", "1",
                    "--no-plots", "--quiet", cwd=tmp_path)
    assert completed.returncode == 0, completed.stderr
    assert "column tolerance study: 200 built columns (normal, seed 1)" in completed.stdout
    assert "every hardpoint coordinate 1 mm, each yoke phasing 1 deg" in completed.stdout
    assert "steering range: +-600 deg" in completed.stdout
