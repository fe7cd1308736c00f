"""``sso.sweep`` in this process: values, failing points, files, progress, bad input."""

import csv
import itertools
import json
import math
import struct

import numpy as np
import pytest

import sso
from sso._studies.element_columns import gathered
from sso._studies.sweep import (
    ARRAY_CHUNK_CAP,
    ARRAY_CHUNK_FLOOR,
    ARRAY_CHUNKS_PER_WORKER,
    ARRAY_SHARE,
    DASK_CHUNK_FLOOR,
    DASK_EVALUATE_CHUNK_CAP,
    _chunk_sizes,
    array_chunk_rule,
)
from sso._studies.table import RESULT_COLUMNS

ONE_JOINT = {"design": {"beta_deg": [20.0]}, "input_speed_rpm": 30.0}
TWO_JOINTS = {"design": {"beta_deg": [30.0, 30.0], "phase_deg": [90.0]},
              "option": 2, "bounds": {"beta_deg": [10.0, 40.0]},
              "solver": {"starts": 1}}
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def png_size(path):
    data = path.read_bytes()
    assert data[:8] == PNG_SIGNATURE
    return struct.unpack(">II", data[16:24])


def test_evaluate_sweep_matches_the_one_joint_closed_form(tmp_path):
    # One joint: the ratio swings between cos(beta) and 1/cos(beta) (docs/model.md, checks).
    result = sso.sweep(ONE_JOINT, {"design.beta_deg[0]": [10.0, 20.0, 35.0]},
                       action="evaluate", out_dir=tmp_path, workers=1, plots=False)
    assert [row["status"] for row in result.rows] == ["ok", "ok", "ok"]
    for row, beta_deg in zip(result.rows, [10.0, 20.0, 35.0], strict=True):
        cos_beta = math.cos(math.radians(beta_deg))
        assert row["fluctuation"] == pytest.approx(1 / cos_beta - cos_beta, rel=1e-9)
        evaluation = sso.ShaftSeries([beta_deg]).evaluate(30.0)
        assert row["residual_error"] == pytest.approx(evaluation.residual_error, rel=1e-12)
        assert row["max_output_accel_rad_s2"] == pytest.approx(
            evaluation.max_output_accel_rad_s2, rel=1e-12)
        assert gathered(row, "design_beta_deg") == [beta_deg]
    with open(tmp_path / "sweep.csv", newline="") as handle:
        table = list(csv.DictReader(handle))
    # One joint: one operating angle, no phase (RESULT_COLUMNS with each list spread).
    assert list(table[0]) == ["point", "design.beta_deg[0]", *(
        "design_beta_deg[0]" if name == "design_beta_deg" else name for name in RESULT_COLUMNS
        if name != "design_phase_deg"), "sweep_hash"]
    assert [float(row["residual_error"]) for row in table] == [
        row["residual_error"] for row in result.rows]  # shortest round-trip floats


def test_optimise_sweep_cancels_two_equal_joints_and_records_both_solvers(tmp_path):
    # Exact model, option 2: two joints at 90 deg cancel when equal, so RE -> 0.
    result = sso.sweep(TWO_JOINTS, {"design.beta_deg[1]": [15.0, 35.0]}, out_dir=tmp_path,
                       workers=1, plots=False)
    assert result.success
    for row in result.rows:
        assert row["residual_error"] < 1e-20
        assert row["design_beta_deg[0]"] == pytest.approx(row["design_beta_deg[1]"], abs=1e-6)
        assert row["crosscheck_agree"] is True
        assert row["ipopt_status"] == 0 and row["slsqp_status"] == 0
        assert row["ipopt_time_s"] > 0 and row["slsqp_time_s"] > 0
    manifest = json.loads((tmp_path / "sweep.json").read_text())
    assert manifest["points"] == 2 and manifest["action"] == "optimise"


def test_a_failing_point_is_recorded_with_its_error_and_the_sweep_goes_on(tmp_path):
    result = sso.sweep(ONE_JOINT, {"design.beta_deg[0]": [20.0, 95.0, 30.0]},
                       action="evaluate", out_dir=tmp_path, workers=1, plots=False)
    assert [row["status"] for row in result.rows] == ["ok", "failed", "ok"]
    assert "design.beta_deg[0] = 95 is outside the allowed range [0, 90) deg" in (
        result.rows[1]["error"])
    assert result.rows[1]["residual_error"] is None
    assert not result.success
    assert "1 failed" in result.summary()
    assert "point 1 failed" in (tmp_path / "report.md").read_text()


def test_one_panel_per_axis_and_a_small_multiples_grid_for_two(tmp_path):
    one = sso.sweep(ONE_JOINT, {"design.beta_deg[0]": [10.0, 20.0]}, action="evaluate",
                    out_dir=tmp_path / "one", workers=1)
    two = sso.sweep({"design": {"beta_deg": [20.0, 20.0], "phase_deg": [90.0]}},
                    {"design.beta_deg[0]": [10.0, 20.0], "design.phase_deg[0]": [0.0, 45.0, 90.0]},
                    action="evaluate", out_dir=tmp_path / "two", workers=1)
    assert {path.name for path in one.files} == {"sweep.csv", "sweep.json", "report.md",
                                                 "report.html", "sweep_re.png"}
    assert png_size(tmp_path / "one" / "sweep_re.png") == (840, 540)  # one panel, 7 x 4.5 in
    assert png_size(tmp_path / "two" / "sweep_re.png") == (864, 396)  # 2 panels side by side
    # Equal joints at 90 deg cancel exactly: the lowest RE is that point, round-off.
    assert two.best["point"] == 5
    assert two.best["residual_error"] < 1e-28
    report = (tmp_path / "two" / "report.md").read_text()
    assert "lowest RE < 1e-15 at point 5" in report
    assert "| 5 | 20 | 90 | ok | < 1e-15 |" in report


def test_a_sweep_of_three_axes_draws_three_panels(tmp_path):
    sso.sweep({"design": {"beta_deg": [20.0, 20.0], "phase_deg": [90.0]}},
              {"design.beta_deg[0]": [10.0, 20.0], "design.beta_deg[1]": [15.0, 20.0],
               "design.phase_deg[0]": [0.0, 90.0]},
              action="evaluate", out_dir=tmp_path, workers=1)
    assert png_size(tmp_path / "sweep_re.png") == (1296, 396)  # 3 panels in one row


def test_a_mechanism_case_cannot_be_swept():
    with pytest.raises(ValueError, match="kind = 'fourbar': sso sweep and sso tolerance work on "
                                         "shaft_series and column cases"):
        sso.sweep("cases/mechanisms/fourbar_crank2.toml", {"input_speed_rpm": [1.0, 2.0]})


def test_progress_is_quiet_off_a_terminal_and_drawn_when_asked(capsys):
    sso.sweep(ONE_JOINT, {"design.beta_deg[0]": [10.0, 20.0]}, action="evaluate", workers=1)
    assert capsys.readouterr().err == ""
    sso.sweep(ONE_JOINT, {"design.beta_deg[0]": [10.0, 20.0]}, action="evaluate", workers=1,
              progress=True)
    assert "2/2 points" in capsys.readouterr().err


def test_an_existing_sweep_is_not_overwritten_and_a_different_one_not_resumed(tmp_path):
    sso.sweep(ONE_JOINT, {"design.beta_deg[0]": [10.0]}, action="evaluate", out_dir=tmp_path,
              workers=1, plots=False)
    with pytest.raises(ValueError, match="already holds a sweep; pass resume=True"):
        sso.sweep(ONE_JOINT, {"design.beta_deg[0]": [10.0]}, action="evaluate",
                  out_dir=tmp_path, workers=1, plots=False)
    with pytest.raises(ValueError, match="holds a different sweep \\(differs in axes, points\\)"):
        sso.sweep(ONE_JOINT, {"design.beta_deg[0]": [10.0, 20.0]}, action="evaluate",
                  out_dir=tmp_path, workers=1, plots=False, resume=True)


@pytest.mark.parametrize("keywords, message", [
    ({"action": "solve"}, "action = 'solve' is not one of 'optimise', 'evaluate'"),
    ({"workers": 0}, r"workers = 0 is outside the allowed range \[1, 1024\]"),
    ({"chunk_size": 0}, r"chunk_size = 0 is outside the allowed range \[1, 50000\]"),
])
def test_bad_arguments_are_refused_naming_the_field(keywords, message):
    with pytest.raises(ValueError, match=message):
        sso.sweep(ONE_JOINT, {"design.beta_deg[0]": [10.0]}, **keywords)


def test_sweep_over_a_shipped_case_file_varies_the_input_speed():
    from pathlib import Path

    case_path = Path("cases") / "driveline_four_joint.toml"
    result = sso.sweep(case_path, {"input_speed_rpm": [10.0, 20.0]}, action="evaluate",
                       workers=1)
    first, second = result.rows
    # The residual error is independent of speed; the acceleration scales with its square.
    assert first["residual_error"] == second["residual_error"]
    assert second["max_output_accel_rad_s2"] == pytest.approx(
        4 * first["max_output_accel_rad_s2"], rel=1e-12)
    assert np.isfinite(first["fluctuation"])


@pytest.mark.parametrize("points, workers", [(103_823, 2), (1_000_000, 2), (600, 2),
                                             (5, 3), (0, 2), (250_000, 1)])
def test_array_tasks_shrink_towards_the_end_of_a_sweep(points, workers):
    sizes = _chunk_sizes(None, points, workers, arrays=True)
    assert sum(sizes) == points and all(size >= 1 for size in sizes)
    assert sizes == sorted(sizes, reverse=True)
    assert max(sizes, default=0) <= ARRAY_CHUNK_CAP
    if points >= ARRAY_CHUNK_FLOOR * ARRAY_CHUNKS_PER_WORKER * workers:
        assert min(sizes[:-1]) >= ARRAY_CHUNK_FLOOR  # never shorter, but the remainder
    if points:  # each takes half a worker's share of the points left, within the limits
        assert sizes[0] == min(ARRAY_CHUNK_CAP, max(
            min(ARRAY_CHUNK_FLOOR, math.ceil(points / (ARRAY_CHUNKS_PER_WORKER * workers))),
            math.ceil(points / (ARRAY_SHARE * workers))), points)
    assert _chunk_sizes(7, points, workers, arrays=True) == [
        min(7, points - start) for start in range(0, points, 7)]


@pytest.mark.parametrize("action, points, pool_tasks, dask_tasks",
                         [("optimise", 103_823, 13, 6), ("evaluate", 1_000_000, 32, 12)])
def test_dask_tasks_are_fewer_and_longer_in_rounds_of_one_a_worker(action, points, pool_tasks,
                                                                     dask_tasks):
    # A Dask task costs the calling process and the worker about ten times what a
    # pool's does, so a sweep on Dask is cut into fewer, longer tasks, in rounds of
    # equal tasks (Dask hands each worker its next task while the current one runs).
    fewest, most, in_rounds = array_chunk_rule(True, action)
    assert (fewest, most, in_rounds) == (DASK_CHUNK_FLOOR[action], DASK_EVALUATE_CHUNK_CAP
                                         if action == "evaluate" else ARRAY_CHUNK_CAP, True)
    assert array_chunk_rule(False, action) == (ARRAY_CHUNK_FLOOR, ARRAY_CHUNK_CAP, False)
    pool = _chunk_sizes(None, points, 2, True)
    dask = _chunk_sizes(None, points, 2, True, fewest, most, in_rounds)
    assert (len(pool), len(dask)) == (pool_tasks, dask_tasks)
    assert sum(dask) == points and max(dask) <= most and min(dask) >= fewest
    assert dask[0] == min(most, math.ceil(points / (ARRAY_SHARE * 2)))
    rounds = [dask[start:start + 2] for start in range(0, len(dask), 2)]
    assert all(max(pair) - min(pair) <= 1 for pair in rounds)
    assert all(sum(later) <= sum(earlier) for earlier, later in itertools.pairwise(rounds))


@pytest.mark.parametrize("points, workers", [(1, 2), (3, 2), (1_000, 2), (103_823, 3),
                                             (10_000_000, 8), (25_001, 2)])
def test_dask_rounds_cover_every_point_in_whole_rounds(points, workers):
    sizes = _chunk_sizes(None, points, workers, True, 10_000, 50_000, True)
    assert sum(sizes) == points and min(sizes) >= 1 and max(sizes) <= 50_000
    if points >= workers:
        assert len(sizes) % workers == 0
        assert all(max(sizes[start:start + workers]) - min(sizes[start:start + workers]) <= 1
                   for start in range(0, len(sizes), workers))
