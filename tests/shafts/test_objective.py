"""The residual error RE against closed forms derived independently of the code.

One joint: the speed ratio is r = c / (1 - s^2 sin^2 t) with c = cos b, s = sin b.
With the standard integrals (1/pi) int_0^pi dt / (1 - k sin^2 t) = 1 / sqrt(1 - k) and
(1/pi) int_0^pi dt / (1 - k sin^2 t)^2 = (2 - k) / (2 (1 - k)^(3/2)), k = s^2:
RE = c^2 (1 + c^2) / (2 c^3) - 2 + 1 = (1 - c)^2 / (2 c).
Two joints in phase (phi = 0): tan t_out = tan t_in / c twice, so they act as one
joint with cos b_eq = c^2. Two equal joints at phi = 90 deg cancel exactly (exact model).
"""

from __future__ import annotations

import math

import casadi
import mpmath
import numpy as np
import pytest

from sso._shafts.objective import angle_grid, residual_error, squared_ratio_error


def closed_form_one_joint(beta_rad: float) -> float:
    c = math.cos(beta_rad)
    return (1.0 - c) ** 2 / (2.0 * c)


@pytest.mark.parametrize("beta_deg", [5.0, 30.0, 45.0, 60.0])
def test_one_joint_matches_the_closed_form(beta_deg):
    beta = math.radians(beta_deg)
    assert residual_error([beta], [], "exact", 256) == pytest.approx(
        closed_form_one_joint(beta), rel=1e-13
    )


def test_closed_form_agrees_with_mpmath_quadrature():
    """A check of the derivation itself, at 30 digits."""
    with mpmath.workdps(30):
        beta = mpmath.pi / 6
        integral = (
            mpmath.quad(
                lambda t: (
                    (mpmath.cos(beta) / (1 - mpmath.sin(beta) ** 2 * mpmath.sin(t) ** 2) - 1) ** 2
                ),
                [0, mpmath.pi],
            )
            / mpmath.pi
        )
    assert float(integral) == pytest.approx(closed_form_one_joint(math.pi / 6), rel=1e-15)


def test_rectangle_rule_converges_geometrically():
    beta = math.radians(40.0)
    exact = closed_form_one_joint(beta)
    errors = [
        abs(residual_error([beta], [], "exact", samples) - exact) / exact for samples in (4, 8, 16)
    ]
    assert errors[0] > 1e-3 and errors[1] < errors[0] / 10 and errors[2] < errors[1] / 100


def test_two_joints_in_phase_act_as_one_with_cos_squared():
    beta = math.radians(30.0)
    equivalent = math.acos(math.cos(beta) ** 2)
    assert residual_error([beta, beta], [0.0], "exact", 256) == pytest.approx(
        closed_form_one_joint(equivalent), rel=1e-12
    )


def test_two_equal_joints_at_ninety_degrees_cancel():
    beta = math.radians(30.0)
    assert residual_error([beta, beta], [math.pi / 2], "exact", 64) < 1e-30


def test_many_designs_at_once_equal_one_at_a_time():
    betas = np.radians([[10.0], [25.0], [50.0]])
    together = residual_error([betas, betas], [np.zeros((3, 1))], "exact", 128)
    one_by_one = [residual_error([b, b], [0.0], "exact", 128) for b in betas[:, 0]]
    np.testing.assert_allclose(together, one_by_one, rtol=1e-14)


def test_angle_grid_covers_half_a_turn_without_its_end():
    cos_theta, sin_theta = angle_grid(4)
    np.testing.assert_allclose(
        np.arctan2(sin_theta, cos_theta), np.pi * np.arange(4) / 4, atol=1e-15
    )


def test_numpy_and_casadi_give_the_same_integrand():
    cos_theta, sin_theta = angle_grid(16)
    beta, phase = [0.3, 0.5, 0.2], [1.2, 0.4]
    numeric = squared_ratio_error(np, cos_theta, sin_theta, beta, phase, "paper")
    symbolic = squared_ratio_error(
        casadi, casadi.DM(cos_theta), casadi.DM(sin_theta), beta, phase, "paper"
    )
    np.testing.assert_allclose(np.array(symbolic).ravel(), numeric, rtol=1e-13, atol=1e-18)
