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
        row, given = factor[r], matrix[r]
        for c in range(r):
            other = factor[c]
            total = given[c]
            for k in range(c):
                total -= row[k] * other[k]
            row[c] = total / other[c]
        total = given[r] + shift
        for k in range(r):
            total -= row[k] * row[k]
        if not total > 0.0:
            return None
        row[r] = math.sqrt(total)
    return factor
