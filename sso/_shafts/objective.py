"""The residual-error objective: mean square speed-ratio error over a revolution.

``RE = (1/pi) * integral_0^pi (w_out/w_in - 1)^2 dtheta`` (dimensionless), computed
by the rectangle rule on ``samples`` equally spaced input angles in ``[0, 180)`` deg.
The integrand is smooth and 180-deg periodic, so the rule converges geometrically.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from sso._kinematics.hooke import speed_ratio


def angle_grid(samples: int) -> tuple[np.ndarray, np.ndarray]:
    """Cosine and sine of ``samples`` equally spaced input angles in ``[0, pi)``."""
    theta_rad = np.pi * np.arange(samples) / samples
    return np.cos(theta_rad), np.sin(theta_rad)


def squared_ratio_error(
    xp: Any,
    cos_theta: Any,
    sin_theta: Any,
    beta_rad: Sequence[Any],
    phase_rad: Sequence[Any],
    model: str,
) -> Any:
    """``(w_out/w_in - 1)^2`` at each input angle, in the namespace ``xp``."""
    error = speed_ratio(xp, cos_theta, sin_theta, beta_rad, phase_rad, model) - 1
    return error * error


def residual_error(
    beta_rad: Sequence[Any],
    phase_rad: Sequence[Any],
    model: str,
    samples: int,
) -> Any:
    """Residual error RE (dimensionless) of one design, or of many at once.

    Parameters
    ----------
    beta_rad, phase_rad : sequence of float or numpy arrays
        Operating angles and relative phases (rad). Arrays of shape ``(m, 1)``
        evaluate ``m`` designs in one call.
    model : {"exact", "paper"}
        Chain model.
    samples : int
        Number of input angles of the rectangle rule.

    Returns
    -------
    float or numpy.ndarray
        RE of each design.
    """
    cos_theta, sin_theta = angle_grid(samples)
    return np.mean(
        squared_ratio_error(np, cos_theta, sin_theta, beta_rad, phase_rad, model), axis=-1
    )
