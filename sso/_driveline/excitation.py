"""A driveline's excitations at its maximum speed, from the exact chain, and their limits.

* inertia excitation, drive: the largest peak angular acceleration of a propshaft over
  a revolution with the gearbox turning at the maximum speed (Spicer judges the driven
  member of a joint whose larger angle is at the drive end);
* inertia excitation, coast: the same with the pinion at that speed;
* torsional excitation: the pinion's peak angular acceleration with the gearbox at that
  speed (what the axle feels).

A single joint (power take-off) has no propshaft: its drive figure is the output
shaft's and its coast figure the gearbox's. Limits: 1,000 and 300 rad/s^2 (Spicer's
torsional analysis calculator, as quoted by NZV8, 29 Oct 2018).

The phase-aware effective angle (second order in the angles) is
``theta_e = sqrt(|sum_k beta_k^2 exp(2 i Phi_k)|)`` with ``Phi_k`` the accumulated
model phase of joint ``k`` (:mod:`sso._column.excitation`, its torsional angle); for a
planar shaft phased 0 or 90 deg it is the signed-square rule
``sqrt(|beta_1^2 - beta_2^2 + beta_3^2 ...|)``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from sso._column.excitation import equivalent_angles
from sso._column.geometry import ColumnGeometry
from sso._driveline.motion import (
    PEAK_SAMPLES,
    RPM_TO_RAD_S,
    accelerations_per_speed2,
    partial_matrices,
    peak_accelerations_per_speed2,
    peak_magnitude,
    ratios_and_slopes,
)

PLANAR_TOLERANCE_DEG = 1e-9
"""Bend-plane angles within this of 0 or 180 deg, and phasings of 0 or 90, are planar."""


@dataclass(frozen=True)
class Excitations:
    """Peak angular accelerations at one speed, rad/s^2.

    Attributes
    ----------
    drive_peak_rad_s2 : tuple of float
        Shafts 1..n (propshafts, then the pinion), gearbox at constant speed.
    coast_peak_rad_s2 : tuple of float
        Shafts 0..n-1 (the gearbox, then the propshafts), pinion at constant speed.
    inertia_drive_rad_s2, inertia_coast_rad_s2, torsional_rad_s2 : float
        See the module notes.
    """

    drive_peak_rad_s2: tuple[float, ...]
    coast_peak_rad_s2: tuple[float, ...]
    inertia_drive_rad_s2: float
    inertia_coast_rad_s2: float
    torsional_rad_s2: float


def excitations(geometry: ColumnGeometry, yoke_phase_deg: tuple[float, ...],
                shaft_speed_rpm: float, samples: int = PEAK_SAMPLES,
                refine: bool = True) -> Excitations:
    """The exact peak accelerations of every shaft and the three excitations.

    ``samples`` per half revolution; ``refine`` the largest by a bounded search (the
    phasing search looks at the samples alone).
    """
    omega_squared = (shaft_speed_rpm * RPM_TO_RAD_S) ** 2
    matrices = partial_matrices(geometry, yoke_phase_deg)
    drive = tuple(omega_squared * peak for peak in peak_accelerations_per_speed2(
        matrices, False, samples, refine))
    coast_shafts = tuple(omega_squared * peak for peak in peak_accelerations_per_speed2(
        matrices, True, samples, refine))

    def gearbox_coast(theta: np.ndarray) -> np.ndarray:
        ratio, slope = ratios_and_slopes(matrices, theta)
        acceleration: np.ndarray = -slope[-1] / ratio[-1] ** 3
        return acceleration

    coast = (omega_squared * peak_magnitude(gearbox_coast, samples, refine), *coast_shafts[:-1])
    propshafts = geometry.joint_count - 1
    if propshafts:
        inertia_drive, inertia_coast = max(drive[:propshafts]), max(coast[1:])
    else:
        inertia_drive, inertia_coast = drive[0], coast[0]
    return Excitations(drive_peak_rad_s2=drive, coast_peak_rad_s2=coast,
                       inertia_drive_rad_s2=inertia_drive, inertia_coast_rad_s2=inertia_coast,
                       torsional_rad_s2=drive[-1])


def effective_angle_deg(geometry: ColumnGeometry, yoke_phase_deg: tuple[float, ...]) -> float:
    """The phase-aware effective angle, deg (module notes)."""
    return equivalent_angles(geometry.series(yoke_phase_deg)).torsional_deg


def signed_square_deg(geometry: ColumnGeometry, yoke_phase_deg: Sequence[float]
                      ) -> float | None:
    """The signed-square rule's effective angle, deg, or None where it does not apply.

    It applies to a planar driveline (every bend-plane angle 0 or 180 deg) with every
    propshaft phased 0 or 90 deg: the sign alternates from joint to joint and flips
    again after each shaft phased 90 deg.
    """
    for gamma in geometry.plane_angle_deg:
        if min(abs(gamma), abs(abs(gamma) - 180.0)) > PLANAR_TOLERANCE_DEG:
            return None
    sign, total = 1.0, 0.0
    for joint, beta in enumerate(geometry.beta_deg):
        if joint > 0:
            phase = float(np.mod(yoke_phase_deg[joint - 1], 180.0))
            if min(phase, 180.0 - phase) <= PLANAR_TOLERANCE_DEG:
                sign = -sign
            elif abs(phase - 90.0) > PLANAR_TOLERANCE_DEG:
                return None
        total += sign * beta**2
    return float(np.sqrt(abs(total)))


def speed_and_acceleration(geometry: ColumnGeometry, yoke_phase_deg: tuple[float, ...],
                           shaft_speed_rpm: float, theta_rad: np.ndarray
                           ) -> tuple[np.ndarray, np.ndarray]:
    """Speed (rpm) and angular acceleration (rad/s^2) of shafts 1..n over ``theta_rad``,
    the gearbox at constant ``shaft_speed_rpm``; each shape ``(n, len(theta))``."""
    matrices = partial_matrices(geometry, yoke_phase_deg)
    ratio, _ = ratios_and_slopes(matrices, theta_rad)
    acceleration = accelerations_per_speed2(matrices, theta_rad, coast=False)
    return ratio * shaft_speed_rpm, acceleration * (shaft_speed_rpm * RPM_TO_RAD_S) ** 2
