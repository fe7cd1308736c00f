"""Residual error near 90 deg against an independent high-precision reference.

The reference integrates the joint law ``tan(output) = cos(beta) tan(input)`` with
mpmath at 20 digits more than the narrowest peak's width needs: shaft angles are carried
as angles (not the unit vectors sso carries), and tanh-sinh quadrature is split at every
speed-ratio peak, found by running the joint law backwards from the joint's peak (input
angle at 90 deg). Near 90 deg these peaks are as narrow as ``prod cos beta`` rad, far
below any double-precision grid: the quadrature must then say it has not converged."""

from __future__ import annotations

import warnings

import mpmath
import numpy as np
import pytest

import sso

TOP_ANGLES_DEG = (89.0, 89.9, 89.99)
JOINTS = (2, 3, 4, 5, 6, 7, 8)
RELATIVE_TOLERANCE = 1e-6  # the accuracy target near 90 deg


def _joint_output(cosine, angle):
    """Output angle of one joint, continuous in its input angle (tan out = c tan in)."""
    turns = mpmath.floor(angle / mpmath.pi + mpmath.mpf("0.5"))
    return mpmath.atan(cosine * mpmath.tan(angle - turns * mpmath.pi)) + turns * mpmath.pi


def _joint_input(cosine, output):
    """Inverse of :func:`_joint_output` (modulo 180 deg)."""
    return mpmath.atan2(mpmath.sin(output), cosine * mpmath.cos(output))


def reference_residual_error(beta_deg, phase_deg, model):
    """RE = (1/pi) int_0^pi (w_out/w_in - 1)^2 dtheta, with 20 digits to spare
    beyond the narrowest peak's width."""
    narrowest = float(np.prod(np.cos(np.radians(beta_deg))))
    with mpmath.workdps(20 + int(max(0.0, -np.log10(narrowest)))):
        cosines = [mpmath.cos(mpmath.radians(mpmath.mpf(beta))) for beta in beta_deg]
        cumulative = [mpmath.mpf(0)]
        for phase in phase_deg:
            cumulative.append(cumulative[-1] + mpmath.radians(mpmath.mpf(phase)))

        def ratio(theta):
            shaft = theta
            product = mpmath.mpf(1)
            for cosine, phase in zip(cosines, cumulative, strict=False):
                angle = (shaft if model == "exact" else theta) + phase
                # derivative of the joint law: d out / d in = c / (cos^2 + c^2 sin^2)
                product *= cosine / (mpmath.cos(angle) ** 2 + (cosine * mpmath.sin(angle)) ** 2)
                if model == "exact":
                    shaft = _joint_output(cosine, angle) - phase
            return product

        peaks = set()
        for k in range(len(cosines)):
            shaft = mpmath.pi / 2 - cumulative[k]
            if model == "exact":
                for j in range(k - 1, -1, -1):
                    shaft = _joint_input(cosines[j], shaft + cumulative[j]) - cumulative[j]
            peaks.add(shaft % mpmath.pi)
        points = [mpmath.mpf(0), *sorted(peaks), mpmath.pi]
        value = mpmath.quad(lambda theta: (ratio(theta) - 1) ** 2, points)
        return float(value / mpmath.pi)


def random_chain(rng, joints, top_deg):
    beta_deg = rng.uniform(0.0, top_deg, joints)
    beta_deg[rng.integers(joints)] = top_deg
    return list(beta_deg), list(rng.uniform(0.0, 180.0, joints - 1))


def test_reference_matches_the_single_joint_closed_form():
    # one joint: RE = (1 + c^2) / (2c) - 1 (mean of r^2 minus 2 mean r plus 1, mean r = 1)
    for beta in TOP_ANGLES_DEG:
        c = np.cos(np.radians(beta))
        expected = (1 + c * c) / (2 * c) - 1
        assert reference_residual_error([beta], [], "exact") == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("model", ["exact", "paper"])
@pytest.mark.parametrize("top_deg", TOP_ANGLES_DEG)
def test_residual_error_is_right_or_flagged(model, top_deg):
    rng = np.random.default_rng(int(top_deg * 100) + (0 if model == "exact" else 1))
    converged = 0
    for joints in JOINTS:
        beta_deg, phase_deg = random_chain(rng, joints, top_deg)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = sso.ShaftSeries(beta_deg, phase_deg, model).evaluate()
        flagged = [w for w in caught if issubclass(w.category, sso.QuadratureWarning)]
        if result.quadrature_converged:
            reference = reference_residual_error(beta_deg, phase_deg, model)
            assert result.residual_error == pytest.approx(reference, rel=RELATIVE_TOLERANCE), (
                joints, beta_deg, phase_deg)
            assert not flagged
            converged += 1
        else:
            assert flagged, (joints, beta_deg, phase_deg)
    if top_deg == 89.0 or model == "paper":
        assert converged == len(JOINTS)  # these grids do resolve the peaks


@pytest.mark.parametrize("model", ["exact", "paper"])
def test_aligned_joints_at_the_top_are_never_wrong_and_converged(model):
    # four joints at 89.97 deg (near the largest angle four joints may have, 89.9786 deg:
    # docs/model.md, "Numerical limits"), zero phases: v0.1 gave a mean speed ratio far
    # from 1 (1.6e-9 at 89.99 deg) flagged converged
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = sso.ShaftSeries([89.97] * 4, [0.0] * 3, model).evaluate()
    # paper: every peak is 5.2e-4 rad wide, resolved by the grid; exact: one peak
    # 7.5e-14 rad wide, which no grid resolves, but the exact model needs none (closed form)
    assert result.quadrature_converged and not caught
    reference = reference_residual_error([89.97] * 4, [0.0] * 3, model)
    assert result.residual_error == pytest.approx(reference, rel=RELATIVE_TOLERANCE)


def test_an_optimum_whose_quadrature_did_not_converge_is_not_a_success():
    # two paper-model joints pinned at 89.9999 deg: peaks 1.7e-6 rad wide need about
    # 2.3e6 angles, beyond the cap, so the quadrature cannot vouch for the RE and the
    # run must not claim success however well the solvers agree
    with pytest.warns(sso.QuadratureWarning):  # the optimum is evaluated when first read
        result = sso.optimise(sso.ShaftSeries([89.9999] * 2, [0.0], "paper"), 2,
                              beta_bounds_deg=(89.9999, 89.9999), starts=1)
        assert not result.optimum.quadrature_converged
        assert not result.success
