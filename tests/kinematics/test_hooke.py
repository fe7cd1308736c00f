"""Checks with known answers from docs/model.md ("Checks with known answers")."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import sso
from sso._kinematics.hooke import chain_kinematics

THETA_DEG = np.linspace(0.0, 360.0, 721)


@pytest.mark.parametrize("model", ["exact", "paper"])
@pytest.mark.parametrize("beta_deg", [5.0, 30.0, 60.0, 85.0])
def test_single_joint_extremes(model, beta_deg):
    # docs/model.md, "One joint": min cos(beta) at theta = 0, max 1/cos(beta) at theta = 90 deg.
    series = sso.ShaftSeries([beta_deg], model=model)
    ratio = series.speed_ratio([0.0, 90.0, 180.0, 270.0])
    cosine = np.cos(np.radians(beta_deg))
    np.testing.assert_allclose(ratio, [cosine, 1 / cosine, cosine, 1 / cosine], rtol=1e-14)
    dense = series.speed_ratio(THETA_DEG)
    assert dense.min() == pytest.approx(cosine, rel=1e-14)
    assert dense.max() == pytest.approx(1 / cosine, rel=1e-14)


def test_single_joint_angle_law():
    # paper eq. 5: tan g = cos(beta) tan(a)
    series = sso.ShaftSeries([35.0])
    theta = np.array([10.0, 45.0, 80.0])
    expected = np.degrees(np.arctan(np.cos(np.radians(35.0)) * np.tan(np.radians(theta))))
    np.testing.assert_allclose(series.output_angle_deg(theta), expected, rtol=1e-13)


def test_output_angle_is_unwrapped_and_advances_one_turn():
    series = sso.ShaftSeries([30.0, 40.0, 50.0], [20.0, 70.0])
    angle = series.output_angle_deg(THETA_DEG)
    assert np.all(np.diff(angle) > 0)
    assert angle[-1] - angle[0] == pytest.approx(360.0, abs=1e-10)


@settings(max_examples=60, deadline=None)
@given(
    beta=st.lists(st.floats(0.0, 70.0), min_size=1, max_size=6),
    data=st.data(),
)
def test_exact_mean_ratio_is_one(beta, data):
    # docs/model.md: exact model, any n, beta, phi: the mean ratio over a revolution is 1.
    phases = data.draw(st.lists(st.floats(-180.0, 180.0), min_size=len(beta) - 1,
                                max_size=len(beta) - 1))
    series = sso.ShaftSeries(beta, phases)
    theta = np.arange(4096) * 180.0 / 4096
    assert np.mean(series.speed_ratio(theta)) == pytest.approx(1.0, abs=1e-12)


def test_paper_model_mean_ratio_is_not_one():
    # docs/model.md: the paper model fails the mean-ratio check (option-3 trial design).
    evaluation = sso.ShaftSeries([30, 40, 50], [90, 90], model="paper").evaluate()
    assert abs(evaluation.mean_speed_ratio - 1.0) > 0.04


@pytest.mark.parametrize("beta_deg", [10.0, 30.0, 60.0])
def test_two_equal_joints_cancel_in_exact_model_only(beta_deg):
    # docs/model.md: exact, two equal joints, phi = 90: ratio = 1 for every theta (round-off);
    # the paper model leaves a fluctuation (about 2 % at 30 deg).
    exact = sso.ShaftSeries([beta_deg, beta_deg], [90.0]).speed_ratio(THETA_DEG)
    np.testing.assert_allclose(exact, 1.0, atol=1e-14)
    paper = sso.ShaftSeries([beta_deg, beta_deg], [90.0], model="paper").speed_ratio(THETA_DEG)
    assert paper.max() - paper.min() > 1e-4


def test_paper_model_two_joint_fluctuation_near_two_percent_at_30():
    paper = sso.ShaftSeries([30.0, 30.0], [90.0], model="paper").speed_ratio(THETA_DEG)
    # peak deviation from 1 at 30 deg; docs/model.md quotes "about 2 %"
    assert 0.015 < np.max(np.abs(paper - 1.0)) < 0.025


@pytest.mark.parametrize("beta_pair", [(10.0, 25.0), (30.0, 5.0), (45.0, 60.0)])
def test_two_joint_closed_form(beta_pair):
    # docs/model.md: exact, two joints, phi = 90: ratio = c1 c2 / (c2^2 cos^2 t + c1^2 sin^2 t)
    c1, c2 = np.cos(np.radians(beta_pair))
    theta = np.radians(THETA_DEG)
    expected = c1 * c2 / (c2**2 * np.cos(theta) ** 2 + c1**2 * np.sin(theta) ** 2)
    ratio = sso.ShaftSeries(list(beta_pair), [90.0]).speed_ratio(THETA_DEG)
    np.testing.assert_allclose(ratio, expected, rtol=1e-13)


@pytest.mark.parametrize(
    "beta_deg, phase_deg, low_rpm, high_rpm",
    [
        # docs/model.md, "Checks with known answers", trial designs: option 3, option 2, option 1
        ([30, 40, 50], [90, 90], 18.17, 34.40),
        ([10, 15, 30], [90, 90], 22.07, 28.31),
        ([15, 20, 9], [30, 40], 22.98, 27.17),
    ],
)
def test_paper_trial_ranges(beta_deg, phase_deg, low_rpm, high_rpm):
    evaluation = sso.ShaftSeries(beta_deg, phase_deg, model="paper").evaluate(input_speed_rpm=25)
    assert evaluation.speed_min_rpm == pytest.approx(low_rpm, abs=0.005)
    assert evaluation.speed_max_rpm == pytest.approx(high_rpm, abs=0.005)


def test_log_slope_matches_finite_difference():
    beta = np.radians([30.0, 40.0, 50.0])
    phase = np.radians([20.0, 75.0])
    for model in ("exact", "paper"):
        theta = np.linspace(0.0, np.pi, 181)
        step = 1e-6
        chain = chain_kinematics(np, np.cos(theta), np.sin(theta), list(beta), list(phase), model)
        plus = chain_kinematics(np, np.cos(theta + step), np.sin(theta + step), list(beta),
                                list(phase), model, figures=False).speed_ratio
        minus = chain_kinematics(np, np.cos(theta - step), np.sin(theta - step), list(beta),
                                 list(phase), model, figures=False).speed_ratio
        np.testing.assert_allclose(chain.speed_ratio * chain.log_ratio_slope,
                                   (plus - minus) / (2 * step), rtol=1e-6, atol=1e-8)


def test_exact_angle_lag_derivative_is_ratio_minus_one():
    series = sso.ShaftSeries([30.0, 40.0, 50.0], [20.0, 75.0])
    step = 1e-5
    theta = np.linspace(0.0, 180.0, 91)
    derivative = (series.output_angle_deg(theta + step)
                  - series.output_angle_deg(theta - step)) / (2 * step)
    np.testing.assert_allclose(derivative, series.speed_ratio(theta), rtol=1e-8)
