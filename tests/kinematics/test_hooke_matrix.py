"""The closed form of the exact chain against independent formulations.

References: the adaptive quadrature of the angle-by-angle chain (``sso._shafts.quadrature``,
``sso._kinematics.hooke``); an mpmath high-precision quadrature of the per-joint angle
law (paper eq. 5 and 8, no matrices) split at every joint's speed peak; complex-step
derivatives; the one-joint extremes ``cos b`` and ``1/cos b`` of the spec
("Checks with known answers").
"""

import math

import casadi
import mpmath
import numpy as np
import pytest

from sso._kinematics import hooke, hooke_matrix
from sso._shafts.quadrature import EVALUATION_MAX_SAMPLES, adaptive_residual_error

RNG_SEED = 20261123


def random_chain(rng, n_joints, beta_max_deg=70.0):
    beta_rad = np.radians(rng.uniform(0.0, beta_max_deg, n_joints))
    phase_rad = np.radians(rng.uniform(-180.0, 360.0, n_joints - 1))
    return beta_rad, phase_rad


def test_closed_form_matches_the_quadrature_of_the_angle_chain():
    # Reference: the adaptive rectangle rule over the angle-by-angle chain
    # (sso._shafts.quadrature with sso._kinematics.hooke, no chain matrix), and the speed
    # ratio's extremes read off a dense grid of that chain, refined by a golden-section
    # search around the grid's best angle.
    rng = np.random.default_rng(RNG_SEED)
    for _ in range(60):
        n_joints = int(rng.integers(1, 9))
        beta_rad, phase_rad = random_chain(rng, n_joints)
        expected, rule = adaptive_residual_error(list(beta_rad), list(phase_rad), "exact",
                                                 rtol=1e-14, atol=1e-300,
                                                 max_samples=EVALUATION_MAX_SAMPLES)
        assert rule.converged
        error = hooke_matrix.residual_error(np, list(beta_rad), list(phase_rad))
        least, greatest = hooke_matrix.ratio_extremes(np, list(beta_rad), list(phase_rad))
        assert error == pytest.approx(expected, rel=1e-10, abs=1e-300)
        assert least == pytest.approx(_angle_chain_extreme(beta_rad, phase_rad, -1.0), rel=1e-10)
        assert greatest == pytest.approx(_angle_chain_extreme(beta_rad, phase_rad, 1.0),
                                         rel=1e-10)


def _angle_chain_ratio(theta_rad, beta_rad, phase_rad):
    """Speed ratio of the angle-by-angle chain (sso._kinematics.hooke), no chain matrix."""
    theta_rad = np.asarray(theta_rad, dtype=float)
    return hooke.speed_ratio(np, np.cos(theta_rad), np.sin(theta_rad), list(beta_rad),
                             list(phase_rad), "exact")


def _angle_chain_extreme(beta_rad, phase_rad, sign):
    """Largest (sign 1) or least (sign -1) speed ratio over a revolution of the angle chain."""
    grid = np.linspace(0.0, np.pi, 4097)
    values = sign * _angle_chain_ratio(grid, beta_rad, phase_rad)
    best = int(np.argmax(values))
    step = grid[1] - grid[0]
    low, high = grid[best] - step, grid[best] + step
    golden = (math.sqrt(5.0) - 1.0) / 2.0
    for _ in range(80):
        left, right = high - golden * (high - low), low + golden * (high - low)
        if (sign * _angle_chain_ratio([left], beta_rad, phase_rad)[0]
                >= sign * _angle_chain_ratio([right], beta_rad, phase_rad)[0]):
            high = right
        else:
            low = left
    return float(_angle_chain_ratio([0.5 * (low + high)], beta_rad, phase_rad)[0])


def test_speed_ratio_matches_the_angle_chain_at_every_angle():
    # Reference: the angle-by-angle chain of sso._kinematics.hooke (each joint's angle
    # law applied in turn), which never forms the chain matrix.
    rng = np.random.default_rng(RNG_SEED + 1)
    theta_deg = np.linspace(0.0, 360.0, 73)
    for n_joints in range(1, 9):
        beta_rad, phase_rad = random_chain(rng, n_joints, 85.0)
        theta_rad = np.radians(theta_deg)
        ratio = hooke_matrix.speed_ratio(np, np.cos(theta_rad), np.sin(theta_rad),
                                         list(beta_rad), list(phase_rad))
        np.testing.assert_allclose(ratio, _angle_chain_ratio(theta_rad, beta_rad, phase_rad),
                                   rtol=1e-10)


def _mpmath_residual_error(beta_rad, phase_rad, digits=40):
    """RE by tanh-sinh quadrature of the angle law, split where each joint peaks.

    Joint k's ratio ``cos b / (1 - sin^2 b sin^2 a_k)`` peaks where its driving
    angle ``a_k`` is 90 deg; that input angle is found by inverting the upstream
    joints (``tan a = tan g / cos b``), so every peak sits at an interval end,
    where tanh-sinh nodes cluster.
    """
    with mpmath.workdps(digits):
        beta = [mpmath.mpf(float(value)) for value in beta_rad]
        cumulative = [mpmath.mpf(0)]
        for value in phase_rad:
            cumulative.append(cumulative[-1] + mpmath.mpf(float(value)))
        cosines = [mpmath.cos(value) for value in beta]

        def ratio(theta):
            psi, product = theta, mpmath.mpf(1)
            for k, cosine in enumerate(cosines):
                driving = psi + cumulative[k]
                product *= cosine / (1 - mpmath.sin(beta[k]) ** 2 * mpmath.sin(driving) ** 2)
                psi = (mpmath.atan2(cosine * mpmath.sin(driving), mpmath.cos(driving))
                       - cumulative[k])
            return product

        peaks = []
        for k in range(len(beta)):
            psi = mpmath.pi / 2 - cumulative[k]
            for j in range(k - 1, -1, -1):
                output = psi + cumulative[j]
                psi = (mpmath.atan2(mpmath.sin(output), cosines[j] * mpmath.cos(output))
                       - cumulative[j])
            peaks.append(psi % mpmath.pi)
        points = sorted({mpmath.mpf(0), mpmath.pi, *peaks})
        value, error = mpmath.quad(lambda theta: (ratio(theta) - 1) ** 2, points, error=True,
                                   maxdegree=10)
        assert error < 1e-12 * value
        return float(value / mpmath.pi)


@pytest.mark.parametrize("n_joints, top_deg, all_at_top", [
    (2, 89.99, True), (3, 89.9, False), (5, 89.99, False), (8, 89.0, False),
])
def test_closed_form_near_90_deg_matches_high_precision_quadrature(n_joints, top_deg,
                                                                   all_at_top):
    rng = np.random.default_rng(RNG_SEED + n_joints)
    beta_deg = np.full(n_joints, top_deg) if all_at_top else rng.uniform(0, top_deg, n_joints)
    beta_deg[rng.integers(n_joints)] = top_deg
    beta_rad = np.radians(beta_deg)
    phase_rad = np.radians(rng.uniform(0.0, 180.0, n_joints - 1))
    reference = _mpmath_residual_error(beta_rad, phase_rad)
    error = hooke_matrix.residual_error(np, list(beta_rad), list(phase_rad))
    assert error == pytest.approx(reference, rel=1e-12)


def test_mean_speed_ratio_is_one():
    # The output turns once per input turn. The rectangle rule is exact to
    # round-off for this periodic integrand at 4096 angles (largest angle 60 deg).
    rng = np.random.default_rng(RNG_SEED + 2)
    theta_rad = np.pi * np.arange(4096) / 4096
    for n_joints in range(1, 9):
        beta_rad, phase_rad = random_chain(rng, n_joints, 60.0)
        ratio = hooke_matrix.speed_ratio(np, np.cos(theta_rad), np.sin(theta_rad),
                                         list(beta_rad), list(phase_rad))
        assert np.mean(ratio) == pytest.approx(1.0, abs=1e-13)


@pytest.mark.parametrize("beta_deg", [5.0, 30.0, 60.0, 89.0])
def test_one_joint_extremes(beta_deg):
    cosine = np.cos(np.radians(beta_deg))
    least, greatest = hooke_matrix.ratio_extremes(np, [np.radians(beta_deg)], [])
    assert least == pytest.approx(cosine, rel=1e-14)
    assert greatest == pytest.approx(1 / cosine, rel=1e-14)


def test_equal_joints_at_90_deg_phase_cancel():
    # spec: two equal joints with phi = 90 deg give ratio 1 at every angle.
    error = hooke_matrix.residual_error(np, [np.radians(30.0)] * 2, [np.pi / 2])
    assert error < 1e-30
    assert hooke_matrix.residual_error(np, [np.radians(30.0)] * 2, [0.0]) > 1e-3


def test_jacobian_matches_complex_step():
    rng = np.random.default_rng(RNG_SEED + 3)
    step = 1e-30
    for n_joints in range(1, 9):
        beta_rad, phase_rad = random_chain(rng, n_joints, 80.0)
        residual, jacobian = hooke_matrix.residuals_and_jacobian_numpy(beta_rad, phase_rad)
        x = np.concatenate([beta_rad, phase_rad]).astype(complex)
        for column in range(x.size):
            shifted = x.copy()
            shifted[column] += 1j * step
            values = hooke_matrix.residuals(np, list(shifted[:n_joints]),
                                            list(shifted[n_joints:]))
            expected = np.array([value.imag / step for value in values])
            np.testing.assert_allclose(jacobian[:, column], expected, rtol=1e-12, atol=1e-13)
        np.testing.assert_allclose(residual, np.real(hooke_matrix.residuals(
            np, list(beta_rad), list(phase_rad))), rtol=0, atol=0)


def test_batched_designs_match_one_at_a_time():
    rng = np.random.default_rng(RNG_SEED + 4)
    beta_rad = np.radians(rng.uniform(0.0, 60.0, (7, 4)))
    phase_rad = np.radians(rng.uniform(0.0, 180.0, (7, 3)))
    residual, jacobian = hooke_matrix.residuals_and_jacobian_numpy(beta_rad, phase_rad)
    assert residual.shape == (7, 2) and jacobian.shape == (7, 2, 7)
    for row in range(7):
        one_residual, one_jacobian = hooke_matrix.residuals_and_jacobian_numpy(
            beta_rad[row], phase_rad[row])
        np.testing.assert_allclose(residual[row], one_residual, rtol=1e-15, atol=1e-16)
        np.testing.assert_allclose(jacobian[row], one_jacobian, rtol=1e-15, atol=1e-16)


def test_numpy_and_casadi_paths_agree():
    rng = np.random.default_rng(RNG_SEED + 5)
    n_joints = 5
    beta_rad, phase_rad = random_chain(rng, n_joints, 80.0)
    beta = casadi.SX.sym("beta", n_joints)
    phase = casadi.SX.sym("phase", n_joints - 1)
    beta_list = [beta[k] for k in range(n_joints)]
    phase_list = [phase[k] for k in range(n_joints - 1)]
    residual, d_beta, d_phase = hooke_matrix.residual_jacobian(casadi, beta_list, phase_list)
    least, greatest = hooke_matrix.ratio_extremes(casadi, beta_list, phase_list)
    outputs = casadi.vertcat(*residual, *[value for pair in (*d_beta, *d_phase) for value in pair],
                             hooke_matrix.residual_error(casadi, beta_list, phase_list),
                             least, greatest)
    function = casadi.Function("closed_form", [beta, phase], [outputs])
    symbolic = np.array(function(beta_rad, phase_rad)).ravel()
    numeric_residual, numeric_jacobian = hooke_matrix.residuals_and_jacobian_numpy(beta_rad,
                                                                                   phase_rad)
    numeric_least, numeric_greatest = hooke_matrix.ratio_extremes(np, list(beta_rad),
                                                                  list(phase_rad))
    expected = np.concatenate([
        numeric_residual, numeric_jacobian.T.ravel(),
        [hooke_matrix.residual_error(np, list(beta_rad), list(phase_rad)),
         numeric_least, numeric_greatest]])
    np.testing.assert_allclose(symbolic, expected, rtol=1e-13, atol=1e-15)
    # CasADi's own derivative of the residual graph agrees with the hand-written one.
    automatic = casadi.Function("jacobian", [beta, phase], [casadi.jacobian(
        casadi.vertcat(*residual), casadi.vertcat(beta, phase))])
    np.testing.assert_allclose(np.array(automatic(beta_rad, phase_rad)), numeric_jacobian,
                               rtol=1e-12, atol=1e-14)


def test_phase_count_and_empty_chain_are_refused():
    with pytest.raises(ValueError, match="phase_rad has 2 entries; 2 joints need 1"):
        hooke_matrix.chain_matrix(np, [0.1, 0.2], [0.3, 0.4])
    with pytest.raises(ValueError, match="beta_rad is empty"):
        hooke_matrix.chain_matrix(np, [], [])


def test_complex_float_jacobian_matches_complex_step():
    # The plain-complex path (used by the single-design least-squares solver and the
    # exact model's shared optimality measure) against complex-step derivatives of
    # the numpy residuals, 1 to 12 joints up to 85 deg.
    rng = np.random.default_rng(RNG_SEED + 7)
    step = 1e-30
    for n_joints in range(1, 13):
        beta_rad, phase_rad = random_chain(rng, n_joints, 85.0)
        rho, jacobian = hooke_matrix.residual_and_jacobian_complex(list(beta_rad),
                                                                   list(phase_rad))
        assert len(jacobian) == 2 * n_joints - 1
        expected_residual = hooke_matrix.residuals(np, list(beta_rad), list(phase_rad))
        # rho = r1 - i r2
        np.testing.assert_allclose([rho.real, -rho.imag], expected_residual, rtol=1e-14,
                                   atol=1e-15)
        x = np.concatenate([beta_rad, phase_rad]).astype(complex)
        for column in range(x.size):
            shifted = x.copy()
            shifted[column] += 1j * step
            values = hooke_matrix.residuals(np, list(shifted[:n_joints]),
                                            list(shifted[n_joints:]))
            np.testing.assert_allclose([jacobian[column].real, -jacobian[column].imag],
                                       [value.imag / step for value in values],
                                       rtol=1e-12, atol=1e-13)


def test_complex_float_jacobian_returns_the_requested_columns():
    rng = np.random.default_rng(RNG_SEED + 8)
    beta_rad, phase_rad = random_chain(rng, 4, 60.0)
    rho, full = hooke_matrix.residual_and_jacobian_complex(list(beta_rad), list(phase_rad))
    rho_beta, beta_only = hooke_matrix.residual_and_jacobian_complex(
        list(beta_rad), list(phase_rad), phase_free=False)
    rho_phase, phase_only = hooke_matrix.residual_and_jacobian_complex(
        list(beta_rad), list(phase_rad), beta_free=False)
    assert rho_beta == rho_phase == rho
    assert beta_only == full[:4]
    assert phase_only == full[4:]


@pytest.mark.parametrize("beta_free, phase_free", [(True, True), (True, False), (False, True)])
def test_closed_form_hessian_matches_casadi_symbolic_hessian(beta_free, phase_free):
    # The chain-rule Hessian of RE = |rho|^2 (prefix and suffix maps of the factors)
    # against CasADi's symbolic Hessian of r1^2 + r2^2 from the matrix residuals, an
    # independent differentiation; 1 to 7 joints up to 85 deg, each set of free angles.
    # docs/model.md quotes the agreement: 2e-15 of the largest entry (measured 1.5e-15).
    rng = np.random.default_rng(RNG_SEED + 9)
    for n_joints in range(1 if beta_free else 2, 8):
        beta_rad, phase_rad = random_chain(rng, n_joints, 85.0)
        rho, jacobian, hessian = hooke_matrix.residual_hessian_complex(
            list(beta_rad), list(phase_rad), beta_free=beta_free, phase_free=phase_free)
        expected_rho, expected_jacobian = hooke_matrix.residual_and_jacobian_complex(
            list(beta_rad), list(phase_rad), beta_free=beta_free, phase_free=phase_free)
        assert abs(rho - expected_rho) <= 1e-14 * max(1.0, abs(rho))
        np.testing.assert_allclose(jacobian, expected_jacobian, rtol=1e-12, atol=1e-14)
        beta = casadi.SX.sym("beta", n_joints)
        phase = casadi.SX.sym("phase", n_joints - 1)
        first, second = hooke_matrix.residuals(casadi, [beta[k] for k in range(n_joints)],
                                               [phase[k] for k in range(n_joints - 1)])
        free = casadi.vertcat(*([beta] if beta_free else []), *([phase] if phase_free else []))
        symbolic = casadi.Function("hessian", [beta, phase],
                                   [casadi.hessian(first**2 + second**2, free)[0]])
        expected = symbolic(beta_rad, phase_rad).full()
        assert np.array(hessian).shape == expected.shape
        np.testing.assert_allclose(hessian, expected, rtol=1e-11,
                                   atol=1e-12 * max(1.0, np.abs(expected).max()))
        assert np.abs(np.array(hessian) - expected).max() <= 2e-15 * np.abs(expected).max()


def test_peak_slope_and_lag_swing_hold_full_precision_near_ninety_degrees():
    # Non-aligned chains of 2 to 6 joints whose angles lie within 1 deg below 89,
    # 89.9 and 89.99 deg: the closed forms against the same formulas evaluated in
    # 50-digit arithmetic (mpmath). det M is the product of the cosines and the
    # swing is atan2(|b|, sqrt(det M)); taking det M from the entries, or asin |b/a|,
    # loses up to 1e-8 relative here.
    class Precise:
        cos = staticmethod(mpmath.cos)
        sin = staticmethod(mpmath.sin)
        sqrt = staticmethod(mpmath.sqrt)

    rng = np.random.default_rng(RNG_SEED + 9)
    for top in (89.0, 89.9, 89.99):
        for _ in range(10):
            n_joints = int(rng.integers(2, 7))
            beta = list(np.radians(rng.uniform(top - 1.0, top, n_joints)))
            phase = list(np.radians(rng.uniform(-180.0, 180.0, n_joints - 1)))
            with mpmath.workdps(50):
                precise_beta = [mpmath.mpf(value) for value in beta]
                precise_phase = [mpmath.mpf(value) for value in phase]
                slope = float(hooke_matrix.peak_ratio_slope(Precise, precise_beta,
                                                            precise_phase))
                m11, m12, m21, m22 = hooke_matrix.chain_matrix(Precise, precise_beta,
                                                               precise_phase)
                swing = float(mpmath.asin(abs(mpmath.mpc(m11 - m22, m21 + m12))
                                          / abs(mpmath.mpc(m11 + m22, m21 - m12))))
            assert hooke_matrix.peak_ratio_slope(math, beta, phase) == pytest.approx(
                slope, rel=1e-12)
            assert hooke_matrix.lag_swing(beta, phase)[1] == pytest.approx(swing, rel=1e-12)
