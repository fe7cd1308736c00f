"""Dense linear algebra on the few-by-few matrices of one design, in plain Python floats.

A numpy call costs a microsecond or more before any arithmetic; a Cholesky factor
of a matrix of a few rows costs less than that written out. Used by the
single-design least-squares solver and the second-order checks.
"""

from __future__ import annotations

import math


def cholesky(matrix: list[list[float]], shift: float) -> list[list[float]] | None:
    """Lower Cholesky factor of ``matrix + shift I``, or None if it is not positive definite.

    Parameters
    ----------
    matrix : list of list of float
        A symmetric square matrix (only its lower triangle is read).
    shift : float
        Added to the diagonal.
    """
    size = len(matrix)
    factor = [[0.0] * size for _ in range(size)]
    for r in range(size):
        for c in range(r + 1):
            total = matrix[r][c] + (shift if r == c else 0.0)
            total -= sum(factor[r][k] * factor[c][k] for k in range(c))
            if r == c:
                if not total > 0.0:
                    return None
                factor[r][r] = math.sqrt(total)
            else:
                factor[r][c] = total / factor[c][c]
    return factor
