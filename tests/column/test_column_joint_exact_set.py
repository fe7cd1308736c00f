"""Joint centres moved within their boxes reach RE = 0 on a set: the design chosen within
it (the joint centres furthest inside their boxes) and the set's extent per coordinate.

The shipped truck column (cases/column_truck_three_joints.toml: its 36-tooth phasing held,
boxes of +-5 mm about P1 .. P3, operating angles within 5 .. 25 deg). Reference: the
independent 3D cross-and-yoke simulation (tests/column/cross_and_yoke.py), minimised by
SciPy's least squares over the other coordinates within the boxes: every end's witness is
an exact optimum, inside the reported extent the speed ratio can be made constant, just
outside an end that is not a box face it cannot (even without the angle bounds, which
only remove designs).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from cross_and_yoke import residual_error as simulated_residual_error
from cross_and_yoke import shaft_axes, speed_ratio
from scipy.optimize import least_squares

import sso
from sso._cases.schema import load_case
from sso._column.joint_centres import optimise_joint_centres

ROOT = Path(__file__).resolve().parents[2]
ANGLES = np.pi * np.arange(64) / 64


@pytest.fixture(scope="module")
def truck():
    case = load_case(ROOT / "cases" / "column_truck_three_joints.toml")
    options = case.joint_position_options()
    return case, options, optimise_joint_centres(case.geometry(), **options)


def _least_simulated_re(points, yoke, index, value, boxes):
    """The least simulated RE over the joint centres' other coordinates within the boxes,
    coordinate ``index`` of P1 x, y, z, P2 x, ... held at ``value`` (mm)."""
    lower, upper = boxes[:, 0, :].ravel(), boxes[:, 1, :].ravel()
    start = np.asarray(points[1:-1], dtype=float).ravel()
    others = [other for other in range(len(start)) if other != index]

    def moved(free):
        centres = start.copy()
        centres[others], centres[index] = free, value
        column = np.asarray(points, dtype=float).copy()
        column[1:-1] = centres.reshape(-1, 3)
        return column

    def residuals(free):
        column = moved(free)
        reference = np.cross(shaft_axes(column)[0], [0.3, -0.5, 0.8])
        return speed_ratio(column, yoke, ANGLES, reference / np.linalg.norm(reference)) - 1.0

    found = least_squares(residuals, start[others], bounds=(lower[others], upper[others]),
                          xtol=1e-15, ftol=1e-15, gtol=1e-15)
    return simulated_residual_error(moved(found.x), yoke)


def test_the_joint_centres_are_chosen_furthest_inside_their_boxes(truck):
    _, options, result = truck
    exact = result.exact_optima
    assert result.success, result.message
    assert exact is not None
    assert exact.criterion == "largest margin of the joint centres to their boxes"
    assert exact.units == ("mm",) * 9 and exact.margin_unit == "mm"
    assert exact.dimension == 7  # nine coordinates, two residuals
    points = np.asarray(result.points_mm)
    assert simulated_residual_error(points, result.yoke_phase_deg) <= 1e-12
    assert result.yoke_phase_deg == pytest.approx(options["yoke_phase_deg"], abs=1e-12)
    boxes = np.asarray(options["joint_boxes_mm"])
    margin = float(np.min(np.minimum(points[1:-1] - boxes[:, 0, :],
                                     boxes[:, 1, :] - points[1:-1])))
    assert exact.margin == pytest.approx(margin, abs=1e-6)
    # measured: 2.33 mm, the first exact optimum the solvers reached 0.40 mm
    assert exact.margin >= 2.0 and exact.first_margin <= 0.5
    assert exact.chosen == pytest.approx(points[1:-1].ravel(), abs=1e-9)
    assert result.best.role == "selection"
    assert result.found_by == "least_squares choosing within the exact optima"
    for beta, (low, high) in zip(result.geometry.beta_deg, result.beta_bounds_deg, strict=True):
        assert low - 1e-9 <= beta <= high + 1e-9


def test_the_extent_of_the_set_is_the_3d_simulations(truck):
    _, options, result = truck
    exact = result.exact_optima
    boxes = np.asarray(options["joint_boxes_mm"])
    faces = boxes.transpose(1, 0, 2).reshape(2, -1)
    points, yoke = np.asarray(result.points_mm), result.yoke_phase_deg
    inner_ends = 0
    for index, ((low, high), pair) in enumerate(zip(exact.extent, exact.extent_search.ends,
                                                    strict=True)):
        assert faces[0, index] <= low <= exact.chosen[index] <= high <= faces[1, index]
        for end, face, step in zip(pair, faces[:, index], (-0.3, 0.3), strict=True):
            # every witness: an exact optimum by the 3D simulation, its joint centres in
            # their boxes, coordinate ``index`` at the end
            witness = np.asarray(end.witness).reshape(-1, 3)
            column = points.copy()
            column[1:-1] = witness
            assert simulated_residual_error(column, yoke) <= 1e-12, (index, end)
            assert end.witness[index] == end.value
            assert np.all(witness >= boxes[:, 0, :]) and np.all(witness <= boxes[:, 1, :])
            if end.at_bound:
                assert end.value == face
            else:
                # a lower estimate: the furthest value the search reached; here the 3D
                # simulation's least squares cannot go 0.3 mm further
                inner_ends += 1
                assert _least_simulated_re(points, yoke, index, end.value + step, boxes) > 1e-9
        for inside in (low + 0.2, high - 0.2):
            assert _least_simulated_re(points, yoke, index, inside, boxes) <= 1e-12, (index, inside)
    # measured: P3 x ends at -1471.12 mm, 1.8 mm inside its box; every other end is a face
    assert inner_ends == 1
    assert not exact.extent_search.ends[6][0].at_bound
    assert exact.extent[6][0] == pytest.approx(-1471.12, abs=0.01)
    # the stated bound on the search: per coordinate and side, 1 + 32 probes at the face
    # and 12 halvings of 2 starts (measured: 67 solves)
    assert exact.extent_search.solves <= 2 * 9 * (1 + 32 + 12 * 2)


def test_the_column_run_reports_the_set(truck, tmp_path):
    from sso._run.column import run_column

    case, _, _ = truck
    run = run_column(case, optimising=True)
    assert run.joint_centres is not None and run.joint_centres.exact_optima is not None
    saved = run.to_dict()["joint_centres"]["exact_optima"]
    assert saved["criterion"] == "largest margin of the joint centres to their boxes"
    assert len(saved["extent_search"]["ends"]) == 9
    assert type(run).from_dict(run.to_dict()).joint_centres.exact_optima.extent_search == (
        run.joint_centres.exact_optima.extent_search)
    sso.write_report(run, tmp_path / "report", formats=("md",))
    text = (tmp_path / "report" / "report.md").read_text()
    assert ("chosen within it by largest margin of the joint centres to their boxes" in text)
    assert "| P3 x | mm |" in text
