"""The exact chain as one 2x2 matrix, vectorised over many phasings at once.

In the exact model each joint maps the direction ``(cos a, sin a)`` of its input
yoke to ``(cos a, cos(beta) sin a)`` up to length and a phase is a rotation, so the
chain is ``M = D_n R(phi_(n-1)) ... R(phi_1) D_1`` with ``D_k = diag(1, cos beta_k)``,
and ``RE = |M|_F^2 / (2 det M) - 1``. The column modules use it to scan thousands of
phasings (brute force, spline teeth) in one array operation; the tests check it
against :meth:`sso.ShaftSeries.evaluate`.
"""

from __future__ import annotations

from typing import Any

import numpy as np


def chain_matrix(beta_rad: Any, phase_rad: Any) -> np.ndarray:
    """``M`` for each row of angles.

    Parameters
    ----------
    beta_rad : array_like, shape (..., n)
        Operating angles, rad.
    phase_rad : array_like, shape (..., n - 1)
        Relative phases, rad. Leading axes of both are batch axes and broadcast.

    Returns
    -------
    numpy.ndarray, shape (..., 2, 2)
    """
    cosines = np.cos(np.asarray(beta_rad, dtype=float))
    phases = np.asarray(phase_rad, dtype=float)
    batch = np.broadcast_shapes(cosines.shape[:-1], phases.shape[:-1])
    matrix = np.zeros((*batch, 2, 2))
    matrix[..., 0, 0] = 1.0
    matrix[..., 1, 1] = cosines[..., 0]
    for k in range(1, cosines.shape[-1]):
        cos_phase = np.cos(phases[..., k - 1])[..., None]
        sin_phase = np.sin(phases[..., k - 1])[..., None]
        top = cos_phase * matrix[..., 0, :] - sin_phase * matrix[..., 1, :]
        bottom = sin_phase * matrix[..., 0, :] + cos_phase * matrix[..., 1, :]
        matrix[..., 0, :] = top
        matrix[..., 1, :] = cosines[..., k, None] * bottom
    return matrix


def matrix_residual_error(matrix: np.ndarray) -> np.ndarray:
    """``RE = ((m11 - m22)^2 + (m12 + m21)^2) / (2 det M)`` of each matrix."""
    m11, m12 = matrix[..., 0, 0], matrix[..., 0, 1]
    m21, m22 = matrix[..., 1, 0], matrix[..., 1, 1]
    residual: np.ndarray = ((m11 - m22) ** 2 + (m12 + m21) ** 2) / (2.0 * (m11 * m22 - m12 * m21))
    return residual


def residual_error(beta_rad: Any, phase_rad: Any) -> np.ndarray:
    """Residual error of the exact model for each row of phases (dimensionless)."""
    return matrix_residual_error(chain_matrix(beta_rad, phase_rad))


def distortion_distance(matrix: np.ndarray) -> np.ndarray:
    """``ln(s_max / s_min)`` of each matrix: 0 for a scaled rotation.

    It is the distance the chain moves the base point of the hyperbolic plane, so
    ``RE = cosh(distance) - 1`` and joints add at most their own ``-ln cos beta``.
    """
    distance: np.ndarray = np.arccosh(1.0 + np.maximum(matrix_residual_error(matrix), 0.0))
    return distance
