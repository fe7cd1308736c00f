"""Start points: the user's start, then rotated Halton points inside the bounds.

Reference for the space filling: scipy's own discrepancy measure
(``scipy.stats.qmc.discrepancy``, the centred L2 discrepancy) of the points against
that of uniform random points.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np

from sso._limits import DEFAULT_SEED
from sso._solvers.starts import rotated_halton, start_points

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
    """Halton's first coordinate is the base-2 van der Corput sequence; the rotation keeps its
    stratification, so 8 points put exactly one in each eighth of the range."""
    points = start_points(USER, LOWER, UPPER, 9)[1:, 0]
    counts = np.histogram(points, bins=8, range=(0.0, 1.0))[0]
    np.testing.assert_array_equal(counts, np.ones(8))


def test_halton_points_fill_the_box_better_than_random_points():
    from scipy.stats import qmc

    points = rotated_halton(256, 5, 3)
    random_points = np.random.default_rng(3).random((256, 5))
    assert qmc.discrepancy(points) < 0.2 * qmc.discrepancy(random_points)


def test_many_starts_do_not_import_scipy_stats():
    code = ("import sys, numpy as np; from sso._solvers.starts import start_points; "
            "start_points(np.zeros(4), np.zeros(4), np.ones(4), 100); "
            "print('scipy.stats' in sys.modules)")
    output = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            check=True)
    assert output.stdout.strip() == "False"


def _radical_inverse(index: int, base: int) -> float:
    """Halton's coordinate of point ``index`` in ``base``, digit by digit in plain floats."""
    value, scale = 0.0, 1.0 / base
    while index:
        index, digit = divmod(index, base)
        value += digit * scale
        scale /= base
    return value


def test_rotated_halton_is_the_radical_inverse_plus_the_seeded_shift_exactly():
    for count, dimension, seed in ((1, 1, 0), (7, 3, 1), (40, 6, 20251122), (300, 11, 5)):
        shift = np.random.default_rng(seed).random(dimension)
        primes = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31][:dimension]
        expected = np.array([[(_radical_inverse(index, base) + shift[column]) % 1.0
                              for column, base in enumerate(primes)]
                             for index in range(1, count + 1)])
        np.testing.assert_array_equal(rotated_halton(count, dimension, seed), expected)
