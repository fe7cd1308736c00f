"""ShaftSeries construction and its input checks (docs/model.md, "Bounds")."""

import math
import warnings

import pytest

import sso


def test_defaults_to_conventional_phases_and_exact_model():
    series = sso.ShaftSeries([30, 40, 50])
    assert series.phase_deg == (90.0, 90.0)
    assert series.model == "exact"
    assert series.n_joints == 3


def test_paper_inert_extra_phase_is_dropped_with_warning():
    with pytest.warns(sso.InertPhaseWarning, match="phi_3"):
        series = sso.ShaftSeries([15, 20, 9], [30, 40, 50], model="paper")
    assert series.phase_deg == (30.0, 40.0)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"beta_deg": []}, r"beta_deg is empty: a shaft series needs at least 1 joint"),
        ({"beta_deg": [30, 90]}, r"beta_deg\[1\] = 90 is outside the allowed range \[0, 90\) deg"),
        ({"beta_deg": [-1]}, r"beta_deg\[0\] = -1 is outside the allowed range \[0, 90\) deg"),
        ({"beta_deg": [30, math.nan]}, r"beta_deg\[1\] = nan must be finite"),
        ({"beta_deg": [math.inf]}, r"beta_deg\[0\] = inf must be finite"),
        ({"beta_deg": ["thirty"]}, r"beta_deg\[0\] = 'thirty' must be a number"),
        ({"beta_deg": [30, 40], "phase_deg": [90, 90, 90]},
         r"phase_deg has 3 entries; 2 joints need 1"),
        ({"beta_deg": [30, 40], "phase_deg": [math.nan]}, r"phase_deg\[0\] = nan must be finite"),
        ({"beta_deg": [30], "model": "approximate"},
         r"model = 'approximate' is not one of 'exact', 'paper'"),
    ],
)
def test_bad_input_names_field_value_and_range(kwargs, message):
    with pytest.raises(ValueError, match=message):
        sso.ShaftSeries(**kwargs)


def test_with_design_keeps_model():
    series = sso.ShaftSeries([10, 20], [90], model="paper").with_design(beta_deg=[5, 6])
    assert series.beta_deg == (5.0, 6.0)
    assert series.phase_deg == (90.0, 90.0)[:1]
    assert series.model == "paper"


@pytest.mark.parametrize("speed", [0.0, -5.0, math.nan, math.inf])
def test_evaluate_rejects_bad_speed(speed):
    with pytest.raises(ValueError, match="input_speed_rpm"):
        sso.ShaftSeries([20]).evaluate(input_speed_rpm=speed)


def test_non_finite_input_angle_rejected():
    with pytest.raises(ValueError, match="theta_deg contains non-finite"):
        sso.ShaftSeries([20]).speed_ratio([0.0, math.nan])


def test_single_joint_without_phases_is_silent():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert sso.ShaftSeries([20], []).phase_deg == ()
