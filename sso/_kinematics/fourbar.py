"""Four-bar linkage: closed-form vector-loop kinematics and Grashof class.

The ground pivot of the crank, O_A, is the origin and the ground pivot of the
rocker, O_B, is at ``(ground, 0)``. The crank O_A-A turns the coupler A-B,
which turns the rocker O_B-B. The loop is
``crank e^{i theta2} + coupler e^{i theta3} = ground + rocker e^{i theta4}``.
Angles are in radians, counter-clockwise from +x; lengths in any consistent unit.
"""

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from sso._kinematics.vector_loop import (
    BoolArray,
    ComplexArray,
    FloatArray,
    circle_circle_intersection,
    solve_real_pair,
)

BRANCH_SIDES = {"open": 1, "crossed": -1}
"""Side of the directed line A -> O_B on which B lies: 1 left, -1 right.

With the crank at 0 deg (A between O_A and O_B) "open" puts B above the ground
line, which is the configuration of the four-bar paper.
"""


@dataclass(frozen=True)
class FourBarMotion:
    """Positions, velocities and accelerations of a four-bar over crank angles.

    Attributes
    ----------
    joint_a, joint_b : ndarray of complex
        Crank-coupler joint A and coupler-rocker joint B (length units).
    coupler_angle, rocker_angle : ndarray of float
        Directions of A -> B and O_B -> B (rad).
    transmission_angle : ndarray of float
        Interior angle at B between the coupler and the rocker (rad, 0..pi).
    coupler_angular_velocity, rocker_angular_velocity : ndarray of float
        Counter-clockwise positive (rad/s).
    coupler_angular_accel, rocker_angular_accel : ndarray of float
        Counter-clockwise positive (rad/s^2).
    assembled : ndarray of bool
        ``False`` where the links cannot be joined; every other field is NaN there.
    """

    joint_a: ComplexArray
    joint_b: ComplexArray
    coupler_angle: FloatArray
    rocker_angle: FloatArray
    transmission_angle: FloatArray
    coupler_angular_velocity: FloatArray
    rocker_angular_velocity: FloatArray
    coupler_angular_accel: FloatArray
    rocker_angular_accel: FloatArray
    assembled: BoolArray


def solve_fourbar(
    ground: float,
    crank: float,
    coupler: float,
    rocker: float,
    side: int,
    crank_angle: ArrayLike,
    crank_speed: float,
    crank_accel: float,
) -> FourBarMotion:
    """Solve the four-bar loop at each crank angle.

    Parameters
    ----------
    ground, crank, coupler, rocker : float
        Link lengths O_A-O_B, O_A-A, A-B and O_B-B (length units, > 0).
    side : {1, -1}
        Branch, as in :data:`BRANCH_SIDES`.
    crank_angle : array_like of float
        Crank angles (rad).
    crank_speed : float
        Crank angular velocity (rad/s, counter-clockwise positive).
    crank_accel : float
        Crank angular acceleration (rad/s^2, counter-clockwise positive).

    Returns
    -------
    FourBarMotion
        NaN and ``assembled == False`` at the angles where the loop does not close.
    """
    crank_angle = np.asarray(crank_angle, dtype=float)
    rocker_pivot = complex(ground, 0.0)
    crank_direction: ComplexArray = np.exp(1j * crank_angle)
    joint_a = crank * crank_direction
    joint_b, assembled = circle_circle_intersection(joint_a, coupler, rocker_pivot, rocker, side)
    coupler_vector = joint_b - joint_a
    rocker_vector = joint_b - rocker_pivot

    # Derivative of the loop: i w2 (A - O_A) + i w3 (B - A) - i w4 (B - O_B) = 0.
    coupler_velocity, rocker_velocity = solve_real_pair(
        1j * crank_speed * joint_a, 1j * coupler_vector, -1j * rocker_vector
    )
    coupler_accel, rocker_accel = solve_real_pair(
        (1j * crank_accel - crank_speed**2) * joint_a
        - coupler_velocity**2 * coupler_vector
        + rocker_velocity**2 * rocker_vector,
        1j * coupler_vector,
        -1j * rocker_vector,
    )
    return FourBarMotion(
        joint_a=joint_a,
        joint_b=joint_b,
        coupler_angle=np.angle(coupler_vector),
        rocker_angle=np.angle(rocker_vector),
        transmission_angle=np.abs(np.angle(coupler_vector * np.conj(rocker_vector))),
        coupler_angular_velocity=coupler_velocity,
        rocker_angular_velocity=rocker_velocity,
        coupler_angular_accel=coupler_accel,
        rocker_angular_accel=rocker_accel,
        assembled=assembled,
    )


def swing_angle(ground: float, crank: float, coupler: float, rocker: float) -> float:
    """Angle swept by the rocker of a crank-rocker over one crank revolution.

    The rocker's extreme positions are where crank and coupler are collinear,
    folded (O_A-B = coupler - crank) and extended (O_A-B = coupler + crank).
    The result is meaningful only for a crank-rocker (see :func:`grashof_class`).

    Parameters
    ----------
    ground, crank, coupler, rocker : float
        Link lengths (length units).

    Returns
    -------
    float
        Swing angle (rad).
    """

    def angle_at_rocker_pivot(pivot_to_b: float) -> float:
        return math.acos((ground**2 + rocker**2 - pivot_to_b**2) / (2.0 * ground * rocker))

    return angle_at_rocker_pivot(coupler + crank) - angle_at_rocker_pivot(coupler - crank)


GRASHOF_CLASSES = (
    "crank-rocker",
    "rocker-crank",
    "double-crank",
    "double-rocker",
    "change-point",
    "non-Grashof triple-rocker",
)


def grashof_class(ground: float, crank: float, coupler: float, rocker: float) -> str:
    """Classify a four-bar by Grashof's criterion and its shortest link.

    Parameters
    ----------
    ground, crank, coupler, rocker : float
        Link lengths (length units, > 0).

    Returns
    -------
    str
        One of :data:`GRASHOF_CLASSES`. With ``s + l < p + q`` (s shortest,
        l longest): shortest ground gives "double-crank", shortest crank
        "crank-rocker", shortest rocker "rocker-crank" (the crank only rocks),
        shortest coupler "double-rocker". ``s + l == p + q`` (to a relative
        1e-12) gives "change-point", ``s + l > p + q`` "non-Grashof triple-rocker".
    """
    lengths = {"ground": ground, "crank": crank, "rocker": rocker, "coupler": coupler}
    ordered = sorted(lengths.values())
    excess = (ordered[0] + ordered[3]) - (ordered[1] + ordered[2])
    if abs(excess) <= 1e-12 * ordered[3]:
        return "change-point"
    if excess > 0.0:
        return "non-Grashof triple-rocker"
    # dicts keep insertion order, so equal shortest links resolve ground, crank, rocker.
    shortest = min(lengths, key=lengths.__getitem__)
    return {
        "ground": "double-crank",
        "crank": "crank-rocker",
        "rocker": "rocker-crank",
        "coupler": "double-rocker",
    }[shortest]
