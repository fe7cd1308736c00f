"""Adaptive quadrature of the residual error (docs/model.md, "The objective")."""

import warnings

import numpy as np
import pytest

import sso
from sso._shafts.objective import residual_error
from sso._shafts.quadrature import adaptive_residual_error, rule_for_bounds


@pytest.mark.parametrize("model", ["exact", "paper"])
def test_bounds_up_to_forty_degrees_need_at_most_64_angles(model):
    # docs/model.md: for beta <= 40 deg, N = 32 is already at round-off (the paper's 3 joints)
    for joints in (1, 2, 3):
        rule = rule_for_bounds(list(np.radians([40.0] * joints)), model)
        assert rule.samples <= 64
        assert rule.converged


def test_many_aligned_joints_act_as_one_large_joint():
    # six joints at 40 deg with zero phases act as one joint with cos B = cos(40)^6,
    # B = 78.4 deg, which needs more angles than one 40-deg joint
    six = rule_for_bounds(list(np.radians([40.0] * 6)), "exact")
    single = rule_for_bounds([np.arccos(np.cos(np.radians(40.0)) ** 6)], "exact")
    assert six.samples == single.samples == 128


def test_near_ninety_degrees_gets_more_angles_and_says_so():
    rule = rule_for_bounds([np.radians(85.0)], "exact")
    assert rule.samples >= 128
    assert rule.converged
    _, strict = adaptive_residual_error([np.radians(89.0)], [], "exact")
    assert strict.samples >= 512


def test_error_estimate_bounds_the_true_error():
    beta = list(np.radians([60.0, 45.0, 70.0]))
    phase = list(np.radians([30.0, 100.0]))
    value, rule = adaptive_residual_error(beta, phase, "exact", rtol=1e-8, atol=0.0)
    reference = residual_error(beta, phase, "exact", 16384)
    assert abs(value - reference) <= rule.error_estimate * 1.01 + 1e-16
    assert abs(value - reference) <= 1e-8 * reference


def test_cap_reached_warns_and_marks_unconverged():
    # one 85-deg joint: peak half-width atanh(cos 85 deg) = 0.0874 rad, resolved from
    # 4 / 0.0874 = 46 -> 64 angles, but 1e-10 needs more than 64
    with pytest.warns(sso.QuadratureWarning, match="cap of"):
        _, rule = adaptive_residual_error([np.radians(85.0)], [], "exact", max_samples=64)
    assert not rule.converged
    assert rule.samples == 64


def test_unresolvable_peaks_warn_and_mark_unconverged():
    # three aligned 85-deg joints act as one joint with cos B = cos(85)^3 = 6.6e-4:
    # 4 / atanh(6.6e-4) = 6040 angles resolve its peak, above a cap of 1024
    with pytest.warns(sso.QuadratureWarning, match="cannot resolve"):
        _, rule = adaptive_residual_error(list(np.radians([85.0, 85.0, 85.0])), [0.0, 0.0],
                                          "exact", max_samples=1024)
    assert not rule.converged
    assert rule.samples == 1024


def test_straight_shafts_need_the_minimum():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        value, rule = adaptive_residual_error([0.0, 0.0], [0.0], "exact")
    assert value == 0.0
    assert rule.samples == 8
