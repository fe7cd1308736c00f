"""Start points: the user's start, then scrambled Halton points inside the bounds."""

from __future__ import annotations

import numpy as np

from sso.solvers.starts import DEFAULT_SEED, start_points

LOWER, UPPER = np.array([0.0, -10.0, 5.0]), np.array([1.0, 10.0, 5.0])
USER = np.array([0.5, 3.0, 5.0])


def test_one_start_is_the_users_own():
    points = start_points(USER, LOWER, UPPER, 1)
    np.testing.assert_array_equal(points, USER[np.newaxis, :])


def test_starts_fill_the_box_and_repeat_with_the_seed():
    points = start_points(USER, LOWER, UPPER, 9)
    assert points.shape == (9, 3)
    np.testing.assert_array_equal(points[0], USER)
    assert np.all(points[1:] >= LOWER) and np.all(points[1:] <= UPPER)
    np.testing.assert_array_equal(points[1:, 2], 5.0)  # a pinned variable stays pinned
    np.testing.assert_array_equal(points, start_points(USER, LOWER, UPPER, 9, DEFAULT_SEED))
    assert not np.array_equal(points, start_points(USER, LOWER, UPPER, 9, DEFAULT_SEED + 1))


def test_first_coordinate_is_stratified():
    """Halton's first coordinate is the base-2 van der Corput sequence; scrambling keeps its
    stratification, so 8 points put exactly one in each eighth of the range."""
    points = start_points(USER, LOWER, UPPER, 9)[1:, 0]
    counts = np.histogram(points, bins=8, range=(0.0, 1.0))[0]
    np.testing.assert_array_equal(counts, np.ones(8))
