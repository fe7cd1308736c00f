"""Start points: reproducible, inside the bounds, space-filling, without scipy.stats.

Reference: scipy's own discrepancy measure (``scipy.stats.qmc.discrepancy``, the
centred L2 discrepancy) of the points against that of uniform random points.
"""

import subprocess
import sys

import numpy as np

from sso.solvers.starts import rotated_halton, start_points


def test_starts_repeat_for_a_seed_and_stay_in_bounds():
    lower, upper = np.array([0.1, -1.0, 2.0]), np.array([0.5, 1.0, 9.0])
    first = start_points(np.array([0.2, 0.0, 3.0]), lower, upper, 50, seed=7)
    again = start_points(np.array([0.2, 0.0, 3.0]), lower, upper, 50, seed=7)
    other = start_points(np.array([0.2, 0.0, 3.0]), lower, upper, 50, seed=8)
    assert first.shape == (50, 3)
    np.testing.assert_array_equal(first, again)
    assert not np.array_equal(first[1:], other[1:])
    np.testing.assert_array_equal(first[0], [0.2, 0.0, 3.0])
    assert np.all(first >= lower) and np.all(first < upper)


def test_halton_points_fill_the_box_better_than_random_points():
    from scipy.stats import qmc

    points = rotated_halton(256, 5, 3)
    random_points = np.random.default_rng(3).random((256, 5))
    assert qmc.discrepancy(points) < 0.2 * qmc.discrepancy(random_points)


def test_many_starts_do_not_import_scipy_stats():
    code = ("import sys, numpy as np; from sso.solvers.starts import start_points; "
            "start_points(np.zeros(4), np.zeros(4), np.ones(4), 100); "
            "print('scipy.stats' in sys.modules)")
    output = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            check=True)
    assert output.stdout.strip() == "False"
