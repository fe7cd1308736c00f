"""Finite-difference check of velocities and accelerations over a crank-angle grid.

A crank turning at speed w with acceleration alpha sweeps the grid; a quantity
f that is w^k times a function of the crank angle theta (k = 0 for positions
and angles, 1 for velocities) has the time derivative
``df/dt = w df/dtheta + k alpha f / w``.
"""

import numpy as np

RTOL = 1e-6
"""Tolerance relative to the largest magnitude of the derivative; central
differences on a 0.01 deg grid are good to about 1e-8 of it."""


def assert_time_derivative(
    derivative: np.ndarray,
    quantity: np.ndarray,
    step_rad: float,
    crank_speed: float,
    crank_accel: float,
    speed_power: int,
) -> None:
    """Assert ``derivative`` is the time derivative of ``quantity`` at interior points."""
    differenced = crank_speed * np.gradient(quantity, step_rad)
    differenced += speed_power * crank_accel * quantity / crank_speed
    tolerance = RTOL * np.max(np.abs(derivative))
    np.testing.assert_allclose(derivative[1:-1], differenced[1:-1], rtol=0, atol=tolerance)
