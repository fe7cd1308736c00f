"""The three design options: which angles are free, the design vector and its bounds.

Reference: the paper's options (README "Case files": 1 phases, 2 operating angles with
phases fixed at 90 deg, 3 both), and the layout documented in DesignProblem.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from sso._shafts.options import (
    StartMovedWarning,
    build_problem,
    parse_option,
    warn_moved_starts,
)

BETA, PHASE = [30.0, 40.0, 20.0], [80.0, 100.0]


@pytest.mark.parametrize(
    "given, number",
    [(1, 1), (np.int64(2), 2), (3, 3), ("phase", 1), (" Angle ", 2), ("BOTH", 3)],
)
def test_parse_option(given, number):
    assert parse_option(given) == number


@pytest.mark.parametrize("given", [0, 4, True, 2.0, "all", None])
def test_parse_option_refuses(given):
    with pytest.raises(ValueError) as caught:
        parse_option(given)
    assert str(caught.value) == (
        f"option = {given!r} is not one of 1, 2, 3, 'phase', 'angle', 'both'"
    )


def test_option_1_frees_the_phases_and_fixes_the_angles():
    problem = build_problem(BETA, PHASE, "exact", "phase", (0, 40), (0, 180))
    assert (problem.beta_free, problem.phase_free, problem.n_free) == (False, True, 2)
    np.testing.assert_array_equal(problem.start_deg, PHASE)
    np.testing.assert_array_equal(problem.parameters_deg, BETA)
    np.testing.assert_allclose(problem.upper_rad, [math.pi, math.pi], rtol=1e-15)
    assert problem.design_deg([85.0, 95.0]) == (tuple(BETA), (85.0, 95.0))
    assert problem.beta_upper_rad == pytest.approx(np.radians(BETA).tolist(), rel=1e-15)


def test_option_2_fixes_every_phase_at_90_whatever_is_given():
    problem = build_problem(BETA, PHASE, "exact", 2, (10, 40), (0, 180))
    assert problem.option_name == "angle" and problem.n_free == 3
    np.testing.assert_array_equal(problem.parameters_deg, [90.0, 90.0])
    assert problem.design_deg([11.0, 12.0, 13.0]) == ((11.0, 12.0, 13.0), (90.0, 90.0))
    assert problem.beta_upper_rad == pytest.approx([math.radians(40.0)] * 3, rel=1e-15)


def test_option_3_lays_out_angles_first_then_phases():
    problem = build_problem(BETA, PHASE, "paper", 3, [(0, 35), (0, 45), (0, 25)], (0, 180))
    np.testing.assert_array_equal(problem.start_deg, BETA + PHASE)
    assert problem.parameters_deg.size == 0
    np.testing.assert_allclose(np.degrees(problem.upper_rad), [35, 45, 25, 180, 180], rtol=1e-15)
    beta, phase = problem.split([1, 2, 3, 4, 5], [])
    assert (beta, phase) == ([1, 2, 3], [4, 5])
    np.testing.assert_allclose(problem.start_rad, np.radians(BETA + PHASE), rtol=1e-15)


def test_a_start_outside_its_bounds_is_moved_and_listed_then_warned():
    problem = build_problem(BETA, PHASE, "exact", 3, (0, 35), (0, 90))
    assert problem.start_deg.tolist() == [30.0, 35.0, 20.0, 80.0, 90.0]
    expected = [
        "start beta_deg[1] = 40 deg lies outside its bounds [0, 35] deg; moved onto 35 deg",
        "start phase_deg[1] = 100 deg lies outside its bounds [0, 90] deg; moved onto 90 deg",
    ]
    assert list(problem.moved_starts) == expected
    with pytest.warns(StartMovedWarning) as caught:
        warn_moved_starts(problem)
    assert [str(warning.message) for warning in caught] == expected


def test_option_1_needs_two_joints_and_bounds_are_checked():
    with pytest.raises(ValueError, match=r"^option = 1 \(phases\) needs at least 2 joints"):
        build_problem([30.0], [], "exact", 1, (0, 40), (0, 180))
    with pytest.raises(
        ValueError,
        match=r"beta_bounds_deg upper = 90 is outside the allowed "
        r"range \[0, 90\) deg",
    ):
        build_problem(BETA, PHASE, "exact", 3, (0, 90), (0, 180))
    with pytest.raises(ValueError, match=r"phase_bounds_deg lower = -400 is outside"):
        build_problem(BETA, PHASE, "exact", 3, (0, 40), (-400, 180))


def test_kept_layout_still_refuses_what_a_fresh_check_refuses():
    """The layout of plain bounds is kept between calls; a value equal to a kept one but
    of another type (a boolean, a float option) is still checked and refused."""
    build_problem(BETA, PHASE, "exact", 2, (1, 40), (0, 180))
    with pytest.raises(ValueError, match=r"beta_bounds_deg = \(True, 40\) must be one"):
        build_problem(BETA, PHASE, "exact", 2, (True, 40), (0, 180))
    with pytest.raises(ValueError, match=r"option = 2.0 is not one of"):
        build_problem(BETA, PHASE, "exact", 2.0, (1, 40), (0, 180))


def test_kept_layout_gives_each_start_its_own_moves_and_read_only_bounds():
    first = build_problem(BETA, PHASE, "exact", 3, (25, 35), (0, 90))
    second = build_problem([26.0, 27.0, 28.0], [10.0, 20.0], "exact", 3, (25, 35), (0, 90))
    assert first.moved_starts == (
        "start beta_deg[1] = 40 deg lies outside its bounds [25, 35] deg; moved onto 35 deg",
        "start beta_deg[2] = 20 deg lies outside its bounds [25, 35] deg; moved onto 25 deg",
        "start phase_deg[1] = 100 deg lies outside its bounds [0, 90] deg; moved onto 90 deg")
    assert second.moved_starts == ()
    np.testing.assert_array_equal(first.start_deg, [30.0, 35.0, 25.0, 80.0, 90.0])
    np.testing.assert_array_equal(second.start_deg, [26.0, 27.0, 28.0, 10.0, 20.0])
    assert first.lower_rad is second.lower_rad
    with pytest.raises(ValueError, match="read-only"):
        first.upper_rad[0] = 0.0


def test_a_start_given_again_is_told_the_same_moves_and_a_zero_keeps_its_sign():
    # The layout keeps the messages of a start given again; 0 and -0 are equal keys but
    # print apart, so a start holding a zero is told its own.
    first = build_problem(BETA, PHASE, "exact", 3, (25, 36), (0, 90))
    again = build_problem(list(BETA), list(PHASE), "exact", 3, (25, 36), (0, 90))
    assert again.moved_starts == first.moved_starts == (
        "start beta_deg[1] = 40 deg lies outside its bounds [25, 36] deg; moved onto 36 deg",
        "start beta_deg[2] = 20 deg lies outside its bounds [25, 36] deg; moved onto 25 deg",
        "start phase_deg[1] = 100 deg lies outside its bounds [0, 90] deg; moved onto 90 deg")
    for zero, shown in ((0.0, "0"), (-0.0, "-0"), (0.0, "0")):
        problem = build_problem([zero, 30.0, 30.0], [10.0, 20.0], "exact", 3, (25, 36), (0, 90))
        assert problem.moved_starts == (
            f"start beta_deg[0] = {shown} deg lies outside its bounds [25, 36] deg; moved onto "
            "25 deg",)
