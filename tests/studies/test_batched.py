"""Sweep points solved together by ``sso.optimise_batch``, against ``sso.optimise`` per point.

Reference: ``sso.optimise(series, option, solvers=("lm",), starts=..., ...)`` on each
point's case (the point-by-point path of a sweep); every batched row's RE must equal
its ``fun`` to 1e-12 (absolute) and its success flag must match.
"""

from __future__ import annotations

import warnings
from dataclasses import replace

import numpy as np
import pytest

import sso
from sso._cases.schema import parse_case
from sso._solvers.lm import MESSAGES as STATUS_MESSAGES
from sso._studies.batched import BatchedPoints, batchable
from sso._studies.element_columns import gathered
from sso._studies.point_row import PointRow
from sso._studies.table import TIME_COLUMNS, read_rows, render_rows
from sso._studies.worker import SweepChunk, run_point, run_sweep_chunk

RE_ATOL = 1e-12
LM_COLUMNS = ("lm_residual_error", "lm_status", "lm_success", "lm_message", "lm_kkt_per_rad",
              "lm_time_s")
POINTS_PER_SHAPE = 8


def lm_base(joints: int, option: int, starts: int, **extra) -> dict:
    return {"design": {"beta_deg": [20.0] * joints, "phase_deg": [90.0] * (joints - 1)},
            "option": option, "bounds": {"beta_deg": [5.0, 40.0]},
            "solver": {"solvers": ["lm"], "starts": starts}, **extra}


def random_axes(joints: int, seed: int) -> dict:
    rng = np.random.default_rng(seed)
    axes = {f"design.beta_deg[{k}]": [round(float(v), 6) for v in
                                       rng.uniform(2.0, 45.0, POINTS_PER_SHAPE)]
            for k in range(joints)}
    axes.update({f"design.phase_deg[{k}]": [round(float(v), 6) for v in
                                            rng.uniform(0.0, 180.0, POINTS_PER_SHAPE)]
                 for k in range(joints - 1)})
    return axes


def reference(base: dict, row: dict, paths) -> sso.OptimisationResult:
    """``sso.optimise`` with "lm" alone on the row's case, as the point-by-point path calls it."""
    document = parse_case(base, "base.toml").to_dict()
    from sso._studies.axes import point_document

    case = parse_case(point_document(document, {path: gathered(row, path) for path in paths}),
                      "point")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return sso.optimise(case.series(), case.option, **case.optimise_options())


def assert_equals_sso_optimise(base: dict, rows, paths) -> None:
    for row in rows:
        assert row["status"] == "ok", row["error"]
        single = reference(base, row, paths)
        assert single.solutions.keys() == {"lm"}
        assert row["residual_error"] == pytest.approx(single.fun, rel=0, abs=RE_ATOL)
        assert row["lm_residual_error"] == pytest.approx(single.fun, rel=0, abs=RE_ATOL)
        assert row["success"] is single.success
        assert row["best_solver"] == "lm"


@pytest.mark.parametrize("starts", [2, 4])
@pytest.mark.parametrize("joints, option", [(2, 3), (3, 1), (3, 2), (3, 3), (4, 3)])
def test_each_batched_point_equals_sso_optimise_with_lm(joints, option, starts):
    base = lm_base(joints, option, starts)
    axes = random_axes(joints, seed=10 * joints + option)
    result = sso.sweep(base, axes, mode="listed", workers=1, progress=False)
    assert [row["point"] for row in result.rows] == list(range(POINTS_PER_SHAPE))
    assert_equals_sso_optimise(base, result.rows, list(axes))
    for row in result.rows:
        # The optimum's figures are those of the design the row reports (numpy over the
        # chunk against math on one design: equal to the last few bits).
        evaluation = sso.ShaftSeries(gathered(row, "design_beta_deg"),
                                     gathered(row, "design_phase_deg")).evaluate()
        assert row["residual_error"] == pytest.approx(evaluation.residual_error, rel=1e-12,
                                                      abs=1e-30)
        assert row["max_output_accel_rad_s2"] == pytest.approx(
            evaluation.max_output_accel_rad_s2, rel=1e-12, abs=1e-30)
        assert all(5.0 <= beta <= 40.0 for beta in gathered(row, "design_beta_deg")) or option == 1
        assert all(row[column] is not None for column in LM_COLUMNS)
        assert row["lm_time_s"] > 0.0 and row["lm_kkt_per_rad"] >= 0.0
        assert row["ipopt_residual_error"] is None and row["slsqp_residual_error"] is None
        assert row["crosscheck_agree"] is None
        assert row["lm_message"] in STATUS_MESSAGES.values()  # the batched solver's words


def test_the_batched_row_has_the_columns_and_warnings_of_the_point_by_point_row():
    # A start outside its bounds (50 > 40 deg) is moved onto them with a warning.
    document = parse_case(lm_base(3, 3, 4), "base.toml").to_dict()
    points = ((0, {"design.beta_deg[2]": 50.0}), (1, {"design.beta_deg[2]": 25.0}))
    batched = list(run_sweep_chunk(SweepChunk.listed(document, "optimise", points)).rows())
    single = [run_point(index, document, point, "optimise") for index, point in points]
    for fast, slow in zip(batched, single, strict=True):
        assert ({key for key, value in fast.items() if value not in (None, "")}
                - {"sweep_hash"}
                == {key for key, value in slow.items() if value not in (None, "")})
        assert fast["residual_error"] == pytest.approx(slow["residual_error"], rel=0,
                                                       abs=RE_ATOL)
        assert fast["success"] is slow["success"] and fast["status"] == "ok"
        assert (fast["warnings"] or "") == slow["warnings"]
    assert "start beta_deg[2] = 50 deg lies outside its bounds" in batched[0]["warnings"]


def test_a_sweep_mixing_shapes_gives_rows_in_point_order():
    # Listed points of two, three and four joints, options, bounds and solvers, in one
    # chunk: the lm points form four batches, the slsqp point is solved on its own.
    base = lm_base(2, 3, 2)
    axes = {
        "design.beta_deg": [[20.0, 30.0], [25.0, 10.0, 30.0], [30.0, 12.0],
                            [15.0, 20.0, 25.0, 30.0], [20.0, 30.0], [35.0, 25.0, 15.0],
                            [18.0, 33.0]],
        "design.phase_deg": [[60.0], [30.0, 120.0], [90.0], [10.0, 80.0, 150.0], [100.0],
                             [45.0, 135.0], [70.0]],
        "option": [3, 1, 3, 3, 3, 2, 3],
        "bounds.beta_deg": [[5.0, 40.0], [5.0, 40.0], [5.0, 40.0], [5.0, 40.0],
                            [22.0, 40.0], [5.0, 40.0], [5.0, 40.0]],
        "solver.solvers": [["lm"], ["lm"], ["slsqp"], ["lm"], ["lm"], ["lm"], ["lm"]],
    }
    result = sso.sweep(base, axes, mode="listed", workers=1, chunk_size=7, progress=False)
    assert [row["point"] for row in result.rows] == list(range(7))
    assert [row["best_solver"] for row in result.rows] == ["lm", "lm", "slsqp", "lm", "lm",
                                                           "lm", "lm"]
    assert [len(gathered(row, "design_beta_deg")) for row in result.rows] == [2, 3, 2, 4, 2, 3, 2]
    assert gathered(result.rows[4], "design_beta_deg")[0] >= 22.0  # its own bounds
    for row, beta_deg in zip(result.rows, axes["design.beta_deg"], strict=True):
        assert gathered(row, "design.beta_deg") == beta_deg
        single = reference(base, row, list(axes))
        assert row["residual_error"] == pytest.approx(single.fun, rel=0, abs=RE_ATOL)
        assert row["success"] is single.success


def test_a_bad_point_in_a_batched_group_is_an_error_row_and_the_others_solve():
    base = lm_base(3, 3, 2)
    axes = {"design.beta_deg[0]": [20.0, 95.0, 30.0, 25.0], "model": ["exact", "exact",
                                                                      "paper", "exact"]}
    result = sso.sweep(base, axes, mode="listed", workers=1, chunk_size=4, progress=False)
    statuses = [row["status"] for row in result.rows]
    assert statuses == ["ok", "failed", "failed", "ok"]
    assert result.rows[1]["error"].startswith(
        "CaseError: point 1: design.beta_deg[0] = 95 is outside the allowed range")
    assert result.rows[2]["error"] == (
        "CaseError: point 2: solver.solvers = ['lm'] includes 'lm', the least-squares solver "
        "of the exact model's closed form; model = 'paper' allows 'ipopt', 'slsqp'")
    assert_equals_sso_optimise(base, [result.rows[0], result.rows[3]], list(axes))


def test_a_group_whose_batch_call_fails_is_solved_point_by_point():
    # optimise_batch refuses this tolerance; sso.optimise, the fallback, refuses it too,
    # so the point is an error row naming it (no exception), and its neighbour solves.
    from sso._studies.worker import _optimise_row

    case = parse_case(lm_base(2, 3, 2), "base.toml")
    broken = replace(case, solver_tol=2.0)
    rows = [PointRow({"point": 0}), PointRow({"point": 1})]
    points = BatchedPoints(_optimise_row)
    points.add(rows[0], broken)
    points.add(rows[1], case)
    points.solve()
    finished = [row.finish() for row in rows]
    assert finished[0]["status"] == "failed"
    assert finished[0]["error"] == ("ValueError: solver_tol = 2 is outside the allowed range "
                                    "(0, 1)")
    assert finished[1]["status"] == "ok" and finished[1]["residual_error"] < 1e-20


def test_only_exact_model_cases_with_lm_alone_and_several_starts_are_batched():
    lm = parse_case(lm_base(2, 3, 2), "lm.toml")
    assert batchable(lm)
    assert not batchable(replace(lm, starts=1))
    assert not batchable(replace(lm, solvers=("lm", "slsqp")))
    assert not batchable(replace(lm, solvers=("ipopt",)))
    assert not batchable(replace(lm, model="paper"))


def test_a_resumed_batched_sweep_writes_the_file_of_an_uninterrupted_run(tmp_path):
    # Resuming regroups the missing points into other chunks; every point's row must
    # still be the one the uninterrupted run wrote (apart from wall times).
    base = lm_base(3, 3, 4)
    axes = random_axes(3, seed=5)
    whole = sso.sweep(base, axes, mode="listed", out_dir=tmp_path / "whole", workers=1,
                      chunk_size=8, plots=False, progress=False)
    assert all(row["status"] == "ok" for row in whole.rows)
    written = read_rows(tmp_path / "whole" / "sweep.csv")
    partial = tmp_path / "partial"
    partial.mkdir()
    for name in ("sweep.json", "sso-files.json"):  # what an interrupted sweep leaves
        (partial / name).write_bytes((tmp_path / "whole" / name).read_bytes())
    (partial / "sweep.csv").write_text(render_rows(list(written[0]), written[::3]))
    resumed = sso.sweep(base, axes, mode="listed", out_dir=partial, workers=1, chunk_size=2,
                        plots=False, progress=False, resume=True)
    assert resumed.resumed == 3 and resumed.computed == POINTS_PER_SHAPE - 3

    def without_times(rows):
        return [{key: value for key, value in row.items() if key not in TIME_COLUMNS}
                for row in sorted(rows, key=lambda row: int(row["point"]))]

    # The file holds the earlier rows first, then the new ones as they were appended.
    assert without_times(read_rows(partial / "sweep.csv")) == without_times(written)


def test_the_local_pool_gives_the_rows_of_one_process():
    base = lm_base(3, 3, 2)
    axes = random_axes(3, seed=6)
    one = sso.sweep(base, axes, mode="listed", workers=1, progress=False)
    pool = sso.sweep(base, axes, mode="listed", workers=2, chunk_size=3, progress=False)
    strip = [{key: value for key, value in row.items() if key not in TIME_COLUMNS}
             for row in one.rows]
    assert [{key: value for key, value in row.items() if key not in TIME_COLUMNS}
            for row in pool.rows] == strip


@pytest.mark.parametrize("option", [1, 2, 3])
def test_a_point_s_starts_are_those_sso_optimise_draws(option):
    from sso._shafts.options import build_problem
    from sso._solvers.starts import start_points
    from sso._studies.batched import _member

    case = parse_case({**lm_base(3, option, 6), "design": {"beta_deg": [12.0, 44.0, 33.0],
                                                           "phase_deg": [70.0, 20.0]},
                       "solver": {"solvers": ["lm"], "starts": 6, "seed": 99}}, "starts.toml")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        member = _member(PointRow({}), case)
        problem = build_problem(case.beta_deg, case.phase_deg, "exact", option,
                                case.beta_bounds_deg, case.phase_bounds_deg)
    expected = start_points(problem.start_rad, problem.lower_rad, problem.upper_rad, 6, 99)
    full = np.hstack([member.beta_deg, member.phase_deg])
    free = {1: [3, 4], 2: [0, 1, 2], 3: [0, 1, 2, 3, 4]}[option]
    fixed = [column for column in range(5) if column not in free]
    np.testing.assert_allclose(np.radians(full[:, free]), expected, rtol=1e-15, atol=0)
    np.testing.assert_array_equal(full[0, free], problem.start_deg)  # the user's, exactly
    given = [12.0, 44.0, 33.0, 90.0, 90.0] if option == 2 else [12.0, 44.0, 33.0, 70.0, 20.0]
    np.testing.assert_array_equal(full[:, fixed], np.broadcast_to(
        np.array(given)[fixed], (6, len(fixed))))
