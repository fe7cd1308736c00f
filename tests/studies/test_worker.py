"""One sweep point as a worker runs it: a row of numbers, or an error row, never a raise.

Reference: one joint's residual error (1 - cos b)^2 / (2 cos b) (derived in
tests/shafts/test_objective.py); two equal joints at a 90 deg phase cancel (RE 0).
"""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

from sso._cases.schema import parse_case
from sso._studies.axes import parse_axes, value_positions, value_ranges
from sso._studies.element_columns import gathered
from sso._studies.table import columns
from sso._studies.worker import (
    GridPositions,
    SweepChunk,
    failed_rows,
    run_point,
    run_sweep_chunk,
)

ONE_JOINT = parse_case({"design": {"beta_deg": [30.0]}, "option": 2}, "one.toml").to_dict()
TWO_JOINTS = parse_case(
    {"design": {"beta_deg": [30.0, 20.0]}, "solver": {"starts": 2}}, "two.toml"
).to_dict()


def test_evaluate_gives_the_closed_form_residual_error():
    row = run_point(4, ONE_JOINT, {"design.beta_deg[0]": 25.0}, "evaluate")
    c = math.cos(math.radians(25.0))
    assert row["status"] == "ok" and row["point"] == 4 and row["design.beta_deg[0]"] == 25.0
    assert row["residual_error"] == pytest.approx((1 - c) ** 2 / (2 * c), rel=1e-9)
    assert gathered(row, "design_beta_deg") == [25.0] and row["time_s"] > 0.0


def test_optimise_row_carries_each_solvers_columns():
    row = run_point(0, TWO_JOINTS, {"design.phase_deg[0]": 60.0}, "optimise")
    assert row["status"] == "ok" and row["success"] is True
    assert row["residual_error"] < 1e-20  # equal angles at 90 deg cancel
    assert row["crosscheck_agree"] is True
    for solver in ("ipopt", "slsqp"):
        assert row[f"{solver}_success"] is True and row[f"{solver}_residual_error"] < 1e-12


def test_a_bad_point_is_an_error_row_naming_the_key():
    row = run_point(1, ONE_JOINT, {"design.beta_deg[0]": 95.0}, "evaluate")
    assert row["status"] == "failed"
    assert row["error"].startswith("CaseError: point 1: design.beta_deg[0] = 95 is outside")
    assert "residual_error" not in row


def test_a_chunk_runs_its_points_in_order_and_lost_chunks_are_marked():
    chunk = SweepChunk.listed(ONE_JOINT, "evaluate",
                              ((7, {"design.beta_deg[0]": 10.0}),
                               (3, {"design.beta_deg[0]": 20.0})), sweep_hash="abc")
    rows = list(run_sweep_chunk(chunk).rows())
    assert [row["point"] for row in rows] == [7, 3]
    assert [row["sweep_hash"] for row in rows] == ["abc", "abc"]
    assert rows[0]["residual_error"] < rows[1]["residual_error"]
    lost = [{key: value for key, value in row.items() if value is not None}
            for row in failed_rows(chunk, MemoryError("worker died")).rows()]
    assert lost == [
        {"point": 7, "design.beta_deg[0]": 10.0, "status": "lost",
         "error": "MemoryError: worker died", "sweep_hash": "abc"},
        {"point": 3, "design.beta_deg[0]": 20.0, "status": "lost",
         "error": "MemoryError: worker died", "sweep_hash": "abc"},
    ]


def test_a_chunk_travels_as_its_first_point_and_count_whatever_its_size():
    case = parse_case({"design": {"beta_deg": [30.0, 20.0]}}, "two.toml")
    axes = parse_axes({"design.beta_deg[0]": {"start": 10.0, "stop": 40.0, "num": 1000},
                       "design.beta_deg[1]": {"start": 10.0, "stop": 40.0, "num": 1000}},
                      case.to_dict())
    sizes = []
    for points in (1_000, 100_000):
        indices = np.arange(5, 5 + points)
        bounds = value_ranges((1000, 1000), "product", 5, 4 + points)
        chunk = SweepChunk(case.to_dict(), "evaluate", tuple(columns(["a", "b"])),
                           tuple(axis.path for axis in axes), indices,
                           tuple(axis.values[low:high] for axis, (low, high)
                                 in zip(axes, bounds, strict=True)),
                           None, "hash", GridPositions("product", (1000, 1000),
                                                       tuple(low for low, _ in bounds)))
        data = pickle.dumps(chunk)
        back = pickle.loads(data)
        assert back.indices.tolist() == indices.tolist()
        # Reference: the positions value_positions gives for the whole sweep, less the
        # chunk's first value of each axis.
        for mine, whole, (low, _) in zip(back.value_indices,
                                         value_positions(axes, "product", indices), bounds,
                                         strict=True):
            assert mine.tolist() == (whole - low).tolist()
        sizes.append(len(data))
    assert sizes[1] < sizes[0] + 25_000  # the values of axis 0 it takes, not its points
