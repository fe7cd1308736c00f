"""Secondary couples of the joints and the radial bearing loads they cause, over a revolution.

The model (stated in the issue and in ``docs/concepts/driveline-conventions.md``):
quasi-static, torque only (no gravity, inertia or friction). A cross carries a moment
only along its normal ``N_k = p_k x q_k / |p_k x q_k|`` (the pins turn freely about
their own axes), so joint ``k`` passes the moment ``m_k N_k`` with
``m_k N_k . u_(k-1) = T_(k-1)`` (the torque of the shaft ahead); the torque behind is
``T_k = m_k N_k . u_k`` and the rest of ``m_k N_k`` bends the shafts: the secondary
couple. Forces through the crosses follow from each shaft's equilibrium:

* the rearmost propshaft holds the slip spline, so it carries no axial force and has
  no bearing: the force through both its joints is ``F = ((M_a - M_b) x u) / L``;
* a propshaft with a centre bearing (radial only, ``c`` ahead of its rear joint)
  takes the force at its rear joint from the shaft behind; its bearing takes
  ``R = (W x u) / (L - c)`` with ``W = M_b - M_a + L u x F_rear``, and its front joint
  ``F_front = F_rear - R``;
* the gearbox output shaft: radial bearings ``b`` (near, B) and ``a + b`` (far, A) ahead
  of the first joint (Dana's notation); the pinion: ``e`` (near, E) and ``e + f``
  (far, F) behind the last joint. Each pair takes its shaft's bending moment and the
  radial part of the force through its joint.
* a driveline of one joint (a power take-off) has no spline shaft: no force passes
  the joint, each side's bearings take its couple alone.

Every propshaft but the rearmost needs a centre bearing (else the forces are not
determined by statics).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from sso._column.geometry import ColumnGeometry
from sso._driveline.motion import pin_axes


@dataclass(frozen=True)
class BearingGeometry:
    """Where the bearings are, mm (Dana's notation).

    Attributes
    ----------
    gearbox_a_mm, gearbox_b_mm : float
        Gearbox output bearings: near (B) at ``b`` and far (A) at ``a + b`` ahead of
        the first joint.
    pinion_e_mm, pinion_f_mm : float
        Pinion bearings: near (E) at ``e`` and far (F) at ``e + f`` behind the last.
    centre_bearing_mm : tuple of float
        For each propshaft but the rearmost, its centre bearing's distance ahead of
        its rear joint centre, mm.
    """

    gearbox_a_mm: float
    gearbox_b_mm: float
    pinion_e_mm: float
    pinion_f_mm: float
    centre_bearing_mm: tuple[float, ...]


@dataclass(frozen=True)
class LoadState:
    """Moments and forces at one gearbox angle (N m, N; vectors in the vehicle axes).

    Attributes
    ----------
    joint_moment_n_m : numpy.ndarray, shape (n, 3)
        Moment each joint passes rearward, ``m_k N_k``.
    bending_ahead_n_m, bending_behind_n_m : numpy.ndarray, shape (n,)
        The secondary couple of each joint on the shaft ahead of it and behind it:
        the magnitude of the part of ``m_k N_k`` normal to that shaft.
    shaft_torque_n_m : numpy.ndarray, shape (n + 1,)
        Torque of each shaft from the gearbox to the pinion.
    joint_force_n : numpy.ndarray, shape (n, 3)
        Force through each cross, from the shaft ahead to the shaft behind.
    bearing_force_n : dict of str to numpy.ndarray
        Radial force on each bearing (the bearing on the shaft): ``"gearbox far (A)"``,
        ``"gearbox near (B)"``, ``"centre bearing k"``, ``"pinion near (E)"``,
        ``"pinion far (F)"``.
    """

    joint_moment_n_m: np.ndarray
    bending_ahead_n_m: np.ndarray
    bending_behind_n_m: np.ndarray
    shaft_torque_n_m: np.ndarray
    joint_force_n: np.ndarray
    bearing_force_n: dict[str, np.ndarray]


def bearing_names(joints: int) -> tuple[str, ...]:
    """The bearings of a driveline of ``joints`` joints, gearbox to pinion."""
    centre = tuple(f"centre bearing {k}" for k in range(1, joints - 1))
    return ("gearbox far (A)", "gearbox near (B)", *centre, "pinion near (E)", "pinion far (F)")


def load_state(geometry: ColumnGeometry, yoke_phase_deg: tuple[float, ...],
               bearings: BearingGeometry, torque_n_m: float, theta_rad: float) -> LoadState:
    """Moments and forces of the whole driveline at gearbox angle ``theta_rad``.

    ``torque_n_m`` is the gearbox output torque, positive driving (right-handed about
    the gearbox axis, front to rear).
    """
    points = np.asarray(geometry.points_mm) / 1000.0
    directions = geometry.shaft_directions
    joints = geometry.joint_count
    driving, driven = pin_axes(geometry, yoke_phase_deg, theta_rad)
    torques = [torque_n_m]
    moments = []
    for joint in range(joints):
        normal = np.cross(driving[joint], driven[joint])
        normal /= np.linalg.norm(normal)
        magnitude = torques[-1] / float(np.dot(normal, directions[joint]))
        moments.append(magnitude * normal)
        torques.append(magnitude * float(np.dot(normal, directions[joint + 1])))
    forces = np.zeros((joints, 3))
    bearing_force: dict[str, np.ndarray] = {}
    if joints > 1:
        rear = joints - 1  # the rearmost propshaft, shaft index joints - 1
        axis = directions[rear]
        length = float(np.linalg.norm(points[rear + 1] - points[rear]))
        force = np.cross(moments[rear - 1] - moments[rear], axis) / length
        forces[rear] = forces[rear - 1] = force
        for shaft in range(rear - 1, 0, -1):
            axis = directions[shaft]
            length = float(np.linalg.norm(points[shaft + 1] - points[shaft]))
            offset = bearings.centre_bearing_mm[shaft - 1] / 1000.0
            imbalance = moments[shaft] - moments[shaft - 1] + length * np.cross(axis, forces[shaft])
            reaction = np.cross(imbalance, axis) / (length - offset)
            forces[shaft - 1] = forces[shaft] - reaction
            bearing_force[f"centre bearing {shaft}"] = reaction
    bearing_force.update(_end_bearings(directions[0], moments[0], torque_n_m, forces[0],
                                       bearings.gearbox_a_mm / 1000.0,
                                       bearings.gearbox_b_mm / 1000.0, gearbox=True))
    bearing_force.update(_end_bearings(directions[-1], moments[-1], torques[-1], forces[-1],
                                       bearings.pinion_f_mm / 1000.0,
                                       bearings.pinion_e_mm / 1000.0, gearbox=False))
    bending_ahead = np.array([_normal_part(moments[k], directions[k]) for k in range(joints)])
    bending_behind = np.array([_normal_part(moments[k], directions[k + 1])
                               for k in range(joints)])
    ordered = {name: bearing_force[name] for name in bearing_names(joints)}
    return LoadState(joint_moment_n_m=np.array(moments), bending_ahead_n_m=bending_ahead,
                     bending_behind_n_m=bending_behind, shaft_torque_n_m=np.array(torques),
                     joint_force_n=forces, bearing_force_n=ordered)


def _normal_part(vector: np.ndarray, axis: np.ndarray) -> float:
    return float(np.linalg.norm(vector - np.dot(vector, axis) * axis))


def _end_bearings(axis: np.ndarray, moment: np.ndarray, torque: float, force: np.ndarray,
                  spacing_m: float, near_m: float, *, gearbox: bool) -> dict[str, np.ndarray]:
    """Radial loads on the two bearings of the gearbox output shaft or of the pinion.

    Gearbox shaft: the joint's moment ``moment`` leaves it at the joint (``-moment`` on
    the shaft), the force through the joint ``force`` likewise (``-force``), the gearbox
    drives it with ``torque`` about ``axis``. Pinion: the joint's moment and force act on
    it (``+moment``, ``+force``), the gear mesh holds ``torque``. Moments are taken about
    the near bearing; the far one is ``spacing_m`` further from the joint.
    """
    sign = -1.0 if gearbox else 1.0
    radial_force = sign * (force - np.dot(force, axis) * axis)
    couple = sign * (moment - torque * axis)
    # Lever of the joint from the near bearing and of the far bearing, signed along axis.
    joint_lever = near_m if gearbox else -near_m
    far_lever = -spacing_m if gearbox else spacing_m
    # couple + joint_lever u x radial_force + far_lever u x far = 0 (normal to the axis),
    # and u x (V x u) = V for V normal to u.
    imbalance = couple + joint_lever * np.cross(axis, radial_force)
    far = -np.cross(imbalance, axis) / far_lever
    near = -radial_force - far
    if gearbox:
        return {"gearbox far (A)": far, "gearbox near (B)": near}
    return {"pinion near (E)": near, "pinion far (F)": far}
