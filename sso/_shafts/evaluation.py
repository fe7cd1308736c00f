"""Figures of merit of one shaft-series design at a constant input speed."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, dataclass
from typing import Any, Protocol

import numpy as np

from sso._display import Part, Readable, TextTable, format_number
from sso._kinematics.hooke import chain_kinematics
from sso._kinematics.hooke_matrix import (
    lag_swing,
    peak_ratio_slope,
    ratio_extremes,
    residual_error,
)
from sso._limits import DEFAULT_INPUT_SPEED_RPM, DEFAULT_QUADRATURE_ATOL, DEFAULT_QUADRATURE_RTOL
from sso._record import register_record
from sso._shafts.objective import angle_grid, squared_ratio_error
from sso._shafts.quadrature import EVALUATION_MAX_SAMPLES, adaptive_rule, resolving_samples
from sso._validation import finite_in_range, validate_speed


class JointAngles(Protocol):
    """What :func:`evaluate` reads of a design (:class:`sso.ShaftSeries` is one).

    A protocol, so this module need not import :mod:`sso._shafts.series`, which
    imports it.
    """

    @property
    def beta_rad(self) -> np.ndarray: ...

    @property
    def phase_rad(self) -> np.ndarray: ...

    @property
    def model(self) -> str: ...

RPM_TO_RAD_S = 2.0 * np.pi / 60.0
# The paper model's figures (extremes of speed, acceleration, angle) are read off a
# grid at least this fine over the 180-deg period (four times the quadrature count when that is
# more), then refined locally. A power of two, so the quadrature grids are in it.
MIN_FIGURE_SAMPLES = 1024
# ``samples`` of an exact-model evaluation: its RE is the closed form, no quadrature.
CLOSED_FORM_SAMPLES = 0


# (field, label with unit) of the figures a summary shows.
SUMMARY_FIGURES = (
    ("residual_error", "residual error RE"),
    ("speed_min_rpm", "output speed min (rpm)"),
    ("speed_max_rpm", "output speed max (rpm)"),
    ("fluctuation", "fluctuation / input speed"),
    ("transmission_error_deg", "transmission error (deg)"),
    ("max_output_accel_rad_s2", "output acceleration max (rad/s^2)"),
)


@register_record
@dataclass(frozen=True, repr=False)
class Evaluation(Readable):
    """Figures of merit of a design, all over one revolution at constant input speed.

    Attributes
    ----------
    input_speed_rpm : float
        Input shaft speed, rpm.
    residual_error : float
        ``RE``, mean square of ``w_out/w_in - 1`` (dimensionless).
    residual_error_rpm2 : float
        ``input_speed_rpm**2 * RE``: the paper's objective ``U``, rpm^2.
    speed_min_rpm, speed_max_rpm : float
        Extremes of the output speed, rpm.
    mean_speed_ratio : float
        Mean of ``w_out/w_in`` (exactly 1 in the exact model, reported as 1.0).
    fluctuation : float
        Peak-to-peak output speed over input speed (dimensionless).
    fluctuation_rpm : float
        Peak-to-peak output speed, rpm.
    transmission_error_deg : float
        Largest ``|output angle - input angle|``, deg.
    max_output_accel_rad_s2 : float
        Largest ``|d w_out / dt|`` at constant input speed, rad/s^2.
    torque_ratio_min, torque_ratio_max : float
        Extremes of ``T_out / T_in = w_in / w_out`` for lossless joints.
    samples : int
        Quadrature angles in ``[0, 180)`` deg used for RE; 0 for the exact model,
        whose RE and speed extremes come from the closed form of the chain matrix
        (:mod:`sso._kinematics.hooke_matrix`), exact to round-off below 90 deg.
    quadrature_error : float
        Estimated absolute error of RE (dimensionless); 0 for the exact model.
    quadrature_converged : bool
        False if the quadrature hit its cap before its tolerance, or if no count up
        to the cap resolves the speed-ratio peaks of angles near 90 deg (then RE
        and the speed figures are unreliable and a QuadratureWarning is raised).
        Always True for the exact model: there is no quadrature.
    """

    input_speed_rpm: float
    residual_error: float
    residual_error_rpm2: float
    speed_min_rpm: float
    speed_max_rpm: float
    mean_speed_ratio: float
    fluctuation: float
    fluctuation_rpm: float
    transmission_error_deg: float
    max_output_accel_rad_s2: float
    torque_ratio_min: float
    torque_ratio_max: float
    samples: int
    quadrature_error: float
    quadrature_converged: bool

    def _repr_text(self) -> str:
        return (f"RE {format_number(self.residual_error, 4)}, output "
                f"{format_number(self.speed_min_rpm)}..{format_number(self.speed_max_rpm)} rpm "
                f"at {format_number(self.input_speed_rpm)} rpm, fluctuation "
                f"{format_number(self.fluctuation, 4)}, max output accel "
                f"{format_number(self.max_output_accel_rad_s2, 4)} rad/s^2")

    def _summary_parts(self) -> list[Part]:
        rows = tuple((label, format_number(getattr(self, name))) for name, label in SUMMARY_FIGURES)
        return [f"Evaluation at {format_number(self.input_speed_rpm)} rpm input speed",
                TextTable(("figure", "value"), rows)]

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary of every field."""
        return asdict(self)


def evaluate(
    series: JointAngles,
    input_speed_rpm: float = DEFAULT_INPUT_SPEED_RPM,
    quadrature_rtol: float = DEFAULT_QUADRATURE_RTOL,
    quadrature_atol: float = DEFAULT_QUADRATURE_ATOL,
) -> Evaluation:
    """Evaluate a design: residual error and the figures docs/model.md lists.

    Parameters
    ----------
    series : sso.ShaftSeries
        The design.
    input_speed_rpm : float
        Constant input speed, rpm (finite, > 0).
    quadrature_rtol, quadrature_atol : float
        Tolerance of the adaptive residual-error quadrature (dimensionless, > 0
        and >= 0); validated always, used by the paper model only.

    Returns
    -------
    Evaluation

    Raises
    ------
    ValueError
        If the speed or a tolerance is not finite or out of range.
    """
    speed_rpm = validate_speed("input_speed_rpm", input_speed_rpm)
    rtol, atol = validate_quadrature_tolerance(quadrature_rtol, quadrature_atol)
    beta_rad = list(series.beta_rad)
    phase_rad = list(series.phase_rad)
    if series.model == "exact":
        return _closed_form_evaluation(speed_rpm, beta_rad, phase_rad)

    def figures(angles_rad: np.ndarray) -> dict[str, np.ndarray]:
        chain = chain_kinematics(np, np.cos(angles_rad), np.sin(angles_rad), beta_rad,
                                 phase_rad, series.model)
        return {
            "ratio": chain.speed_ratio,
            "negative_ratio": -chain.speed_ratio,
            "slope": np.abs(chain.speed_ratio * chain.log_ratio_slope),
            "lag": np.abs(chain.angle_lag_rad),
        }

    # One pass over a power-of-two grid serves the figures and, by striding, every
    # quadrature count that divides it.
    figure_samples = MIN_FIGURE_SAMPLES
    theta_rad = np.pi * np.arange(figure_samples) / figure_samples
    sampled = figures(theta_rad)
    squared = (sampled["ratio"] - 1.0) ** 2

    def squared_errors(count: int) -> np.ndarray:
        if figure_samples % count == 0:
            return squared[:: figure_samples // count]
        cos_theta, sin_theta = angle_grid(count)
        computed: np.ndarray = squared_ratio_error(np, cos_theta, sin_theta, beta_rad, phase_rad,
                                                   series.model)
        return computed

    residual, rule = adaptive_rule(squared_errors, rtol, atol, EVALUATION_MAX_SAMPLES,
                                   resolving_samples(beta_rad, series.model))
    if figure_samples < 4 * rule.samples:
        figure_samples = 4 * rule.samples
        theta_rad = np.pi * np.arange(figure_samples) / figure_samples
        sampled = figures(theta_rad)
    peaks = _peaks(figures, theta_rad, sampled, np.pi / figure_samples)
    ratio_min, ratio_max = -peaks["negative_ratio"], peaks["ratio"]
    return _evaluation(speed_rpm, float(residual), ratio_min, ratio_max,
                       float(np.mean(sampled["ratio"])), peaks, rule.samples,
                       float(rule.error_estimate), rule.converged)


def _closed_form_evaluation(speed_rpm: float, beta_rad: list[float],
                            phase_rad: list[float]) -> Evaluation:
    """The exact model's figures, every one from the chain matrix (no sampling).

    RE, the speed extremes, the peak ratio slope (the acceleration) and the lag's
    swing are closed forms of ``M`` (:mod:`sso._kinematics.hooke_matrix`); the lag's
    constant part needs the joint-by-joint lag at one input angle, ``theta = 0``.
    The peak transmission error is then ``|constant| + swing``.
    """
    residual = float(residual_error(math, beta_rad, phase_rad))
    ratio_min, ratio_max = ratio_extremes(math, beta_rad, phase_rad)
    lag_at_zero = float(chain_kinematics(math, 1.0, 0.0, beta_rad, phase_rad,
                                         "exact").angle_lag_rad)
    moving_at_zero, swing = lag_swing(beta_rad, phase_rad)
    peaks = {"slope": float(peak_ratio_slope(math, beta_rad, phase_rad)),
             "lag": abs(lag_at_zero - moving_at_zero) + swing}
    return _evaluation(speed_rpm, residual, float(ratio_min), float(ratio_max), 1.0, peaks,
                       CLOSED_FORM_SAMPLES, 0.0, True)


def _evaluation(speed_rpm: float, residual: float, ratio_min: float, ratio_max: float,
                mean_ratio: float, peaks: dict[str, float], samples: int,
                quadrature_error: float, converged: bool) -> Evaluation:
    """An :class:`Evaluation` from RE, the ratio extremes and the refined peaks."""
    input_speed_rad_s = speed_rpm * RPM_TO_RAD_S
    return Evaluation(
        input_speed_rpm=speed_rpm,
        residual_error=float(residual),
        residual_error_rpm2=float(speed_rpm**2 * residual),
        speed_min_rpm=float(speed_rpm * ratio_min),
        speed_max_rpm=float(speed_rpm * ratio_max),
        mean_speed_ratio=mean_ratio,
        fluctuation=float(ratio_max - ratio_min),
        fluctuation_rpm=float(speed_rpm * (ratio_max - ratio_min)),
        transmission_error_deg=float(np.degrees(peaks["lag"])),
        max_output_accel_rad_s2=float(input_speed_rad_s**2 * peaks["slope"]),
        torque_ratio_min=float(1.0 / ratio_max),
        torque_ratio_max=float(1.0 / ratio_min),
        samples=samples,
        quadrature_error=quadrature_error,
        quadrature_converged=converged,
    )


def validate_quadrature_tolerance(rtol: Any, atol: Any) -> tuple[float, float]:
    """Return ``(rtol, atol)`` as floats, or raise naming the field and range."""
    return (finite_in_range("quadrature_rtol", rtol, 0.0, 1.0, lower_open=True, upper_open=True),
            finite_in_range("quadrature_atol", atol, 0.0, math.inf, upper_open=True))


def _peaks(
    figures: Callable[[np.ndarray], dict[str, np.ndarray]],
    theta_rad: np.ndarray,
    sampled: dict[str, np.ndarray],
    step_rad: float,
) -> dict[str, float]:
    """Maximum of each smooth periodic quantity sampled at ``theta_rad``.

    Each grid maximum is refined on a 64-times finer local grid around it (all
    quantities' local grids in one evaluation of the chain) and then by a
    parabola through the three best points, which is accurate to about 1e-12
    relative. Maxima of ``abs`` values are smooth (their kinks are at minima).
    """
    offsets = (step_rad / 32) * np.arange(-32, 33)
    centres = {name: theta_rad[int(np.argmax(values))] for name, values in sampled.items()}
    local_angles = np.concatenate([centre + offsets for centre in centres.values()])
    local_values = figures(local_angles)
    peaks = {}
    for position, name in enumerate(centres):
        local = local_values[name][position * len(offsets):(position + 1) * len(offsets)]
        index = int(np.clip(np.argmax(local), 1, len(local) - 2))
        left, middle, right = local[index - 1], local[index], local[index + 1]
        curvature = left - 2.0 * middle + right
        if curvature >= 0.0:
            peaks[name] = float(local.max())
        else:
            offset = 0.5 * (left - right) / curvature
            peaks[name] = float(middle - 0.25 * (left - right) * offset)
    return peaks
