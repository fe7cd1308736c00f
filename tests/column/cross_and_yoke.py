"""An independent 3D cross-and-yoke simulation of a column of Hooke joints.

It never uses the joint law ``tan g = cos b tan a``. Each shaft turns about its own
axis; a joint's cross joins the pin axis ``p`` of the yoke before it to the pin axis
``q`` of the yoke after it, and the cross keeps them perpendicular. So ``q`` is the
line perpendicular to both ``p`` and the output shaft axis, and the speed ratio of
the joint follows from differentiating ``p . q = 0``:
``w_in (u_in x p) . q + w_out p . (u_out x q) = 0``. On the intermediate shaft the
next yoke's pin axis is ``q`` turned by the yoke phasing about the shaft axis.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import minimize_scalar


def rotate(axis: np.ndarray, angle_rad: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """Rodrigues rotation of row vectors about a unit ``axis`` by ``angle_rad`` (per row)."""
    angle = np.asarray(angle_rad, dtype=float)[..., None]
    return (vectors * np.cos(angle) + np.cross(axis, vectors) * np.sin(angle)
            + axis * (vectors @ axis)[..., None] * (1.0 - np.cos(angle)))


def shaft_axes(points_mm: np.ndarray) -> np.ndarray:
    """Unit direction of each shaft from consecutive points."""
    differences = np.diff(np.asarray(points_mm, dtype=float), axis=0)
    return differences / np.linalg.norm(differences, axis=1, keepdims=True)


def speed_ratio(points_mm: np.ndarray, yoke_phase_deg: np.ndarray, theta_rad: np.ndarray,
                input_pin_reference: np.ndarray) -> np.ndarray:
    """Output over input speed at input angles ``theta_rad``.

    ``theta = 0`` puts the input yoke's pin axis along ``input_pin_reference`` (a
    unit vector normal to the input shaft); ``theta`` turns it about the input
    shaft's axis by the right-hand rule.
    """
    return _turn(points_mm, yoke_phase_deg, theta_rad, input_pin_reference)[0]


def output_angle(points_mm: np.ndarray, yoke_phase_deg: np.ndarray, theta_rad: np.ndarray,
                 input_pin_reference: np.ndarray, output_reference: np.ndarray) -> np.ndarray:
    """Angle (rad) of the output yoke's pin axis about the output shaft, from
    ``output_reference`` (right-hand rule), modulo pi (a pin axis is a line)."""
    axes = shaft_axes(points_mm)
    pin = _turn(points_mm, yoke_phase_deg, theta_rad, input_pin_reference)[1]
    sine = np.cross(output_reference, pin) @ axes[-1]
    return np.mod(np.arctan2(sine, pin @ output_reference), np.pi)


def _turn(points_mm: np.ndarray, yoke_phase_deg: np.ndarray, theta_rad: np.ndarray,
          input_pin_reference: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Speed ratio and the output yoke's pin axis at each input angle."""
    axes = shaft_axes(points_mm)
    theta = np.atleast_1d(np.asarray(theta_rad, dtype=float))
    pin_in = rotate(axes[0], theta, np.tile(input_pin_reference, (len(theta), 1)))
    ratio = np.ones(len(theta))
    joints = len(axes) - 1
    for joint in range(1, joints + 1):
        axis_in, axis_out = axes[joint - 1], axes[joint]
        pin_out = np.cross(axis_out, pin_in)
        pin_out /= np.linalg.norm(pin_out, axis=1, keepdims=True)
        driving = np.einsum("ij,ij->i", np.cross(axis_in, pin_in), pin_out)
        driven = np.einsum("ij,ij->i", pin_in, np.cross(axis_out, pin_out))
        ratio *= -driving / driven
        if joint < joints:
            pin_in = rotate(axis_out, np.full(len(theta), np.radians(yoke_phase_deg[joint - 1])),
                            pin_out)
    return ratio, pin_out


def residual_error(points_mm: np.ndarray, yoke_phase_deg: np.ndarray,
                   samples: int = 512) -> float:
    """Mean of ``(ratio - 1)^2`` over ``samples`` equally spaced input angles in [0, 180) deg.

    The ratio is smooth with period 180 deg, so the rectangle rule converges
    geometrically; 512 angles are at round-off for the angles the tests use.
    The input reference does not change the mean over a period.
    """
    axes = shaft_axes(points_mm)
    reference = np.cross(axes[0], [0.3, -0.5, 0.8])
    reference /= np.linalg.norm(reference)
    theta = np.pi * np.arange(samples) / samples
    return float(np.mean((speed_ratio(points_mm, yoke_phase_deg, theta, reference) - 1.0) ** 2))


GRID = 4001


def first_bend_normal(points: np.ndarray) -> np.ndarray:
    axes = shaft_axes(points)
    normal = np.cross(axes[0], axes[1])
    return normal / np.linalg.norm(normal)


class Simulated:
    """Speed ratio and transmission error of the 3D simulation, straight ahead at theta_c."""

    def __init__(self, points: np.ndarray, yoke: np.ndarray, centre_rad: float) -> None:
        self.points, self.yoke, self.centre = points, yoke, centre_rad
        self.reference = first_bend_normal(points)
        output_axis = shaft_axes(points)[-1]
        side = np.cross(output_axis, [0.31, -0.72, 0.62])
        self.output_reference = side / np.linalg.norm(side)
        self.centre_output = self._output(np.array([centre_rad]))[0]

    def _output(self, theta: np.ndarray) -> np.ndarray:
        return output_angle(self.points, self.yoke, theta, self.reference, self.output_reference)

    def ratio(self, theta: np.ndarray) -> np.ndarray:
        return speed_ratio(self.points, self.yoke, theta, self.reference)

    def error(self, theta: np.ndarray) -> np.ndarray:
        """Output turn minus input turn from straight ahead, rad, wrapped to +-90 deg (a
        pin axis is a line; the error of these columns stays far inside that)."""
        turn = self._output(theta) - self.centre_output - (theta - self.centre)
        return np.mod(turn + np.pi / 2, np.pi) - np.pi / 2


def extremes(function, low: float, high: float) -> tuple[float, float]:
    """Least and largest value of a smooth function on [low, high]: grid, then Brent."""
    grid = np.linspace(low, high, GRID)
    values = function(grid)
    found = [values[0], values[-1]]
    for sign in (1.0, -1.0):
        signed = sign * values
        peaks = np.flatnonzero((signed[1:-1] >= signed[:-2]) & (signed[1:-1] >= signed[2:])) + 1
        for index in peaks:
            result = minimize_scalar(lambda x, sign=sign: -sign * function(np.array([x]))[0],
                                     bounds=(grid[index - 1], grid[index + 1]), method="bounded",
                                     options={"xatol": 1e-13})
            found.append(function(np.array([result.x]))[0])
    return float(min(found)), float(max(found))
