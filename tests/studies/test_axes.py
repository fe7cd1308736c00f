"""Sweep axes: key paths, ranges, point expansion, and the errors for bad input."""

import numpy as np
import pytest

from sso._studies.axes import (
    Axis,
    base_case,
    expand_points,
    parse_axes,
    point_count,
    point_document,
    value_positions,
    value_ranges,
)

BASE = {"design": {"beta_deg": [30.0, 40.0, 50.0], "phase_deg": [90.0, 90.0]},
        "bounds": {"beta_deg": [10.0, 40.0]}}


@pytest.fixture
def document():
    return base_case(BASE).to_dict()


def test_ranges_by_count_and_by_step_include_both_ends(document):
    axes = parse_axes({"design.beta_deg[0]": {"start": 10, "stop": 40, "num": 4},
                       "input_speed_rpm": {"start": 0.1, "stop": 0.5, "step": 0.1}}, document)
    assert axes[0].values == (10.0, 20.0, 30.0, 40.0)
    # 0.1 + 2 * 0.1 is 0.30000000000000004 in binary; the grid is rounded to 12 digits.
    assert axes[1].values == (0.1, 0.2, 0.3, 0.4, 0.5)


def test_product_varies_the_last_axis_fastest_and_listed_pairs_values(document):
    axes = parse_axes({"option": [1, 3], "model": ["exact", "paper", "exact"]}, document)
    product = expand_points(axes, "product")
    assert len(product) == 6
    assert product[1] == {"option": 1, "model": "paper"}
    assert product[3] == {"option": 3, "model": "exact"}
    axes = parse_axes({"option": [1, 3], "model": ["exact", "paper"]}, document)
    assert expand_points(axes, "listed") == [{"option": 1, "model": "exact"},
                                             {"option": 3, "model": "paper"}]


def test_point_document_sets_nested_indices_without_touching_the_base(document):
    point = point_document(document, {"design.beta_deg[1]": 12.5, "bounds.beta_deg[1]": 35.0})
    assert point["design"]["beta_deg"] == [30.0, 12.5, 50.0]
    assert point["bounds"]["beta_deg"] == [10.0, 35.0]
    assert document["design"]["beta_deg"] == [30.0, 40.0, 50.0]


@pytest.mark.parametrize("axes, message", [
    ({"design.beta_dge[0]": [1]}, r"'design\.beta_dge' is not a key that can be swept; "
                                  r"did you mean 'design\.beta_deg'\?"),
    ({"name": ["a"]}, "'name' is not a key that can be swept"),
    ({"design.beta_deg[3]": [1]}, r"index 3 of design\.beta_deg is outside the allowed "
                                  r"range \[0, 2\]"),
    ({"option[0]": [1]}, r"index 0 of option is outside the allowed range none"),
    ({"option": []}, "axis 'option' is empty"),
    ({"option": 3}, "must be a list of values or a range"),
    ({"input_speed_rpm": {"start": 1, "stop": 2}}, "give start, stop and either num or step"),
    ({"input_speed_rpm": {"start": 1, "stop": 2, "num": 0}},
     r"num = 0 is outside the allowed range \[1, 10000000\]"),
    ({"input_speed_rpm": {"start": 2, "stop": 1, "step": 0.5}},
     "must be non-zero and point from start 2 towards stop 1"),
    ({"design beta": [1]}, "is not a case key with optional"),
    ({}, "must map one or more case keys"),
])
def test_bad_axes_are_refused_naming_the_axis_and_the_allowed_range(document, axes, message):
    with pytest.raises(ValueError, match=message):
        parse_axes(axes, document)


def test_listed_axes_of_different_lengths_and_unknown_modes_are_refused(document):
    axes = parse_axes({"option": [1, 3], "model": ["exact"]}, document)
    with pytest.raises(ValueError, match="mode 'listed' needs axes of equal length"):
        expand_points(axes, "listed")
    with pytest.raises(ValueError, match="mode = 'grid' is not one of 'product', 'listed'"):
        expand_points(axes, "grid")


def test_an_invalid_base_case_is_refused_naming_the_key():
    with pytest.raises(ValueError, match=r"design\.beta_deg\[0\] = 95 is outside the allowed "
                                         r"range \[0, 90\) deg"):
        base_case({"design": {"beta_deg": [95.0]}})


@pytest.mark.parametrize("lengths", [(5,), (3, 4), (2, 3, 4), (4, 1, 3)])
@pytest.mark.parametrize("mode", ["product", "listed"])
def test_value_ranges_hold_every_position_between_two_points(lengths, mode):
    # Reference: the positions of every point from first to last (value_positions), so
    # the ranges found from the ends alone must contain them and, where the positions
    # do not wrap around, be exactly their span.
    axes = [Axis(f"design.beta_deg[{axis}]", tuple(range(length)))
            for axis, length in enumerate(lengths)]
    if mode == "listed":
        axes = [Axis(axis.path, tuple(range(lengths[0]))) for axis in axes]
    count = point_count(axes, mode)
    for first in range(count):
        for last in range(first, count):
            ranges = value_ranges([len(axis.values) for axis in axes], mode, first, last)
            positions = value_positions(axes, mode, np.arange(first, last + 1))
            for (low, high), column in zip(ranges, positions, strict=True):
                assert low <= column.min() and column.max() < high
                if np.all(np.diff(column) >= 0):
                    assert (low, high) == (column.min(), column.max() + 1)
