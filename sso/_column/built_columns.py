"""Operating and bend-plane angles of many built columns at once (a tolerance sample).

The same definitions as :class:`sso.ColumnGeometry` (``docs/column.md``), on arrays of
shape ``(samples, n + 2, 3)``: ``beta_k`` is the angle between the shaft directions
``u_(k-1)`` and ``u_k``, ``n_k`` their unit normal, and ``gamma_k`` the signed angle
from ``n_k`` to ``n_(k+1)`` about ``u_k``. A sample whose joint is nearly straight (its
bend plane borrowed, :mod:`sso._column.geometry`) or that is no column at all is
built by :class:`sso.ColumnGeometry` itself, which names what is wrong.
"""

from __future__ import annotations

import numpy as np

from sso._column.geometry import ROUND_OFF_SINE, ColumnGeometry
from sso._validation import unresolvable_chains

NEARLY_STRAIGHT_SINE = 1e-9
"""A joint's ``|u_(k-1) x u_k|`` at or below this is left to :class:`ColumnGeometry`."""
LARGEST_ARRAY_BETA_DEG = 89.0
"""A sample with an operating angle above this is left to :class:`ColumnGeometry` (its
checks of the 90 deg limit and of the chain's conditioning; below it, the conditioning
is checked here, and a sample beyond it goes to :class:`ColumnGeometry` too)."""


def built_angles(points_mm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Operating angles ``(samples, n)`` and bend-plane angles ``(samples, n - 1)``, deg.

    Parameters
    ----------
    points_mm : numpy.ndarray, shape (samples, n + 2, 3)
        The hardpoints of each built column, mm.

    Raises
    ------
    ValueError
        ``"sample i: ..."`` with :class:`ColumnGeometry`'s reason, for a sample that
        is not a column.
    """
    points = np.asarray(points_mm, dtype=float)
    differences = np.diff(points, axis=1)
    lengths = np.linalg.norm(differences, axis=2, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        directions = differences / lengths
        crossed = np.cross(directions[:, :-1], directions[:, 1:])
        sines = np.linalg.norm(crossed, axis=2)
        cosines = np.sum(directions[:, :-1] * directions[:, 1:], axis=2)
        beta = np.degrees(np.arctan2(sines, cosines))
        normals = crossed / sines[..., None]
        axis = directions[:, 1:-1]
        first, second = normals[:, :-1], normals[:, 1:]
        plane_sines = np.sum(np.cross(first, second) * axis, axis=2)
        plane_cosines = np.sum(first * second, axis=2)
    plane_sines = np.where((plane_cosines < 0.0) & (np.abs(plane_sines) <= ROUND_OFF_SINE),
                           0.0, plane_sines)
    gamma = np.degrees(np.arctan2(plane_sines, plane_cosines))
    regular = (np.all(np.isfinite(points.reshape(len(points), -1)), axis=1)
               & np.all(sines > NEARLY_STRAIGHT_SINE, axis=1)
               & np.all(beta <= LARGEST_ARRAY_BETA_DEG, axis=1))
    # Regular angles may still be too many, too steep, for float64 to resolve RE.
    irregular = ~regular | unresolvable_chains(np.where(regular[:, None], beta, 0.0))
    for index in np.flatnonzero(irregular).tolist():
        try:
            built = ColumnGeometry(points[index])
        except ValueError as error:
            raise ValueError(f"sample {index}: {error}") from None
        beta[index] = built.beta_deg
        gamma[index] = built.plane_angle_deg
    return beta, gamma
