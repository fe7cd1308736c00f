"""Every shaft's speed and angular acceleration over a revolution, from the exact chain.

The chain is the column's (:mod:`sso._kinematics.hooke_matrix`): after joint ``k`` the
partial matrix ``M_k = D_k R(phi_(k-1)) ... D_1`` gives shaft ``k``'s speed ratio to the
gearbox, ``r_k(theta) = det M_k / |M_k v|^2`` with ``v = (cos theta, sin theta)``, and
its derivative ``r_k' = -det M_k 2 (M_k v).(M_k v') / |M_k v|^4`` in closed form.

* drive: the gearbox turns at a constant ``w``; shaft ``k`` accelerates at
  ``w^2 r_k'(theta)``;
* coast: the pinion turns at a constant ``w``; shaft ``k`` turns at
  ``w r_k / r_n`` and accelerates at ``w^2 (r_k / r_n)' / r_n``.

``theta`` is the gearbox output shaft's angle; at ``theta = 0`` the gearbox yoke's
cross arm lies along the normal of joint 1's plane (``u_0 x u_1``), where the first
joint's speed ratio is least (``cos beta_1``), and it turns right-handed about the
gearbox axis ``u_0`` (front to rear). The peaks are the largest magnitudes over a
revolution: sampled, then refined by a bounded scalar search around the best sample.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from sso._column.chain_matrix import chain_matrix
from sso._column.geometry import ColumnGeometry

RPM_TO_RAD_S = 2.0 * np.pi / 60.0
PEAK_SAMPLES = 2048
"""Samples of a half revolution (every figure repeats twice per revolution) before refining."""


def partial_matrices(geometry: ColumnGeometry, yoke_phase_deg: tuple[float, ...]) -> np.ndarray:
    """``M_1 .. M_n`` (shape ``(n, 2, 2)``): the chain from the gearbox to each shaft."""
    beta_rad = np.radians(geometry.beta_deg)
    phase_rad = np.radians(geometry.phase_deg_from_yoke(yoke_phase_deg))
    return np.stack([chain_matrix(beta_rad[:k], phase_rad[:k - 1])
                     for k in range(1, len(beta_rad) + 1)])


def ratios_and_slopes(matrices: np.ndarray, theta_rad: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray]:
    """``r_k(theta)`` and ``r_k'(theta)``, shape ``(n, len(theta))``."""
    direction = np.stack([np.cos(theta_rad), np.sin(theta_rad)])
    turned = np.stack([-np.sin(theta_rad), np.cos(theta_rad)])
    image = np.einsum("kij,jt->kit", matrices, direction)
    image_turned = np.einsum("kij,jt->kit", matrices, turned)
    determinant = np.linalg.det(matrices)[:, None]
    squared = np.sum(image * image, axis=1)
    ratio = determinant / squared
    slope = -determinant * 2.0 * np.sum(image * image_turned, axis=1) / squared**2
    return ratio, slope


def accelerations_per_speed2(matrices: np.ndarray, theta_rad: np.ndarray,
                             coast: bool) -> np.ndarray:
    """Angular acceleration of each shaft 1..n divided by the constant shaft's ``w^2``.

    Parameters
    ----------
    matrices : numpy.ndarray
        :func:`partial_matrices`.
    theta_rad : numpy.ndarray
        Gearbox angles, rad.
    coast : bool
        False: the gearbox turns at constant speed (drive). True: the pinion does.
    """
    ratio, slope = ratios_and_slopes(matrices, theta_rad)
    if not coast:
        return slope
    last, last_slope = ratio[-1], slope[-1]
    relative_slope = (slope * last - ratio * last_slope) / last**2
    accelerations: np.ndarray = relative_slope / last
    return accelerations


def speeds_per_speed(matrices: np.ndarray, theta_rad: np.ndarray, coast: bool) -> np.ndarray:
    """Speed of each shaft 1..n divided by the constant shaft's speed."""
    ratio, _ = ratios_and_slopes(matrices, theta_rad)
    speeds: np.ndarray = ratio / ratio[-1] if coast else ratio
    return speeds


def peak_magnitude(function: Callable[[np.ndarray], np.ndarray],
                   samples: int = PEAK_SAMPLES, refine: bool = True) -> float:
    """Largest ``|function(theta)|`` over a revolution of a function of period pi.

    Without ``refine`` the largest sample (the phasing search's quick look).
    """
    theta = np.pi * np.arange(samples) / samples
    values = np.abs(function(theta))
    best = int(np.argmax(values))
    if not refine:
        return float(values[best])
    from scipy.optimize import minimize_scalar

    step = np.pi / samples
    found = minimize_scalar(lambda angle: -float(np.abs(function(np.array([angle]))[0])),
                            bounds=(theta[best] - step, theta[best] + step),
                            method="bounded", options={"xatol": 1e-12})
    return max(float(values[best]), -float(found.fun))


def peak_accelerations_per_speed2(matrices: np.ndarray, coast: bool,
                                  samples: int = PEAK_SAMPLES,
                                  refine: bool = True) -> tuple[float, ...]:
    """Peak angular acceleration of each shaft 1..n over a revolution per ``w^2``
    (rad/s^2 per (rad/s)^2)."""
    peaks = []
    for shaft in range(matrices.shape[0]):
        def acceleration(theta: np.ndarray, shaft: int = shaft) -> np.ndarray:
            values: np.ndarray = accelerations_per_speed2(matrices, theta, coast)[shaft]
            return values

        peaks.append(peak_magnitude(acceleration, samples, refine))
    return tuple(peaks)


def pin_axes(geometry: ColumnGeometry, yoke_phase_deg: tuple[float, ...],
             theta_rad: float) -> tuple[np.ndarray, np.ndarray]:
    """Pin axes of every cross at gearbox angle ``theta``: ``p_k`` (driving yoke's, on
    shaft ``k - 1``) and ``q_k`` (driven yoke's, on shaft ``k``), each shape ``(n, 3)``.

    ``p_1`` is the gearbox yoke's pin axis (see the module notes for ``theta = 0``);
    ``q_k`` is normal to ``u_k`` and to ``p_k`` (the cross's arms are square), and
    shaft ``k``'s yoke at joint ``k + 1`` holds ``q_k`` turned by its yoke phasing
    ``delta_k`` about ``u_k`` (the column's convention).
    """
    directions = geometry.shaft_directions
    normal = geometry.bend_normals[0]
    driving = np.cos(theta_rad) * normal + np.sin(theta_rad) * np.cross(directions[0], normal)
    driving_pins: list[np.ndarray] = []
    driven_pins: list[np.ndarray] = []
    for joint in range(geometry.joint_count):
        if joint > 0:
            axis = directions[joint]
            previous = driven_pins[-1]
            angle = np.radians(yoke_phase_deg[joint - 1])
            driving = (np.cos(angle) * previous + np.sin(angle) * np.cross(axis, previous))
        driven = np.cross(driving, directions[joint + 1])
        driven = driven / np.linalg.norm(driven)
        driving_pins.append(driving)
        driven_pins.append(driven)
    return np.array(driving_pins), np.array(driven_pins)
