"""Quick-return mechanism: a crank-rocker four-bar driving a slider through a link.

Geometry of the quick-return paper: crank pivot O2 at the origin, rocker
pivot O4 at ``(ground, 0)``, four-bar O2-A-B-O4, and a slider link B-C whose end
C slides on the line ``y = 0`` on the far (+x) side of B. Angles in radians,
counter-clockwise from +x; lengths in any consistent unit.
"""

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from sso._kinematics.fourbar import FourBarMotion, solve_fourbar
from sso._kinematics.vector_loop import (
    BoolArray,
    ComplexArray,
    FloatArray,
    circle_horizontal_line_intersection,
    solve_real_pair,
)


@dataclass(frozen=True)
class QuickReturnMotion:
    """Motion of the quick-return mechanism over crank angles.

    Attributes
    ----------
    linkage : FourBarMotion
        The driving four-bar O2-A-B-O4 (A, B, coupler and rocker motion).
    joint_b_velocity, joint_b_accel : ndarray of complex
        Velocity and acceleration of B (length/s, length/s^2).
    joint_c : ndarray of complex
        Slider C (length units, on y = 0).
    slider_link_angle : ndarray of float
        Direction of B -> C (rad).
    slider_link_angular_velocity, slider_link_angular_accel : ndarray of float
        Counter-clockwise positive (rad/s, rad/s^2).
    slider_velocity, slider_accel : ndarray of float
        Velocity and acceleration of C along +x (length/s, length/s^2).
    assembled : ndarray of bool
        ``False`` where the four-bar does not close or the slider link cannot
        reach the slider line; every other field is NaN there.
    """

    linkage: FourBarMotion
    joint_b_velocity: ComplexArray
    joint_b_accel: ComplexArray
    joint_c: ComplexArray
    slider_link_angle: FloatArray
    slider_link_angular_velocity: FloatArray
    slider_link_angular_accel: FloatArray
    slider_velocity: FloatArray
    slider_accel: FloatArray
    assembled: BoolArray


def solve_quick_return(
    ground: float,
    crank: float,
    coupler: float,
    rocker: float,
    slider_link: float,
    side: int,
    crank_angle: ArrayLike,
    crank_speed: float,
    crank_accel: float,
) -> QuickReturnMotion:
    """Solve the quick-return mechanism at each crank angle.

    Parameters
    ----------
    ground, crank, coupler, rocker : float
        Four-bar link lengths O2-O4, O2-A, A-B and O4-B (length units, > 0).
    slider_link : float
        Length B-C (length units, > 0).
    side : {1, -1}
        Four-bar branch, as in :data:`sso._kinematics.fourbar.BRANCH_SIDES`.
    crank_angle : array_like of float
        Crank angles (rad).
    crank_speed : float
        Crank angular velocity (rad/s, counter-clockwise positive).
    crank_accel : float
        Crank angular acceleration (rad/s^2, counter-clockwise positive).

    Returns
    -------
    QuickReturnMotion
        NaN and ``assembled == False`` at the angles where it does not close.
    """
    linkage = solve_fourbar(
        ground, crank, coupler, rocker, side, crank_angle, crank_speed, crank_accel
    )
    rocker_vector = linkage.joint_b - complex(ground, 0.0)
    joint_b_velocity = 1j * linkage.rocker_angular_velocity * rocker_vector
    joint_b_accel = (
        1j * linkage.rocker_angular_accel - linkage.rocker_angular_velocity**2
    ) * rocker_vector
    joint_c, reaches_line = circle_horizontal_line_intersection(linkage.joint_b, slider_link, 0.0)
    link_vector = joint_c - linkage.joint_b

    # Derivative of B + (C - B) = C: v_B + i w5 (C - B) - v_C = 0, unknowns w5 and v_C.
    link_velocity, slider_velocity = solve_real_pair(joint_b_velocity, 1j * link_vector, -1.0)
    link_accel, slider_accel = solve_real_pair(
        joint_b_accel - link_velocity**2 * link_vector, 1j * link_vector, -1.0
    )
    return QuickReturnMotion(
        linkage=linkage,
        joint_b_velocity=joint_b_velocity,
        joint_b_accel=joint_b_accel,
        joint_c=joint_c,
        slider_link_angle=np.angle(link_vector),
        slider_link_angular_velocity=link_velocity,
        slider_link_angular_accel=link_accel,
        slider_velocity=slider_velocity,
        slider_accel=slider_accel,
        assembled=linkage.assembled & reaches_line,
    )
