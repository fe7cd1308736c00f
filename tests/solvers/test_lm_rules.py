"""The rules' Cholesky factor (plain floats) and the lowest eigenvalue by their bisection
(the CasADi function the Newton blocks call) against numpy's (LAPACK's) factor and
eigenvalues."""

import numpy as np
import pytest

from sso._solvers.lm_kernel import lowest_eigenvalue_function
from sso._solvers.lm_rules import (
    EIGENVALUE_HALVINGS,
    PYTHON,
    cholesky,
    eigenvalue_bracket,
    halve_eigenvalue_bracket,
    solve_factored,
)


@pytest.mark.parametrize("size", [1, 2, 3, 5, 8])
def test_factor_matches_numpy_for_positive_definite_matrices(size):
    rng = np.random.default_rng(size)
    square = rng.normal(size=(size, size))
    matrix = square @ square.T + 0.1 * np.eye(size)
    factor, positive = cholesky(PYTHON, matrix.tolist(), 0.5)
    assert positive
    np.testing.assert_allclose(factor, np.linalg.cholesky(matrix + 0.5 * np.eye(size)),
                               rtol=1e-12, atol=1e-12)
    gradient = rng.normal(size=size)
    np.testing.assert_allclose(solve_factored(PYTHON, factor, gradient.tolist()),
                               np.linalg.solve(matrix + 0.5 * np.eye(size), -gradient),
                               rtol=1e-10, atol=1e-12)


def test_no_factor_exactly_when_the_shifted_matrix_is_not_positive_definite():
    # Eigenvalues 3 and -1: a shift of 0.999 leaves a negative eigenvalue, a shift of
    # 1.001 makes every eigenvalue positive.
    matrix = [[1.0, 2.0], [2.0, 1.0]]
    assert sorted(np.linalg.eigvalsh(np.array(matrix))) == pytest.approx([-1.0, 3.0])
    assert not cholesky(PYTHON, matrix, 0.0)[1]
    assert not cholesky(PYTHON, matrix, 0.999)[1]
    assert cholesky(PYTHON, matrix, 1.001)[1]


@pytest.mark.parametrize("size", [1, 2, 5, 11])
def test_bisected_lowest_eigenvalue_matches_lapack_on_indefinite_matrices(size):
    # Symmetric matrices with a negative eigenvalue, scaled over six decades: the
    # bisection keeps the least shift that gives a factor, so it ends at or below
    # LAPACK's eigenvalue by round-off of the matrix's size.
    rng = np.random.default_rng(100 + size)
    for scale in (1e-3, 1.0, 1e3):
        square = rng.normal(size=(size, size))
        matrix = scale * (square + square.T)
        matrix[0, 0] -= scale * (abs(matrix[0, 0]) / scale + 1.0)
        lowest = np.linalg.eigvalsh(matrix)[0]
        assert lowest < 0.0
        found = float(lowest_eigenvalue_function(size)(matrix.ravel()))
        size_of_matrix = np.max(np.sum(np.abs(matrix), axis=1))
        assert lowest - 1e-13 * size_of_matrix <= found <= lowest + 1e-15 * size_of_matrix
        assert cholesky(PYTHON, matrix.tolist(), -found)[1]


def _bisected_on_floats(matrix):
    """The Newton blocks' bisection (EIGENVALUE_HALVINGS halvings of eigenvalue_bracket) on
    plain floats: minus the least shift found with a factor."""
    low, high = eigenvalue_bracket(PYTHON, matrix)
    for _ in range(EIGENVALUE_HALVINGS):
        low, high = halve_eigenvalue_bracket(PYTHON, matrix, low, high)
    return -high


def test_bisected_lowest_eigenvalue_of_the_zero_matrix_is_zero_from_below():
    # No row sum to bracket it with: the bracket's floor (1e-300) still holds the
    # eigenvalue 0, and the least shift kept puts the answer at or below it.
    for found in (_bisected_on_floats([[0.0, 0.0], [0.0, 0.0]]),
                  float(lowest_eigenvalue_function(2)(np.zeros(4)))):
        assert -1e-300 <= found <= 0.0


def test_bisected_lowest_eigenvalue_of_a_tiny_matrix_is_relative_to_its_size():
    # Entries of 1e-9: the bracket is twice the largest row sum, nothing absolute, so the
    # eigenvalue is found to round-off of the matrix's own size (3e-9).
    matrix = 1e-9 * np.array([[1.0, 2.0], [2.0, 1.0]])
    lowest = np.linalg.eigvalsh(matrix)[0]
    assert lowest == pytest.approx(-1e-9, rel=1e-15)
    for found in (_bisected_on_floats(matrix.tolist()),
                  float(lowest_eigenvalue_function(2)(matrix.ravel()))):
        assert abs(found - lowest) <= 1e-15 * 3e-9
