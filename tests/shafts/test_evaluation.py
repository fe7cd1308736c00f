"""Figures of an Evaluation against closed forms for one joint (paper eq. 5 and 8)."""

import functools
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest

import sso

RPM_TO_RAD_S = 2 * np.pi / 60


@pytest.mark.parametrize("beta_deg", [10.0, 35.0, 70.0])
def test_single_joint_figures_match_closed_forms(beta_deg):
    speed_rpm = 120.0
    evaluation = sso.ShaftSeries([beta_deg]).evaluate(input_speed_rpm=speed_rpm)
    cosine, sine = np.cos(np.radians(beta_deg)), np.sin(np.radians(beta_deg))
    # eq. 8 extremes
    assert evaluation.speed_min_rpm == pytest.approx(speed_rpm * cosine, rel=1e-12)
    assert evaluation.speed_max_rpm == pytest.approx(speed_rpm / cosine, rel=1e-12)
    assert evaluation.fluctuation == pytest.approx(1 / cosine - cosine, rel=1e-12)
    assert evaluation.torque_ratio_min == pytest.approx(cosine, rel=1e-12)
    assert evaluation.torque_ratio_max == pytest.approx(1 / cosine, rel=1e-12)
    # RE of one joint: (1/pi) int (r - 1)^2 with int r = pi and int r^2 = pi (1 + c^2) / (2 c)
    expected_re = (1 + cosine**2) / (2 * cosine) - 1
    assert evaluation.residual_error == pytest.approx(expected_re, rel=1e-10)
    assert evaluation.residual_error_rpm2 == pytest.approx(speed_rpm**2 * expected_re, rel=1e-10)
    # eq. 5: largest |atan(c tan t) - t| is 90 - 2 atan(sqrt(c)) deg, at tan t = 1/sqrt(c)
    expected_lag_deg = 90.0 - 2 * np.degrees(np.arctan(np.sqrt(cosine)))
    # read off a 0.25-deg grid refined locally (sso._shafts.evaluation._peak)
    assert evaluation.transmission_error_deg == pytest.approx(expected_lag_deg, rel=1e-10)
    # d(ratio)/dtheta = c s^2 sin(2t) / (1 - s^2 sin^2 t)^2, maximised on a fine grid
    theta = np.linspace(0, np.pi, 2_000_001)
    slope = cosine * sine**2 * np.sin(2 * theta) / (1 - sine**2 * np.sin(theta) ** 2) ** 2
    expected_accel = (speed_rpm * RPM_TO_RAD_S) ** 2 * np.max(np.abs(slope))
    assert evaluation.max_output_accel_rad_s2 == pytest.approx(expected_accel, rel=1e-9)
    assert evaluation.mean_speed_ratio == pytest.approx(1.0, abs=1e-14)
    assert evaluation.quadrature_converged


def test_evaluation_is_speed_independent_in_ratio_terms():
    series = sso.ShaftSeries([30, 40, 50], [20, 75])
    slow, fast = series.evaluate(1e-3), series.evaluate(1e5)
    assert slow.residual_error == fast.residual_error
    assert slow.fluctuation == pytest.approx(fast.fluctuation, rel=1e-14)
    assert fast.residual_error_rpm2 == pytest.approx(1e10 * fast.residual_error, rel=1e-14)


def test_to_dict_is_complete_and_plain():
    evaluation = sso.ShaftSeries([20, 20], [90]).evaluate()
    record = evaluation.to_dict()
    assert set(record) == set(sso.Evaluation.__dataclass_fields__)
    assert all(isinstance(value, (int, float, bool)) for value in record.values())


def test_exact_figures_come_from_the_closed_form_and_match_a_fine_quadrature():
    # RE and speed extremes of the exact model are the chain matrix's closed form
    # (samples = 0); checked against the rectangle rule on 4096 angles of the
    # angle-by-angle chain and against the extremes of a dense speed-ratio grid.
    from sso._shafts.objective import residual_error as quadrature_re

    rng = np.random.default_rng(20261123)
    for n_joints in (1, 2, 4, 7):
        beta = rng.uniform(0.0, 60.0, n_joints)
        phase = rng.uniform(0.0, 180.0, n_joints - 1)
        series = sso.ShaftSeries(beta, phase)
        evaluation = series.evaluate(30.0)
        assert evaluation.samples == 0 and evaluation.quadrature_error == 0.0
        assert evaluation.quadrature_converged and evaluation.mean_speed_ratio == 1.0
        reference = float(quadrature_re(list(series.beta_rad), list(series.phase_rad), "exact",
                                        4096))
        assert evaluation.residual_error == pytest.approx(reference, rel=1e-10, abs=1e-16)
        from sso._kinematics.hooke import chain_kinematics

        theta = np.linspace(0.0, np.pi, 200_001)
        dense = chain_kinematics(np, np.cos(theta), np.sin(theta), list(series.beta_rad),
                                 list(series.phase_rad), "exact").speed_ratio
        assert evaluation.speed_min_rpm == pytest.approx(30.0 * dense.min(), rel=1e-9)
        assert evaluation.speed_max_rpm == pytest.approx(30.0 * dense.max(), rel=1e-9)


def _fine_peak(values_at: Callable[[np.ndarray], np.ndarray],
               grid_points: int = 100_001) -> float:
    """Largest value of a smooth function of theta on [0, pi): a dense grid, then a
    bounded scalar maximisation between the grid neighbours of the best point."""
    from scipy.optimize import minimize_scalar

    theta = np.linspace(0.0, np.pi, grid_points)
    values = values_at(theta)
    best = int(np.argmax(values))
    bracket = (theta[max(best - 1, 0)], theta[min(best + 1, grid_points - 1)])
    found = minimize_scalar(lambda angle: -float(values_at(np.array([angle]))[0]),
                            bounds=bracket, method="bounded", options={"xatol": 1e-14})
    return max(float(values[best]), -float(found.fun))


@pytest.mark.parametrize("top_deg", [30.0, 60.0, 85.0, 89.0])
def test_exact_acceleration_and_transmission_error_match_the_joint_by_joint_chain(top_deg):
    # The exact model's peak output acceleration and transmission error are closed
    # forms of the chain matrix (sso._kinematics.hooke_matrix.peak_ratio_slope and
    # lag_swing). The reference is independent of the matrix: the joint-by-joint chain
    # (sso._kinematics.hooke.chain_kinematics, one joint's law after another), its
    # ratio slope and angle lag maximised over theta by a 100,001-point grid and a
    # bounded scalar search. Agreement to 1e-9 relative, up to 89 deg, 1 to 7 joints.
    rng = np.random.default_rng(int(top_deg))
    speed_rpm = 60.0 / (2.0 * np.pi)  # 1 rad/s: the acceleration is the ratio slope
    for _ in range(12):
        n_joints = int(rng.integers(1, 8))
        series = sso.ShaftSeries(rng.uniform(0.0, top_deg, n_joints),
                                 rng.uniform(-360.0, 360.0, n_joints - 1))
        chain = functools.partial(_joint_by_joint, list(series.beta_rad),
                                  list(series.phase_rad))
        evaluation = series.evaluate(speed_rpm)
        slope = _fine_peak(functools.partial(_ratio_slope, chain))
        lag = _fine_peak(functools.partial(_angle_lag, chain))
        assert evaluation.max_output_accel_rad_s2 == pytest.approx(slope, rel=1e-9)
        assert evaluation.transmission_error_deg == pytest.approx(np.degrees(lag), rel=1e-9,
                                                                  abs=1e-12)


def _ratio_slope(chain: Callable[[np.ndarray], Any], theta: np.ndarray) -> np.ndarray:
    kinematics = chain(theta)
    slope: np.ndarray = np.abs(kinematics.speed_ratio * kinematics.log_ratio_slope)
    return slope


def _angle_lag(chain: Callable[[np.ndarray], Any], theta: np.ndarray) -> np.ndarray:
    lag: np.ndarray = np.abs(chain(theta).angle_lag_rad)
    return lag


def _joint_by_joint(beta_rad: list[float], phase_rad: list[float], theta: np.ndarray) -> Any:
    """The exact chain joint after joint (sso._kinematics.hooke), not the chain matrix."""
    from sso._kinematics.hooke import chain_kinematics

    return chain_kinematics(np, np.cos(theta), np.sin(theta), beta_rad, phase_rad, "exact")


def test_exact_acceleration_stays_finite_for_aligned_joints_near_ninety_degrees():
    # Four aligned joints at 89.97 deg (near the largest angle four joints may have,
    # 89.9786 deg: docs/model.md, "Numerical limits"): M = diag(1, k),
    # k = cos^4 89.97 deg ~ 7.5e-14, so the least |M v|^2 is k^2 ~ 5.6e-27, a difference
    # the closed form must not take. The peak is ~1e-13 rad wide, beyond any grid: the
    # reference is the exact slope of w_out / w_in = k / (cos^2 theta + k^2 sin^2 theta),
    # in t = tan theta 2 k (1 - k^2) t (1 + t^2) / (1 + k^2 t^2)^2, maximised in 50-digit
    # arithmetic (its log-derivative's root near t = sqrt(3) / k; the peak is about
    # 3 sqrt(3) / (8 k^2) ~ 1.2e26 per (rad/s)^2).
    import mpmath

    mpmath.mp.dps = 50
    k = mpmath.cos(mpmath.radians(mpmath.mpf("89.97"))) ** 4

    def log_derivative(t: Any) -> Any:
        return 1 / t + 2 * t / (1 + t**2) - 4 * k**2 * t / (1 + k**2 * t**2)

    peak_t = mpmath.findroot(log_derivative, mpmath.sqrt(3) / k)
    reference = 2 * k * (1 - k**2) * peak_t * (1 + peak_t**2) / (1 + k**2 * peak_t**2) ** 2
    accel = sso.ShaftSeries([89.97] * 4, [0.0] * 3).evaluate(60.0 / (2.0 * np.pi))
    assert accel.max_output_accel_rad_s2 == pytest.approx(float(reference), rel=1e-9)
