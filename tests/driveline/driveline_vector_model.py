"""An independent 3D model of a driveline for the tests: rotation matrices, each cross's
constraint solved numerically, and the statics of every body solved as one linear system.

Nothing here calls the package's chain: the shafts are rigid bodies turning about their
axes ``u_k`` (Rodrigues' rotation), each yoke holds a pin at a fixed angle on its shaft,
and the angle of shaft ``k`` at each gearbox angle is the root of the cross's condition
``p_k . q_k = 0`` (the two pins of a cross are square), found by Brent's method next to
the previous angle. Speeds and accelerations come from the spectral derivative of the
periodic part of each shaft's angle (exact for a band-limited function, and these are
analytic, so the error falls geometrically with the samples).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq


def rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues' rotation matrix about a unit axis."""
    cross = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]],
                      [-axis[1], axis[0], 0.0]])
    return np.eye(3) + np.sin(angle) * cross + (1.0 - np.cos(angle)) * cross @ cross


def unit(vector: np.ndarray) -> np.ndarray:
    return vector / np.linalg.norm(vector)


class VectorDriveline:
    """Shafts from points (mm), yoke phasings (deg): the conventions of the docs page
    ``docs/concepts/driveline-conventions.md`` (gearbox yoke's pin along ``u_0 x u_1`` at
    gearbox angle 0; shaft ``k``'s rear yoke pin turned by ``delta_k`` about ``u_k`` from its
    front yoke's pin)."""

    def __init__(self, points_mm: list[list[float]], yoke_phase_deg: list[float]) -> None:
        self.points = np.asarray(points_mm, dtype=float)
        self.axes = [unit(b - a) for a, b in zip(self.points[:-1], self.points[1:], strict=True)]
        self.joints = len(self.axes) - 1
        self.phases = np.radians(yoke_phase_deg)
        # Reference pin of the front yoke of shaft k (any vector normal to u_k).
        self.reference = []
        for axis in self.axes:
            trial = np.array([0.0, 0.0, 1.0]) if abs(axis[2]) < 0.9 else np.array([1.0, 0, 0])
            self.reference.append(unit(trial - np.dot(trial, axis) * axis))
        self.gearbox_pin = unit(np.cross(self.axes[0], self.axes[1]))

    def joint_angles_deg(self) -> np.ndarray:
        return np.array([np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b)), np.dot(a, b)))
                         for a, b in zip(self.axes[:-1], self.axes[1:], strict=True)])

    def pins(self, theta: float, shaft_angles: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
        """``(p_k, q_k)`` of every cross at the given angles."""
        crosses = []
        driving = rotation(self.axes[0], theta) @ self.gearbox_pin
        for k in range(1, self.joints + 1):
            axis = self.axes[k]
            driven = rotation(axis, shaft_angles[k]) @ self.reference[k]
            crosses.append((driving, driven))
            if k < self.joints:
                driving = rotation(axis, shaft_angles[k] + self.phases[k - 1]) @ self.reference[k]
        return crosses

    def shaft_angles(self, theta: np.ndarray) -> np.ndarray:
        """Angle of every shaft (row 0 the gearbox, = theta), continuous in theta."""
        angles = np.zeros((self.joints + 1, len(theta)))
        angles[0] = theta
        previous = np.zeros(self.joints + 1)
        for index, gearbox in enumerate(theta):
            current = np.zeros(self.joints + 1)
            current[0] = gearbox
            driving = rotation(self.axes[0], gearbox) @ self.gearbox_pin
            for k in range(1, self.joints + 1):
                axis = self.axes[k]

                def condition(angle: float, axis: np.ndarray = axis, k: int = k,
                              driving: np.ndarray = driving) -> float:
                    return float(np.dot(driving, rotation(axis, angle) @ self.reference[k]))

                if index == 0:
                    grid = np.linspace(-np.pi, np.pi, 721)
                    values = [condition(angle) for angle in grid]
                    start = next(i for i in range(720) if values[i] * values[i + 1] <= 0)
                    root = brentq(condition, grid[start], grid[start + 1], xtol=1e-15)
                else:
                    root = brentq(condition, previous[k] - 0.6, previous[k] + 0.6, xtol=1e-15)
                current[k] = root
                if k < self.joints:
                    driving = rotation(axis, root + self.phases[k - 1]) @ self.reference[k]
            angles[:, index] = current
            previous = current
        return angles

    def derivatives(self, samples: int = 128) -> tuple[np.ndarray, np.ndarray]:
        """First and second derivatives of every shaft's angle by the gearbox's, on a fine
        grid of 16384 gearbox angles over a revolution (spectral interpolation)."""
        theta = 2.0 * np.pi * np.arange(samples) / samples
        angles = self.shaft_angles(theta)
        periodic = angles - theta  # each shaft turns once per gearbox turn
        periodic -= np.round((periodic - periodic[:, :1]) / (2 * np.pi)) * 2 * np.pi
        spectrum = np.fft.rfft(periodic, axis=1)
        wave = np.fft.rfftfreq(samples, 1.0 / samples)
        fine = 16384
        first = 1.0 + np.fft.irfft(spectrum * (1j * wave), n=fine, axis=1) * fine / samples
        second = np.fft.irfft(spectrum * (-(wave**2)), n=fine, axis=1) * fine / samples
        return first, second

    def peaks(self, speed_rpm: float) -> tuple[np.ndarray, np.ndarray]:
        """Peak |acceleration| of shafts 1..n (gearbox constant) and 0..n-1 (pinion constant)."""
        omega_squared = (speed_rpm * np.pi / 30.0) ** 2
        first, second = self.derivatives()
        drive = omega_squared * np.max(np.abs(second[1:]), axis=1)
        # pinion constant: w_k = W r_k / r_n, a_k = W^2 (r_k / r_n)' / r_n
        last, last_second = first[-1], second[-1]
        coast = omega_squared * np.max(np.abs(
            (second[:-1] * last - first[:-1] * last_second) / last**3), axis=1)
        return drive, coast
