"""Slider-crank: exact vector-loop kinematics and the classical series approximation.

The crank pivot is the origin; the piston pin B slides on the line
``y = offset`` on the +x side. The loop is
``crank e^{i theta2} + rod e^{i theta3} = x + i offset``, with x the piston
position. Angles in radians, counter-clockwise from +x; lengths in any
consistent unit; piston velocity and acceleration along +x.
"""

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from sso._kinematics.vector_loop import (
    BoolArray,
    ComplexArray,
    FloatArray,
    circle_horizontal_line_intersection,
    solve_real_pair,
)


@dataclass(frozen=True)
class SliderCrankMotion:
    """Positions, velocities and accelerations of a slider-crank over crank angles.

    Attributes
    ----------
    crank_pin : ndarray of complex
        Crank-rod joint A (length units).
    piston_position : ndarray of float
        x of the piston pin B (length units).
    rod_angle : ndarray of float
        Direction of A -> B (rad).
    rod_angular_velocity : ndarray of float
        Counter-clockwise positive (rad/s).
    rod_angular_accel : ndarray of float
        Counter-clockwise positive (rad/s^2).
    piston_velocity, piston_accel : ndarray of float
        Along +x (length/s, length/s^2).
    assembled : ndarray of bool
        ``False`` where the rod cannot reach the slider line; every other
        field is NaN there.
    """

    crank_pin: ComplexArray
    piston_position: FloatArray
    rod_angle: FloatArray
    rod_angular_velocity: FloatArray
    rod_angular_accel: FloatArray
    piston_velocity: FloatArray
    piston_accel: FloatArray
    assembled: BoolArray


def solve_slider_crank(
    crank: float,
    rod: float,
    offset: float,
    crank_angle: ArrayLike,
    crank_speed: float,
    crank_accel: float,
) -> SliderCrankMotion:
    """Solve the slider-crank loop exactly at each crank angle.

    Parameters
    ----------
    crank, rod : float
        Crank O-A and connecting rod A-B lengths (length units, > 0).
    offset : float
        Height of the slider line above the crank pivot (length units).
    crank_angle : array_like of float
        Crank angles (rad).
    crank_speed : float
        Crank angular velocity (rad/s, counter-clockwise positive).
    crank_accel : float
        Crank angular acceleration (rad/s^2, counter-clockwise positive).

    Returns
    -------
    SliderCrankMotion
        NaN and ``assembled == False`` at the angles where the loop does not close.
    """
    crank_direction: ComplexArray = np.exp(1j * np.asarray(crank_angle, dtype=float))
    crank_pin = crank * crank_direction
    piston, assembled = circle_horizontal_line_intersection(crank_pin, rod, offset)
    rod_vector = piston - crank_pin

    # Derivative of the loop: i w2 A + i w3 (B - A) - v = 0, unknowns w3 and v.
    rod_velocity, piston_velocity = solve_real_pair(
        1j * crank_speed * crank_pin, 1j * rod_vector, -1.0
    )
    rod_accel, piston_accel = solve_real_pair(
        (1j * crank_accel - crank_speed**2) * crank_pin - rod_velocity**2 * rod_vector,
        1j * rod_vector,
        -1.0,
    )
    return SliderCrankMotion(
        crank_pin=crank_pin,
        piston_position=piston.real,
        rod_angle=np.angle(rod_vector),
        rod_angular_velocity=rod_velocity,
        rod_angular_accel=rod_accel,
        piston_velocity=piston_velocity,
        piston_accel=piston_accel,
        assembled=assembled,
    )


def series_piston_motion(
    crank: float,
    rod: float,
    crank_angle: ArrayLike,
    crank_speed: float,
    crank_accel: float,
) -> tuple[FloatArray, FloatArray]:
    """Classical two-term series (Holowenko) piston velocity and acceleration.

    Derivatives of the in-line approximation
    ``x ~ crank cos(theta) + rod - crank^2 sin^2(theta) / (2 rod)``:
    ``v = -crank w (sin theta + crank/(2 rod) sin 2 theta)`` and
    ``a = -crank w^2 (cos theta + crank/rod cos 2 theta)
    - crank alpha (sin theta + crank/(2 rod) sin 2 theta)``.
    Valid for an in-line slider-crank (zero offset) only.

    Parameters
    ----------
    crank, rod : float
        Crank and connecting rod lengths (length units, > 0).
    crank_angle : array_like of float
        Crank angles (rad).
    crank_speed : float
        Crank angular velocity w (rad/s, counter-clockwise positive).
    crank_accel : float
        Crank angular acceleration alpha (rad/s^2, counter-clockwise positive).

    Returns
    -------
    velocity, accel : ndarray of float
        Approximate piston velocity and acceleration along +x
        (length/s, length/s^2).
    """
    angle = np.asarray(crank_angle, dtype=float)
    ratio = crank / rod
    sine_series = np.sin(angle) + 0.5 * ratio * np.sin(2.0 * angle)
    cosine_series = np.cos(angle) + ratio * np.cos(2.0 * angle)
    velocity = -crank * crank_speed * sine_series
    accel = -crank * crank_speed**2 * cosine_series - crank * crank_accel * sine_series
    return velocity, accel
