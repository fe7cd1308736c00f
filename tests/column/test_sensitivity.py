"""The first-order sensitivity estimator from given data, on functions whose indices are
known in closed form, before it is trusted on columns."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sso._column.sensitivity import bin_count, first_order_indices, ranked


def test_the_ishigami_functions_indices():
    # Ishigami and Homma (1990), a = 7, b = 0.1, inputs uniform on [-pi, pi]: the
    # variance shares in closed form (Saltelli et al., Global Sensitivity Analysis: The
    # Primer, 2008, section 4.4): V1 = (1 + b pi^4 / 5)^2 / 2, V2 = a^2 / 8, V3 = 0,
    # V = a^2 / 8 + b pi^4 / 5 + b^2 pi^8 / 18 + 1 / 2; S1 = 0.3139, S2 = 0.4424, S3 = 0.
    a, b = 7.0, 0.1
    variance = a * a / 8 + b * math.pi**4 / 5 + b * b * math.pi**8 / 18 + 0.5
    expected = [0.5 * (1 + b * math.pi**4 / 5) ** 2 / variance, a * a / 8 / variance, 0.0]
    inputs = np.random.default_rng(11).uniform(-math.pi, math.pi, (20_000, 3))
    output = (np.sin(inputs[:, 0]) + a * np.sin(inputs[:, 1]) ** 2
              + b * inputs[:, 2] ** 4 * np.sin(inputs[:, 0]))
    # 141 bins of about 142 samples: each index within 0.02 (sampling error and the
    # bins' width; measured +0.009, +0.006, 0 at this seed)
    assert first_order_indices(inputs, output) == pytest.approx(expected, abs=0.02)


def test_a_linear_model_shares_its_variance_by_the_squared_coefficients():
    # Y = sum c_i X_i, X_i independent normal with standard deviations s_i: S_i =
    # c_i^2 s_i^2 / sum_j c_j^2 s_j^2 exactly, and the indices sum to 1 (no interactions).
    coefficients = np.array([3.0, -2.0, 1.0, 0.0])
    deviations = np.array([1.0, 1.0, 2.0, 5.0])
    shares = coefficients**2 * deviations**2
    inputs = np.random.default_rng(3).normal(0.0, deviations, (10_000, 4))
    indices = first_order_indices(inputs, inputs @ coefficients)
    # measured within 0.004 at this seed
    assert indices == pytest.approx(shares / shares.sum(), abs=0.02)
    assert indices[3] < 0.01  # an input the figure ignores explains nothing (0.003 here)
    assert [item.tolerance for item in ranked(("a", "b", "c", "d"), indices)] == [
        "a", "b", "c", "d"]


def test_a_constant_figure_has_no_shares_and_the_bins_follow_the_square_root():
    inputs = np.random.default_rng(0).normal(size=(100, 2))
    assert first_order_indices(inputs, np.full(100, 4.0)).tolist() == [0.0, 0.0]
    assert (bin_count(2000), bin_count(20_000), bin_count(3)) == (45, 141, 2)


@pytest.mark.parametrize("inputs, output, match", [
    (np.zeros((10, 2)), np.zeros(10), "at least 16"),
    (np.zeros((20, 2)), np.zeros(19), "need \\(samples, inputs\\)"),
    (np.full((20, 1), np.nan), np.zeros(20), "finite"),
])
def test_bad_samples_are_refused(inputs, output, match):
    with pytest.raises(ValueError, match=match):
        first_order_indices(inputs, output)
