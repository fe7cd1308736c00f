"""Speed ratio, torque ratio and transmission error of a column from lock to lock.

A steering engineer signs a column off on what the driver turns: the steering-wheel
angle ``w`` from straight ahead, over ``-lock_deg .. +lock_deg``. The steering wheel
sits on the input shaft, so the input yoke's angle is ``theta = straight_ahead_deg +
w``, with ``theta`` measured as in :mod:`sso._column.feel`: from the first bend plane's
normal ``n_1`` about the input shaft's direction ``u_0`` (right-hand rule). ``u_0``
points from the steering wheel into the column, so a positive ``w`` is a clockwise
turn of the wheel as the driver sees it.

With ``M`` the chain matrix (:mod:`sso._column.chain_matrix`) and ``v = (cos theta,
sin theta)``, the output turns by the angle of ``M v``, so

* speed ratio ``r = det M / |M v|^2`` (output over input speed; mean 1 over a turn);
* output torque ratio ``T_out / T_in = 1 / r`` (no friction, no inertia);
* transmission error ``TE(w) = (output angle - input angle)``, both from straight
  ahead, deg: 0 on-centre. With the polar split ``M = R(alpha) P`` (``P``
  symmetric positive definite) the output angle is ``theta + alpha + angle(v, P v)``
  and ``v . P v > 0``, so ``TE = angle(v, P v) - angle(v_c, P v_c)`` with no
  wrapping.

The extremes over the range are exact, not sampled: ``|M v|^2 = A + R cos(2 theta -
phi)``, so the ratio is stationary at ``theta = phi / 2 + k 90 deg`` and the
transmission error where ``r = 1``, ``cos(2 theta - phi) = (det M - A) / R``; each
extreme is the largest or least value at those angles inside the range and at its
ends. Fluctuations are peak-to-peak in percent of the mean ratio over a turn (1).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from sso._column.chain_matrix import chain_matrix
from sso._column.design import column_design
from sso._display import Part, Readable, TextTable, format_number, format_numbers
from sso._limits import DEFAULT_LOCK_DEG, DEFAULT_ON_CENTRE_DEG, DEFAULT_STRAIGHT_AHEAD_DEG
from sso._record import Record
from sso._validation import finite_float, finite_in_range

MAX_LOCK_DEG = 3600.0
CURVE_POINTS = 721
# Stationary angles closer than this (rad) to the range's ends are the ends themselves.
ANGLE_SLACK_RAD = 1e-12


@dataclass(frozen=True, eq=False, repr=False)
class SteeringRange(Record, Readable):
    """Steering figures of one assembly from lock to lock.

    Attributes
    ----------
    straight_ahead_deg : float
        Input yoke angle ``theta`` at straight ahead, deg (module notes).
    lock_deg : float
        Steering-wheel angle from straight ahead to each lock, deg.
    on_centre_deg : float
        Half-width of the on-centre window, steering-wheel deg.
    wheel_angle_deg : tuple of float
        The curves' abscissa: ``CURVE_POINTS`` steering-wheel angles from
        ``-lock_deg`` to ``+lock_deg``, deg (positive: clockwise as the driver sees it).
    speed_ratio, torque_ratio, transmission_error_deg : tuple of float
        The curves: output over input speed, output over input torque, and the
        transmission error (deg) at each wheel angle.
    speed_ratio_min, speed_ratio_max : float
        Exact extremes of the speed ratio over the range.
    speed_fluctuation_percent : float
        ``100 (speed_ratio_max - speed_ratio_min)``, percent of the mean ratio 1.
    torque_fluctuation_percent : float
        ``100 (1 / speed_ratio_min - 1 / speed_ratio_max)``, percent.
    transmission_error_min_deg, transmission_error_max_deg : float
        Exact extremes of the transmission error over the range, deg (0 lies between).
    largest_transmission_error_deg : float
        The largest ``|TE|`` over the range, deg.
    transmission_error_peak_to_peak_deg : float
        ``transmission_error_max_deg - transmission_error_min_deg``, deg.
    on_centre_speed_ratio, on_centre_torque_ratio : float
        Ratios at straight ahead.
    on_centre_fluctuation_percent : float
        Peak-to-peak speed ratio over ``+- on_centre_deg`` (within the range), percent.
    lock_speed_ratio, lock_torque_ratio, lock_transmission_error_deg : (float, float)
        At the anticlockwise lock (``-lock_deg``) and the clockwise lock (``+lock_deg``).
    """

    straight_ahead_deg: float
    lock_deg: float
    on_centre_deg: float
    # The curves would fill a repr with thousands of numbers.
    wheel_angle_deg: tuple[float, ...] = field(repr=False)
    speed_ratio: tuple[float, ...] = field(repr=False)
    torque_ratio: tuple[float, ...] = field(repr=False)
    transmission_error_deg: tuple[float, ...] = field(repr=False)
    speed_ratio_min: float
    speed_ratio_max: float
    speed_fluctuation_percent: float
    torque_fluctuation_percent: float
    transmission_error_min_deg: float
    transmission_error_max_deg: float
    largest_transmission_error_deg: float
    transmission_error_peak_to_peak_deg: float
    on_centre_speed_ratio: float
    on_centre_torque_ratio: float
    on_centre_fluctuation_percent: float
    lock_speed_ratio: tuple[float, float]
    lock_torque_ratio: tuple[float, float]
    lock_transmission_error_deg: tuple[float, float]

    def _summary_parts(self) -> list[Part]:
        figures = (
            ("speed ratio, min .. max", f"{format_number(self.speed_ratio_min)} .. "
                                        f"{format_number(self.speed_ratio_max)}"),
            ("speed fluctuation (%)", format_number(self.speed_fluctuation_percent)),
            ("torque fluctuation (%)", format_number(self.torque_fluctuation_percent)),
            ("transmission error, min .. max (deg)",
             f"{format_number(self.transmission_error_min_deg)} .. "
             f"{format_number(self.transmission_error_max_deg)}"),
            ("on-centre speed ratio", format_number(self.on_centre_speed_ratio)),
            ("on-centre fluctuation (%)", format_number(self.on_centre_fluctuation_percent)),
            ("speed ratio at the locks", format_numbers(self.lock_speed_ratio)),
            ("transmission error at the locks (deg)",
             format_numbers(self.lock_transmission_error_deg)))
        return [f"Steering from lock to lock (+-{format_number(self.lock_deg)} deg of the "
                f"wheel, straight ahead at {format_number(self.straight_ahead_deg)} deg)",
                TextTable(("figure", "value"), figures)]


def steering_range(design: Any, *, lock_deg: float = DEFAULT_LOCK_DEG,
                   straight_ahead_deg: float = DEFAULT_STRAIGHT_AHEAD_DEG,
                   on_centre_deg: float = DEFAULT_ON_CENTRE_DEG) -> SteeringRange:
    """Speed ratio, torque ratio and transmission error of a design from lock to lock.

    Parameters
    ----------
    design : (ColumnGeometry, sequence of float) or result
        A column and its yoke phasing (deg, fitter's convention), or a result with
        ``geometry`` and ``yoke_phase_deg``.
    lock_deg : float
        Steering-wheel angle from straight ahead to each lock, deg, in ``(0, 3600]``;
        default 540 (1.5 turns each way, 3 turns lock to lock).
    straight_ahead_deg : float
        Input yoke angle ``theta`` at straight ahead, deg, finite; default 0 (the
        input yoke's pin axis along the first bend plane's normal).
    on_centre_deg : float
        Half-width of the on-centre window, steering-wheel deg, in ``(0, 90)``;
        default 30.

    Returns
    -------
    SteeringRange

    Raises
    ------
    TypeError, ValueError
        For a bad design or option, naming the field and its range.
    """
    geometry, yoke = column_design(design)
    lock = finite_in_range("lock_deg", lock_deg, 0.0, MAX_LOCK_DEG, "deg", lower_open=True)
    centre = finite_float("straight_ahead_deg", straight_ahead_deg)
    window = finite_in_range("on_centre_deg", on_centre_deg, 0.0, 90.0, "deg",
                             lower_open=True, upper_open=True)
    matrix = chain_matrix(np.radians(geometry.beta_deg),
                          np.radians(geometry.phase_deg_from_yoke(yoke)))
    chain = _Chain(matrix, math.radians(centre))
    low, high = math.radians(centre - lock), math.radians(centre + lock)
    wheel = np.linspace(-lock, lock, CURVE_POINTS)
    theta = np.radians(centre + wheel)
    ratio = chain.ratio(theta)
    error = np.degrees(chain.transmission_error(theta))
    ratio_low, ratio_high, error_low, error_high = _extremes(chain, low, high)
    window_low, window_high = chain.ratio_extremes(math.radians(centre - min(window, lock)),
                                                   math.radians(centre + min(window, lock)))
    ends = np.array([low, high])
    end_ratio = chain.ratio(ends)
    end_error = np.degrees(chain.transmission_error(ends))
    at_centre = float(chain.ratio(np.array([math.radians(centre)]))[0])
    return SteeringRange(
        straight_ahead_deg=centre, lock_deg=lock, on_centre_deg=window,
        wheel_angle_deg=_floats(wheel), speed_ratio=_floats(ratio),
        torque_ratio=_floats(1.0 / ratio), transmission_error_deg=_floats(error),
        speed_ratio_min=ratio_low, speed_ratio_max=ratio_high,
        speed_fluctuation_percent=100.0 * (ratio_high - ratio_low),
        torque_fluctuation_percent=100.0 * (1.0 / ratio_low - 1.0 / ratio_high),
        transmission_error_min_deg=error_low, transmission_error_max_deg=error_high,
        largest_transmission_error_deg=max(abs(error_low), abs(error_high)),
        transmission_error_peak_to_peak_deg=error_high - error_low,
        on_centre_speed_ratio=at_centre, on_centre_torque_ratio=1.0 / at_centre,
        on_centre_fluctuation_percent=100.0 * (window_high - window_low),
        lock_speed_ratio=(float(end_ratio[0]), float(end_ratio[1])),
        lock_torque_ratio=(float(1.0 / end_ratio[0]), float(1.0 / end_ratio[1])),
        lock_transmission_error_deg=(float(end_error[0]), float(end_error[1])),
    )


def range_extremes(matrix: np.ndarray, straight_ahead_deg: float,
                   lock_deg: float) -> tuple[float, float, float, float]:
    """Exact extremes of one chain matrix's figures over the steering range.

    Parameters
    ----------
    matrix : numpy.ndarray, shape (2, 2)
        The chain matrix (:func:`sso._column.chain_matrix.chain_matrix`).
    straight_ahead_deg, lock_deg : float
        As :func:`steering_range` takes them (not checked here), deg.

    Returns
    -------
    (float, float, float, float)
        Least and largest speed ratio, least and largest transmission error (deg).
    """
    centre = math.radians(straight_ahead_deg)
    lock = math.radians(lock_deg)
    return _extremes(_Chain(matrix, centre), centre - lock, centre + lock)


def _extremes(chain: _Chain, low: float, high: float) -> tuple[float, float, float, float]:
    ratio_low, ratio_high = chain.ratio_extremes(low, high)
    error_low, error_high = (math.degrees(value) for value in chain.error_extremes(low, high))
    return ratio_low, ratio_high, error_low, error_high


class _Chain:
    """The speed ratio and transmission error of one chain matrix, and their extremes."""

    def __init__(self, matrix: np.ndarray, centre_rad: float) -> None:
        m11, m12, m21, m22 = (float(matrix[0, 0]), float(matrix[0, 1]),
                              float(matrix[1, 0]), float(matrix[1, 1]))
        self.matrix = matrix
        self.determinant = m11 * m22 - m12 * m21
        mean = 0.5 * (m11 * m11 + m12 * m12 + m21 * m21 + m22 * m22)
        cosine_part = 0.5 * (m11 * m11 + m21 * m21 - m12 * m12 - m22 * m22)
        sine_part = m11 * m12 + m21 * m22
        self.amplitude = math.hypot(cosine_part, sine_part)
        self.mean = mean
        self.phase = math.atan2(sine_part, cosine_part)
        rotation = math.atan2(m21 - m12, m11 + m22)
        cosine, sine = math.cos(rotation), math.sin(rotation)
        # P = R(-alpha) M: symmetric positive definite when det M > 0.
        self.stretch = np.array([[cosine, sine], [-sine, cosine]]) @ matrix
        self.centre_lag = float(self._lag(np.array([centre_rad]))[0])

    def ratio(self, theta_rad: np.ndarray) -> np.ndarray:
        directions = np.stack([np.cos(theta_rad), np.sin(theta_rad)], axis=-1) @ self.matrix.T
        ratio: np.ndarray = self.determinant / np.sum(directions**2, axis=-1)
        return ratio

    def transmission_error(self, theta_rad: np.ndarray) -> np.ndarray:
        error: np.ndarray = self._lag(theta_rad) - self.centre_lag
        return error

    def ratio_extremes(self, low: float, high: float) -> tuple[float, float]:
        candidates = [low, high]
        if self.amplitude > 0.0:
            candidates += _angles_between(0.5 * self.phase, 0.5 * math.pi, low, high)
        values = self.ratio(np.array(candidates))
        return float(values.min()), float(values.max())

    def error_extremes(self, low: float, high: float) -> tuple[float, float]:
        candidates = [low, high]
        if self.amplitude > 0.0:
            cosine = min(1.0, max(-1.0, (self.determinant - self.mean) / self.amplitude))
            for sign in (1.0, -1.0):
                candidates += _angles_between(0.5 * (self.phase + sign * math.acos(cosine)),
                                              math.pi, low, high)
        values = self.transmission_error(np.array(candidates))
        return float(values.min()), float(values.max())

    def _lag(self, theta_rad: np.ndarray) -> np.ndarray:
        """``angle(v, P v)`` at each input angle, rad, in ``(-pi/2, pi/2)``."""
        cos_theta, sin_theta = np.cos(theta_rad), np.sin(theta_rad)
        stretch = self.stretch
        x = stretch[0, 0] * cos_theta + stretch[0, 1] * sin_theta
        y = stretch[1, 0] * cos_theta + stretch[1, 1] * sin_theta
        lag: np.ndarray = np.arctan2(cos_theta * y - sin_theta * x, cos_theta * x + sin_theta * y)
        return lag


def _angles_between(base: float, period: float, low: float, high: float) -> list[float]:
    """Every ``base + k period`` inside ``(low, high)``."""
    first = math.ceil((low - base) / period)
    last = math.floor((high - base) / period)
    return [base + k * period for k in range(first, last + 1)
            if low + ANGLE_SLACK_RAD < base + k * period < high - ANGLE_SLACK_RAD]


def _floats(values: np.ndarray) -> tuple[float, ...]:
    return tuple(float(value) for value in values)
