"""The exact chain as one 2x2 matrix, vectorised over many phasings at once.

In the exact model each joint maps the direction ``(cos a, sin a)`` of its input
yoke to ``(cos a, cos(beta) sin a)`` up to length and a phase is a rotation, so the
chain is ``M = D_n R(phi_(n-1)) ... R(phi_1) D_1`` with ``D_k = diag(1, cos beta_k)``,
and ``RE = |M|_F^2 / (2 det M) - 1``. The column modules use it to scan thousands of
phasings (brute force, spline teeth) in one array operation; the tests check it
against :meth:`sso.ShaftSeries.evaluate`.

The closed form itself lives once, in :mod:`sso._kinematics.hooke_matrix`; this module
gives it the layout the column modules use (``(..., 2, 2)`` arrays, angles along the
last axis). :func:`chain_entries` and :func:`entries_residual_error` use nothing but
``+ - * /``, so the same source builds numpy arrays here and the CasADi graph of the
joint-position NLP (:mod:`sso._column.joint_centres`). RE does not change when ``M``
is scaled, so a rotation may be given scaled (``lambda (cos phi, sin phi)``, any
``lambda != 0``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from sso._kinematics import hooke_matrix


def chain_entries(cos_beta: Sequence[Any], cos_phase: Sequence[Any],
                  sin_phase: Sequence[Any]) -> tuple[Any, Any, Any, Any]:
    """Entries ``(m11, m12, m21, m22)`` of ``M`` in any arithmetic (numpy, CasADi).

    Parameters
    ----------
    cos_beta : sequence
        ``cos beta_k`` of each joint (``n`` entries).
    cos_phase, sin_phase : sequence
        ``cos phi_k`` and ``sin phi_k`` of each phase (``n - 1`` entries each); the
        pair of one phase may be scaled by a common non-zero factor.
    """
    return hooke_matrix.chain_entries(cos_beta, cos_phase, sin_phase)


def entries_residual_error(m11: Any, m12: Any, m21: Any, m22: Any) -> Any:
    """``RE = ((m11 - m22)^2 + (m12 + m21)^2) / (2 det M)`` in any arithmetic."""
    return hooke_matrix.matrix_residual_error((m11, m12, m21, m22))


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
    beta = np.asarray(beta_rad, dtype=float)
    phases = np.asarray(phase_rad, dtype=float)
    batch = np.broadcast_shapes(beta.shape[:-1], phases.shape[:-1])
    entries = hooke_matrix.chain_matrix(np, [beta[..., k] for k in range(beta.shape[-1])],
                                        [phases[..., k] for k in range(phases.shape[-1])])
    m11, m12, m21, m22 = (np.broadcast_to(entry, batch) for entry in entries)
    matrix: np.ndarray = np.stack([np.stack([m11, m12], axis=-1),
                                   np.stack([m21, m22], axis=-1)], axis=-2)
    return matrix


def matrix_residual_error(matrix: np.ndarray) -> np.ndarray:
    """``RE = ((m11 - m22)^2 + (m12 + m21)^2) / (2 det M)`` of each matrix."""
    residual: np.ndarray = entries_residual_error(matrix[..., 0, 0], matrix[..., 0, 1],
                                                  matrix[..., 1, 0], matrix[..., 1, 1])
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
