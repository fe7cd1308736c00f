"""Figures of an Evaluation against closed forms for one joint (paper eq. 5 and 8)."""

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
    # read off a 0.25-deg grid refined locally (sso.shafts.evaluation._peak)
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
    from sso.shafts.objective import residual_error as quadrature_re

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
        from sso.kinematics.hooke import chain_kinematics

        theta = np.linspace(0.0, np.pi, 200_001)
        dense = chain_kinematics(np, np.cos(theta), np.sin(theta), list(series.beta_rad),
                                 list(series.phase_rad), "exact").speed_ratio
        assert evaluation.speed_min_rpm == pytest.approx(30.0 * dense.min(), rel=1e-9)
        assert evaluation.speed_max_rpm == pytest.approx(30.0 * dense.max(), rel=1e-9)
