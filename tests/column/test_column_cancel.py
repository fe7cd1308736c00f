"""sso._column.cancel: the cancellation rule and closed forms against brute-force phasing."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from sso._column.cancel import can_cancel, cancelling_phases_deg, minimising_phases_deg
from sso._column.chain_matrix import residual_error


def _polish(beta_rad: np.ndarray, phase_rad: np.ndarray, iterations: int = 30) -> np.ndarray:
    """Damped Newton on RE for every row at once (central-difference gradient and
    Hessian); returns the RE reached by each row. ``beta_rad`` has a row per phase row."""
    phase = phase_rad.copy()
    count = phase.shape[1]
    damping = np.full(len(phase), 1e-6)
    gradient_step, hessian_step = 1e-6, 1e-4
    unit = np.eye(count)

    def objective(rows: np.ndarray) -> np.ndarray:
        return residual_error(beta_rad, rows)

    for _ in range(iterations):
        value = objective(phase)
        gradient = np.stack([(objective(phase + gradient_step * unit[i])
                              - objective(phase - gradient_step * unit[i])) / (2 * gradient_step)
                             for i in range(count)], axis=-1)
        hessian = np.empty((len(phase), count, count))
        for i in range(count):
            for j in range(count):
                shift_i, shift_j = hessian_step * unit[i], hessian_step * unit[j]
                hessian[:, i, j] = (objective(phase + shift_i + shift_j)
                                    - objective(phase + shift_i - shift_j)
                                    - objective(phase - shift_i + shift_j)
                                    + objective(phase - shift_i - shift_j)) / (4 * hessian_step**2)
        scale = damping * (1.0 + np.abs(hessian).max(axis=(1, 2)))
        shifted = hessian + scale[:, None, None] * unit
        trial = phase - np.linalg.solve(shifted, gradient[..., None])[..., 0]
        better = objective(trial) < value
        phase[better] = trial[better]
        damping = np.where(better, damping / 10.0, damping * 10.0)
    return objective(phase)


def _brute_force_minima(beta_rad: np.ndarray, grid: int, polishes: int = 6) -> np.ndarray:
    """Least RE over all phasings of each row of angles: every point of a phase grid
    (vectorised closed form), then a damped Newton polish of the best few. The
    grids are offset, so they miss the 0 / 90 deg optima of chains that cannot
    cancel: the polish has to find them."""
    axis = np.radians((np.arange(grid) + 0.37) * 180.0 / grid)
    phases = np.array(list(itertools.product(axis, repeat=beta_rad.shape[1] - 1)))
    values = residual_error(beta_rad[:, None, :], phases[None, :, :])
    best = np.argsort(values, axis=1)[:, :polishes]
    starts = phases[best].reshape(-1, phases.shape[1])
    polished = _polish(np.repeat(beta_rad, polishes, axis=0), starts).reshape(-1, polishes)
    return np.minimum(values.min(axis=1), polished.min(axis=1))


def test_can_cancel_agrees_with_brute_force_on_300_random_angle_sets():
    # Issue acceptance: 300 random sets of 3 to 5 joints. Brute force = global
    # phasing search (grid + polish) on the closed-form chain, which
    # test_column_geometry checks against the package's quadrature and the 3D simulation.
    rng = np.random.default_rng(2026)
    grids = {3: 25, 4: 11, 5: 7}
    joints = rng.integers(3, 6, 300)
    verdicts = {True: 0, False: 0}
    for count, grid in grids.items():
        beta_deg = rng.uniform(1.0, 45.0, (int(np.sum(joints == count)), count))
        brute = _brute_force_minima(np.radians(beta_deg), grid)
        for row, minimum in zip(beta_deg, brute, strict=True):
            verdict = can_cancel(row)
            assert verdict.possible == (minimum < 1e-18), (row, verdict, minimum)
            assert minimum == pytest.approx(verdict.minimum_residual_error, rel=1e-8, abs=1e-18)
            verdicts[verdict.possible] += 1
    assert sum(verdicts.values()) == 300
    assert min(verdicts.values()) >= 60, verdicts


def test_two_joints_cancel_only_with_equal_angles():
    assert can_cancel([20.0, 20.0]).possible
    assert can_cancel([20.0, 20.0]).margin == 0.0
    assert cancelling_phases_deg([20.0, 20.0]) == ((90.0,),)
    verdict = can_cancel([20.0, 21.0])
    assert not verdict.possible and verdict.margin < 0
    # Least RE of two joints: distance |l1 - l2| (closed form), reached at phi = 90.
    assert residual_error(np.radians([20.0, 21.0]), np.radians([[90.0]]))[0] == pytest.approx(
        verdict.minimum_residual_error, rel=1e-12)
    assert _brute_force_minima(np.radians([[20.0, 21.0]]), 361)[0] == pytest.approx(
        verdict.minimum_residual_error, rel=1e-9)


def test_one_joint_cancels_only_when_straight():
    assert can_cancel([0.0]).possible
    assert not can_cancel([10.0]).possible
    assert can_cancel([10.0]).minimum_residual_error == pytest.approx(
        residual_error(np.radians([10.0]), np.zeros((1, 0)))[0], rel=1e-12)


@pytest.mark.parametrize("seed", range(40))
def test_three_joint_closed_form_phases_cancel(seed):
    rng = np.random.default_rng(seed)
    beta_deg = rng.uniform(2.0, 70.0, 3)
    verdict = can_cancel(beta_deg)
    solutions = cancelling_phases_deg(beta_deg)
    if not verdict.possible:
        assert solutions == ()
        return
    assert len(solutions) == 2
    first, mirror = solutions
    assert mirror == pytest.approx((180.0 - first[0], 180.0 - first[1]), abs=1e-12)
    for phases in solutions:
        assert residual_error(np.radians(beta_deg), np.radians([phases]))[0] < 1e-24


def test_three_joints_with_a_straight_one_cancel_on_the_stated_representative():
    for beta_deg in ([0.0, 15.0, 15.0], [15.0, 0.0, 15.0], [15.0, 15.0, 0.0]):
        (phases,) = cancelling_phases_deg(beta_deg)
        assert residual_error(np.radians(beta_deg), np.radians([phases]))[0] < 1e-28
    assert minimising_phases_deg([15.0, 0.0, 15.0]) is None


@pytest.mark.parametrize("beta_deg", [[9.2, 13.3, 19.9], [5.0, 4.0, 3.0, 12.0], [30.0, 10.0],
                                      [8.0, 25.0, 3.0, 4.0, 6.0]])
def test_minimising_phases_when_cancelling_is_impossible_are_0_and_90(beta_deg):
    verdict = can_cancel(beta_deg)
    assert not verdict.possible
    (phases,) = minimising_phases_deg(beta_deg)
    assert set(phases) <= {0.0, 90.0}
    assert residual_error(np.radians(beta_deg), np.radians([phases]))[0] == pytest.approx(
        verdict.minimum_residual_error, rel=1e-12)


def test_spicer_small_angle_rule_is_the_limit():
    # cos(b_max) - prod cos(b_other) = (sum b_other^2 - b_max^2) / 2 + O(b^4), b in rad.
    beta_deg = np.array([3.0, 4.0, 4.5, 2.0])
    for scale in (1.0, 0.1, 0.01):
        verdict = can_cancel(beta_deg * scale)
        small = math.radians(1.0) ** 2 * verdict.small_angle_margin_deg2 / 2.0
        assert verdict.margin == pytest.approx(small, rel=0.01 * scale**2)
    assert can_cancel([3.0, 4.0, 5.0]).small_angle_margin_deg2 == pytest.approx(0.0, abs=1e-12)
    assert can_cancel([3.0, 4.0, 5.0]).limiting_joint == 3


@pytest.mark.parametrize("beta_deg, message", [
    ([], "empty"), ([10.0, 90.0], r"beta_deg\[1\] = 90"), ([float("nan")], r"beta_deg\[0\]"),
    ([-1.0, 3.0], r"beta_deg\[0\] = -1 is outside"),
])
def test_bad_angles_are_refused(beta_deg, message):
    with pytest.raises(ValueError, match=message):
        can_cancel(beta_deg)


def test_closed_form_phases_need_two_or_three_joints():
    with pytest.raises(ValueError, match="4 joints"):
        cancelling_phases_deg([10.0, 10.0, 10.0, 10.0])
