"""ColumnGeometry against an independent 3D cross-and-yoke simulation and mpmath."""

from __future__ import annotations

import mpmath
import numpy as np
import pytest
from column_cases import load, random_column
from cross_and_yoke import residual_error as simulated_residual_error
from cross_and_yoke import speed_ratio as simulated_speed_ratio

import sso
from sso._column.chain_matrix import residual_error as closed_form_residual_error
from sso._column.geometry import ColumnGeometry
from sso._shafts.quadrature import adaptive_residual_error

mpmath.mp.dps = 40


def _mp_vector(point_a, point_b):
    return [mpmath.mpf(b) - mpmath.mpf(a) for a, b in zip(point_a, point_b, strict=True)]


def _mp_dot(a, b):
    return sum(x * y for x, y in zip(a, b, strict=True))


def _mp_beta_deg(points, joint):
    # Law of cosines on the two shaft vectors at joint `joint`, 40 digits.
    before = _mp_vector(points[joint - 1], points[joint])
    after = _mp_vector(points[joint], points[joint + 1])
    cosine = _mp_dot(before, after) / mpmath.sqrt(_mp_dot(before, before) * _mp_dot(after, after))
    return float(mpmath.degrees(mpmath.acos(cosine)))


def _mp_gamma_deg(points, k):
    # Dihedral angle of P(k-1), P(k), P(k+1), P(k+2) about shaft k: project the shaft
    # before (pointing back) and the shaft after onto the plane normal to shaft k and
    # measure the signed angle between the projections (0 for a U, 180 for a Z).
    axis = _mp_vector(points[k], points[k + 1])
    length = mpmath.sqrt(_mp_dot(axis, axis))
    axis = [x / length for x in axis]
    back = _mp_vector(points[k], points[k - 1])
    ahead = _mp_vector(points[k + 1], points[k + 2])
    back = [x - _mp_dot(back, axis) * a for x, a in zip(back, axis, strict=True)]
    ahead = [x - _mp_dot(ahead, axis) * a for x, a in zip(ahead, axis, strict=True)]
    cross = [back[1] * ahead[2] - back[2] * ahead[1], back[2] * ahead[0] - back[0] * ahead[2],
             back[0] * ahead[1] - back[1] * ahead[0]]
    return float(mpmath.degrees(mpmath.atan2(_mp_dot(cross, axis), _mp_dot(back, ahead))))


@pytest.mark.parametrize("seed", range(12))
def test_speed_ratio_and_re_match_the_3d_simulation(seed):
    # Random non-planar columns of 2..6 joints, random yoke phasings.
    rng = np.random.default_rng(seed)
    joints = 2 + seed % 5
    points = random_column(rng, joints)
    geometry = ColumnGeometry(points)
    yoke = rng.uniform(-180.0, 180.0, joints - 1)
    series = geometry.series(yoke)
    theta_deg = rng.uniform(0.0, 360.0, 40)
    simulated = simulated_speed_ratio(points, yoke, np.radians(theta_deg),
                                      geometry.bend_normals[0])
    np.testing.assert_allclose(series.speed_ratio(theta_deg), simulated, rtol=0, atol=1e-12)
    simulated_re = simulated_residual_error(points, yoke)
    assert series.evaluate().residual_error == pytest.approx(simulated_re, rel=1e-9)
    assert float(closed_form_residual_error(np.radians(series.beta_deg),
                                            np.radians(series.phase_deg))) == pytest.approx(
        simulated_re, rel=1e-9)


def test_the_mirror_phase_relation_is_refuted_by_the_speed_curve_not_by_re():
    # phi' = 90 - delta + gamma is the mirror (phi' = -phi mod 180) of the relation
    # that holds. Mirrored phases give the same RE (theta -> -theta), so only the
    # speed ratio against the input angle tells the two apart: the simulation
    # follows phi = 90 + delta - gamma and not the mirror.
    points = np.asarray(load("truck_three_joints")["points_mm"])
    geometry = ColumnGeometry(points)
    yoke = np.array([25.0, -40.0])
    gamma = np.asarray(geometry.plane_angle_deg)
    mirror = sso.ShaftSeries(geometry.beta_deg, np.mod(90.0 - yoke + gamma, 180.0))
    theta_deg = np.linspace(0.0, 180.0, 19)
    simulated = simulated_speed_ratio(points, yoke, np.radians(theta_deg), geometry.bend_normals[0])
    np.testing.assert_allclose(geometry.series(yoke).speed_ratio(theta_deg), simulated, atol=1e-12)
    assert np.max(np.abs(mirror.speed_ratio(theta_deg) - simulated)) > 1e-3
    assert mirror.evaluate().residual_error == pytest.approx(
        simulated_residual_error(points, yoke), rel=1e-9)


@pytest.mark.parametrize("seed", range(6))
def test_beta_and_gamma_match_an_independent_mpmath_computation(seed):
    rng = np.random.default_rng(100 + seed)
    points = random_column(rng, 2 + seed, beta_range_deg=(0.5, 80.0))
    geometry = ColumnGeometry(points)
    expected_beta = [_mp_beta_deg(points, joint) for joint in range(1, geometry.joint_count + 1)]
    expected_gamma = [_mp_gamma_deg(points, k) for k in range(1, geometry.joint_count)]
    np.testing.assert_allclose(geometry.beta_deg, expected_beta, rtol=0, atol=1e-9)
    np.testing.assert_allclose(geometry.plane_angle_deg, expected_gamma, rtol=0, atol=1e-9)


def test_example_columns_have_their_stated_angles():
    # tests/data/columns/*.json descriptions.
    truck = ColumnGeometry(load("truck_three_joints")["points_mm"])
    np.testing.assert_allclose(truck.beta_deg, [9.2, 13.3, 19.9], atol=0.05)
    np.testing.assert_allclose(truck.plane_angle_deg, [100.0, 100.0], atol=0.05)
    car = ColumnGeometry(load("car_intermediate_shaft")["points_mm"])
    np.testing.assert_allclose(car.beta_deg, [24.0, 24.5], atol=0.05)
    np.testing.assert_allclose(car.plane_angle_deg, [35.0], atol=0.1)
    assert car.shaft_length_mm == pytest.approx((320.0, 260.0, 120.0), abs=0.1)
    assert truck.joint_count == 3


def test_planar_u_and_z_columns():
    # U: both bends the same way, gamma = 0; Z: opposite ways, gamma = 180.
    u_column = ColumnGeometry([[-300, 100, 0], [0, 0, 0], [300, 0, 0], [600, 100, 0]])
    z_column = ColumnGeometry([[-300, 100, 0], [0, 0, 0], [300, 0, 0], [600, -100, 0]])
    assert u_column.plane_angle_deg == pytest.approx((0.0,), abs=1e-12)
    assert abs(z_column.plane_angle_deg[0]) == pytest.approx(180.0, abs=1e-12)
    beta = np.degrees(np.arctan2(100.0, 300.0))
    assert u_column.beta_deg == pytest.approx((beta, beta), abs=1e-12)
    # Planar: phi = 90 + delta (mod 180) for both, the planar textbook reading.
    assert u_column.phase_deg_from_yoke([0.0]) == pytest.approx((90.0,), abs=1e-12)
    assert z_column.phase_deg_from_yoke([0.0]) == pytest.approx((90.0,), abs=1e-12)


def test_mirror_assembly_has_the_same_re_in_the_3d_simulation():
    points = np.asarray(load("truck_three_joints")["points_mm"])
    geometry = ColumnGeometry(points)
    yoke = (25.0, -40.0)
    mirror = geometry.mirror_yoke_phase_deg(yoke)
    gamma = np.asarray(geometry.plane_angle_deg)
    np.testing.assert_allclose(np.mod(np.subtract(mirror, 2 * gamma - yoke) + 90, 180) - 90, 0,
                               atol=1e-12)
    assert simulated_residual_error(points, mirror) == pytest.approx(
        simulated_residual_error(points, yoke), rel=1e-12)
    np.testing.assert_allclose(np.add(geometry.phase_deg_from_yoke(mirror),
                                      geometry.phase_deg_from_yoke(yoke)) % 180.0, 0.0, atol=1e-9)


def test_planar_z_gives_plus_180_even_with_round_off():
    # A planar Z turned into random orientations: round-off leaves the sine of gamma
    # a few ulp either side of zero, which atan2 would turn into +-180. The angle
    # stays +180, the top of the documented range (-180, 180].
    from scipy.spatial.transform import Rotation

    z_points = np.array([[-300, 100, 0], [0, 0, 0], [300, 0, 0], [600, -100, 0]], dtype=float)
    for seed in range(12):
        turned = Rotation.random(random_state=seed).apply(z_points)
        assert ColumnGeometry(turned).plane_angle_deg[0] == pytest.approx(180.0, abs=1e-12)


def test_phase_and_yoke_converters_are_inverse_mod_180():
    geometry = ColumnGeometry(load("truck_three_joints")["points_mm"])
    yoke = (33.0, -71.5)
    phase = geometry.phase_deg_from_yoke(yoke)
    gamma = geometry.plane_angle_deg
    np.testing.assert_allclose(phase, np.mod(90.0 + np.array(yoke) - gamma, 180.0), atol=1e-12)
    np.testing.assert_allclose(geometry.yoke_phase_deg_from_phase(phase), yoke, atol=1e-12)
    assert all(-90.0 <= value < 90.0 for value in geometry.yoke_phase_deg_from_phase([5.0, 175.0]))


def test_straight_joint_borrows_a_plane_and_the_motion_does_not_depend_on_it():
    # Joint 2 straight: P1, P2, P3 collinear. Its borrowed plane is joint 1's.
    rng = np.random.default_rng(7)
    points = random_column(rng, 4)
    points[3] = points[2] + 0.8 * (points[2] - points[1])
    geometry = ColumnGeometry(points)
    assert geometry.straight_joints == (False, True, False, False)
    assert geometry.beta_deg[1] == 0.0
    np.testing.assert_allclose(geometry.bend_normals[1], geometry.bend_normals[0], atol=1e-12)
    assert geometry.plane_angle_deg[0] == pytest.approx(0.0, abs=1e-12)
    yoke = rng.uniform(-90.0, 90.0, 3)
    re_model = geometry.series(yoke).evaluate().residual_error
    assert re_model == pytest.approx(simulated_residual_error(points, yoke), rel=1e-9)
    # Any other plane for the straight joint: gamma_1 and gamma_2 change by opposite
    # amounts, phi_1 + phi_2 stays, so RE stays.
    for turn_deg in (17.0, 95.0, -130.0):
        gamma = np.array(geometry.plane_angle_deg)
        gamma[0] += turn_deg
        gamma[1] -= turn_deg
        phase = np.mod(90.0 + yoke - gamma, 180.0)
        other = sso.ShaftSeries(geometry.beta_deg, phase)
        assert other.evaluate().residual_error == pytest.approx(re_model, rel=1e-12)


def test_leading_straight_joint_borrows_the_plane_downstream():
    rng = np.random.default_rng(8)
    points = random_column(rng, 3)
    points[0] = points[1] - 0.5 * (points[2] - points[1])
    geometry = ColumnGeometry(points)
    assert geometry.straight_joints[0]
    np.testing.assert_allclose(geometry.bend_normals[0], geometry.bend_normals[1], atol=1e-12)
    yoke = [10.0, 50.0]
    theta = np.linspace(0.0, 360.0, 13)
    np.testing.assert_allclose(
        geometry.series(yoke).speed_ratio(theta),
        simulated_speed_ratio(points, yoke, np.radians(theta), geometry.bend_normals[0]),
        atol=1e-12)


@pytest.mark.parametrize("points, message", [
    ([[0, 0, 0], [1, 0, 0]], "at least 3"),
    ([[0, 0, 0], [1, 0], [1, 1, 0]], r"points_mm\[1\]"),
    ([[0, 0, 0], [1, 0, 0], [1, float("nan"), 0]], r"points_mm\[2\]\[1\]"),
    ([[0, 0, 0], [1, 0, 0], [1, float("inf"), 0]], "finite"),
    ([[0, 0, 0], [100, 0, 0], [100, 0, 0], [200, 50, 0]],
     r"points_mm\[1\] and points_mm\[2\] coincide"),
    ([[0, 0, 0], [100, 0, 0], [200, 0, 0], [300, 0, 0]], "collinear"),
    ([[0, 0, 0], [100, 0, 0], [100, 100, 0]], r"points_mm\[1\]: joint 1 bends by beta = 90 deg"),
    ([[0, 0, 0], [100, 0, 0], [0, 10, 0]], r"joint 1 .*outside the allowed range \[0, 90\)"),
])
def test_bad_points_are_refused_naming_the_point(points, message):
    with pytest.raises(ValueError, match=message):
        ColumnGeometry(points)


@pytest.mark.parametrize("points", ["points", 5, None])
def test_points_that_are_not_a_list_are_a_type_error(points):
    with pytest.raises(TypeError, match="points_mm = .* must be a list of"):
        ColumnGeometry(points)


def test_phasing_with_the_wrong_count_is_refused():
    geometry = ColumnGeometry(load("truck_three_joints")["points_mm"])
    with pytest.raises(ValueError,
                       match="yoke_phase_deg has 1 entries; a column of 3 joints has 2"):
        geometry.series([10.0])
    with pytest.raises(ValueError, match=r"phase_deg\[1\]"):
        geometry.yoke_phase_deg_from_phase([10.0, float("nan")])


def test_closed_form_matches_the_package_quadrature():
    # Reference: the package's adaptive rectangle rule over the angle-by-angle chain
    # (sso._shafts.quadrature with sso._kinematics.hooke), which never forms the chain matrix.
    rng = np.random.default_rng(11)
    beta = rng.uniform(0.0, 60.0, (40, 4))
    phase = rng.uniform(0.0, 180.0, (40, 3))
    closed = closed_form_residual_error(np.radians(beta[0]), np.radians(phase[:1]))
    assert closed.shape == (1,)
    for row_beta, row_phase in zip(beta, phase, strict=True):
        expected, rule = adaptive_residual_error(list(np.radians(row_beta)),
                                                 list(np.radians(row_phase)), "exact",
                                                 rtol=1e-13, atol=1e-300)
        assert rule.converged
        got = float(closed_form_residual_error(np.radians(row_beta), np.radians(row_phase)))
        assert got == pytest.approx(expected, rel=1e-9)
