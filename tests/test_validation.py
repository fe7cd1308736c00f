"""sso._validation: bad input fails with a message naming the field, the value and the range.

The expected messages are the house rule's wording (COMMON.md: "ValueError naming
the field, the value and the allowed range"); the intervals are the ones each call
passes in.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from sso._validation import (
    as_float_tuple,
    check_choice,
    check_in_range,
    finite_float,
    finite_in_range,
    per_item_bounds,
    validate_count,
    validate_solver_tol,
    validate_solvers,
    validate_speed,
)


def test_finite_float_accepts_numbers_and_numpy_scalars():
    assert finite_float("x", 3) == 3.0
    assert finite_float("x", np.float32(0.5)) == 0.5
    assert finite_float("x", "2.5") == 2.5  # float() parses it; callers that care check types
    assert type(finite_float("x", np.int64(7))) is float


@pytest.mark.parametrize(
    "value, message",
    [
        (True, "x = True must be a number, not a boolean"),
        (None, "x = None must be a number"),
        ("fast", "x = 'fast' must be a number"),
        (math.nan, "x = nan must be finite (not NaN or infinite)"),
        (-math.inf, "x = -inf must be finite (not NaN or infinite)"),
    ],
)
def test_finite_float_refuses(value, message):
    with pytest.raises(ValueError) as caught:
        finite_float("x", value)
    assert str(caught.value) == message


def test_as_float_tuple_takes_a_scalar_or_a_sequence():
    assert as_float_tuple("beta_deg", 20) == (20.0,)
    assert as_float_tuple("beta_deg", np.array([1, 2.5])) == (1.0, 2.5)
    with pytest.raises(ValueError, match=r"^beta_deg = '20' must be a number or a list"):
        as_float_tuple("beta_deg", "20")
    with pytest.raises(ValueError, match=r"^beta_deg\[1\] = nan must be finite"):
        as_float_tuple("beta_deg", [1.0, math.nan])


def test_check_in_range_closed_and_open_ends():
    assert check_in_range("beta_deg[0]", 0.0, 0.0, 90.0, "deg", upper_open=True) == 0.0
    with pytest.raises(ValueError) as caught:
        check_in_range("beta_deg[0]", 90.0, 0.0, 90.0, "deg", upper_open=True)
    assert str(caught.value) == "beta_deg[0] = 90 is outside the allowed range [0, 90) deg"
    with pytest.raises(ValueError) as caught:
        check_in_range("rtol", 0.0, 0.0, 1.0, lower_open=True)
    assert str(caught.value) == "rtol = 0 is outside the allowed range (0, 1]"
    assert check_in_range("rtol", 1.0, 0.0, 1.0, lower_open=True) == 1.0


def test_finite_in_range_and_speed_and_tolerance():
    assert finite_in_range("phase_deg", -360, -360.0, 360.0, "deg") == -360.0
    assert validate_speed("input_speed_rpm", 25) == 25.0
    with pytest.raises(ValueError) as caught:
        validate_speed("input_speed_rpm", 0.0)
    assert str(caught.value) == "input_speed_rpm = 0 is outside the allowed range (0, 1e+06] rpm"
    with pytest.raises(ValueError, match="must be finite"):
        validate_speed("input_speed_rpm", math.inf)
    assert validate_solver_tol(1e-12) == 1e-12
    with pytest.raises(ValueError) as caught:
        validate_solver_tol(1.0)
    assert str(caught.value) == "solver_tol = 1 is outside the allowed range (0, 1)"


def test_check_choice_names_the_choices():
    assert check_choice("model", "paper", ("exact", "paper")) == "paper"
    with pytest.raises(ValueError) as caught:
        check_choice("model", "fast", iter(["exact", "paper"]))
    assert str(caught.value) == "model = 'fast' is not one of 'exact', 'paper'"


def test_per_item_bounds_expands_one_pair_or_checks_each():
    assert (
        per_item_bounds("beta_bounds_deg", (10, 40), 3, 0.0, 90.0, "deg", True)
        == ((10.0, 40.0),) * 3
    )
    pairs = per_item_bounds(
        "beta_bounds_deg", [(0, 10), np.array([5.0, 5.0])], 2, 0.0, 90.0, "deg", True
    )
    assert pairs == ((0.0, 10.0), (5.0, 5.0))  # an equal pair pins the item


@pytest.mark.parametrize(
    "bounds, count, message",
    [
        (
            (40, 10),
            2,
            (
                "beta_bounds_deg = (40, 10) deg is inverted (empty): the lower bound must "
                "not exceed the upper bound"
            ),
        ),
        (
            [(0, 10)],
            2,
            "beta_bounds_deg = [(0, 10)] must be one (lower, upper) pair or 2 pairs",
        ),
        (5.0, 1, "beta_bounds_deg = 5.0 must be one (lower, upper) pair or 1 pairs"),
        ("ab", 1, "beta_bounds_deg = 'ab' must be one (lower, upper) pair or 1 pairs"),
        (
            (0, 90),
            1,
            "beta_bounds_deg upper = 90 is outside the allowed range [0, 90) deg",
        ),
        (
            [(0, 10), (-1, 10)],
            2,
            ("beta_bounds_deg[1] lower = -1 is outside the allowed range [0, 90) deg"),
        ),
        ((True, 10), 1, "must be one (lower, upper) pair or 1 pairs"),
    ],
)
def test_per_item_bounds_refuses(bounds, count, message):
    with pytest.raises(ValueError) as caught:
        per_item_bounds("beta_bounds_deg", bounds, count, 0.0, 90.0, "deg", upper_open=True)
    assert message in str(caught.value)


def test_validate_solvers():
    assert validate_solvers("slsqp") == ("slsqp",)
    assert validate_solvers(["ipopt", "slsqp"]) == ("ipopt", "slsqp")
    for solvers, message in [
        ([], "solvers is empty; choose one or more of ipopt, slsqp"),
        (["ipopt", "cobyla"], "solvers[1] = 'cobyla' is not one of ipopt, slsqp"),
        (["ipopt", "ipopt"], "solvers = ['ipopt', 'ipopt'] names a solver twice"),
    ]:
        with pytest.raises(ValueError) as caught:
            validate_solvers(solvers)
        assert str(caught.value) == message


def test_validate_count():
    assert validate_count("starts", np.int64(4), 1, 10) == 4
    assert type(validate_count("starts", np.int64(4), 1, 10)) is int
    for value, message in [
        (4.0, "starts = 4.0 must be a whole number in [1, 10]"),
        (True, "starts = True must be a whole number in [1, 10]"),
        (11, "starts = 11 is outside the allowed range [1, 10]"),
        (0, "starts = 0 is outside the allowed range [1, 10]"),
    ]:
        with pytest.raises(ValueError) as caught:
            validate_count("starts", value, 1, 10)
        assert str(caught.value) == message
