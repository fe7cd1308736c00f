"""The plain-float Cholesky factor against numpy's (LAPACK's) factor and eigenvalues."""

import numpy as np
import pytest

from sso.solvers.small_matrices import cholesky


@pytest.mark.parametrize("size", [1, 2, 3, 5, 8])
def test_factor_matches_numpy_for_positive_definite_matrices(size):
    rng = np.random.default_rng(size)
    square = rng.normal(size=(size, size))
    matrix = square @ square.T + 0.1 * np.eye(size)
    factor = cholesky(matrix.tolist(), 0.5)
    np.testing.assert_allclose(factor, np.linalg.cholesky(matrix + 0.5 * np.eye(size)),
                               rtol=1e-12, atol=1e-12)


def test_no_factor_exactly_when_the_shifted_matrix_is_not_positive_definite():
    # Eigenvalues 3 and -1: a shift of 0.999 leaves a negative eigenvalue, a shift of
    # 1.001 makes every eigenvalue positive.
    matrix = [[1.0, 2.0], [2.0, 1.0]]
    assert sorted(np.linalg.eigvalsh(np.array(matrix))) == pytest.approx([-1.0, 3.0])
    assert cholesky(matrix, 0.0) is None
    assert cholesky(matrix, 0.999) is None
    assert cholesky(matrix, 1.001) is not None
