"""The figures of many built columns at once: RE and the steering figures from lock to lock.

One row per built column, from its operating angles and model phases (rad): RE of
its chain matrix (:mod:`sso._column.chain_matrix`), and the exact extremes over the
steering range (:func:`sso._column.steering_range.range_extremes`): the speed-ratio
and output-torque fluctuations (peak to peak, percent) and the largest
``|transmission error|`` (deg). The tolerance study evaluates its chunks with it, and
a column run the sample of its ``[tolerances]``.
"""

from __future__ import annotations

import numpy as np

from sso._column.chain_matrix import chain_matrix, matrix_residual_error
from sso._column.steering_range import range_extremes

BUILT_FIGURES = ("residual_error", "speed_fluctuation_percent", "torque_fluctuation_percent",
                 "largest_transmission_error_deg")


def built_column_figures(beta_rad: np.ndarray, phase_rad: np.ndarray, straight_ahead_deg: float,
                         lock_deg: float) -> np.ndarray:
    """The figures of :data:`BUILT_FIGURES` of every built column, shape ``(4, samples)``.

    Parameters
    ----------
    beta_rad, phase_rad : numpy.ndarray
        Operating angles ``(samples, n)`` and model phases ``(samples, n - 1)``, rad.
    straight_ahead_deg, lock_deg : float
        The steering range (as :func:`sso.steering_range` takes it, checked there), deg.
    """
    matrices = chain_matrix(beta_rad, phase_rad)
    figures = np.empty((len(BUILT_FIGURES), len(matrices)))
    figures[0] = matrix_residual_error(matrices)
    for index, matrix in enumerate(matrices):
        ratio_low, ratio_high, error_low, error_high = range_extremes(
            matrix, straight_ahead_deg, lock_deg)
        figures[1, index] = 100.0 * (ratio_high - ratio_low)
        figures[2, index] = 100.0 * (1.0 / ratio_low - 1.0 / ratio_high)
        figures[3, index] = max(-error_low, error_high)
    return figures


def limited_figures(beta_deg: np.ndarray, figures: np.ndarray) -> dict[str, np.ndarray]:
    """The figures limits judge, by name (:data:`sso._column.yields.COLUMN_LIMITS`), from
    the operating angles ``(samples, n)`` deg and :func:`built_column_figures`' array."""
    return {**dict(zip(BUILT_FIGURES, figures, strict=True)),
            "largest_operating_angle_deg": np.max(beta_deg, axis=1)}
