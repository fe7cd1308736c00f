"""Tolerances and optimise_robust: RE over a seeded sample of built columns.

The sample's RE is checked against the independent 3D cross-and-yoke simulation of
each built column (perturbed points, perturbed yoke phasing); the percentiles
against numpy on the same values; CVaR against its definition on sorted samples.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from column_cases import load
from cross_and_yoke import residual_error as simulated_residual_error

from sso._column.geometry import ColumnGeometry
from sso._column.robust_phasing import optimise_robust
from sso._column.scenarios import cvar
from sso._column.tolerances import Tolerances

TOLERANCES = Tolerances(hardpoint_mm=1.0, yoke_phase_deg=1.0, samples=100, seed=1)


@pytest.fixture(scope="module")
def tilt_down():
    # The truck column tilted down 6 deg: operating angles 17.4, 14.1, 19.9 deg, so
    # phasing cancels (cos 19.9 >= cos 17.4 cos 14.1) and the nominal optimum
    # (RE ~ 1e-25) sits in a narrow valley.
    return ColumnGeometry(load("truck_three_positions")["positions"]["tilt_down"]["points_mm"])


@pytest.fixture(scope="module")
def robust_p95(tilt_down):
    return optimise_robust(tilt_down, TOLERANCES, robust_objective="p95")


def test_sample_re_is_the_3d_simulation_of_each_built_column(tilt_down):
    sample = TOLERANCES.sample(tilt_down)
    design = (12.0, -40.0)
    values = sample.residual_error(design)
    points = np.asarray(tilt_down.points_mm)
    for index in (0, 7, 99):
        built = points + sample.hardpoint_offsets_mm[index]
        yoke = np.add(design, sample.yoke_phase_errors_deg[index])
        assert values[index] == pytest.approx(simulated_residual_error(built, yoke), rel=1e-9)


def test_sample_is_seeded_and_draws_with_the_stated_spread(tilt_down):
    first, again = TOLERANCES.sample(tilt_down), TOLERANCES.sample(tilt_down)
    np.testing.assert_array_equal(first.beta_rad, again.beta_rad)
    np.testing.assert_array_equal(first.gamma_rad, again.gamma_rad)
    other = Tolerances(hardpoint_mm=1.0, yoke_phase_deg=1.0, samples=100, seed=2).sample(tilt_down)
    assert not np.array_equal(first.beta_rad, other.beta_rad)
    # 100 x 5 x 3 normal draws of sd 1 mm, 100 x 2 of sd 1 deg: sample sd within 10 %.
    assert np.std(first.hardpoint_offsets_mm) == pytest.approx(1.0, rel=0.1)
    assert np.std(first.yoke_phase_errors_deg) == pytest.approx(1.0, rel=0.1)
    uniform = Tolerances(hardpoint_mm=2.0, samples=50, distribution="uniform").sample(tilt_down)
    assert np.max(np.abs(uniform.hardpoint_offsets_mm)) <= 2.0
    assert np.all(uniform.yoke_phase_errors_deg == 0.0)


def test_p95_optimum_beats_the_nominal_optimum_on_the_same_samples(tilt_down, robust_p95):
    result = robust_p95
    assert result.success, result.message
    assert result.crosscheck is not None and result.crosscheck.agree, result.crosscheck.message
    assert result.solutions["ipopt"].fun == pytest.approx(result.solutions["slsqp"].fun, rel=1e-9)
    sample = TOLERANCES.sample(tilt_down)
    robust_values = sample.residual_error(result.yoke_phase_deg)
    nominal_values = sample.residual_error(result.nominal.yoke_phase_deg)
    assert result.robust_study.p95 == pytest.approx(np.percentile(robust_values, 95), rel=1e-12)
    assert result.nominal_study.p95 == pytest.approx(np.percentile(nominal_values, 95), rel=1e-12)
    assert result.robust_study.max == pytest.approx(robust_values.max(), rel=1e-12)
    assert result.nominal_study.p50 == pytest.approx(np.median(nominal_values), rel=1e-12)
    # The objective is CVaR95 (docs/robust.md); measured 1.044e-4 against 1.094e-4 for
    # the nominal optimum. (The p95 itself, 6.32e-5, depends on which of the continuum
    # of cancelling phasings the nominal multi-start picks: 8.31e-5 with the scipy
    # Halton starts, 5.94e-5 with the numpy Halton starts of sso._solvers.starts.)
    assert result.robust_study.cvar95 <= 0.96 * result.nominal_study.cvar95
    # The nominal RE given up: the nominal optimum cancels (1e-25), the robust one not quite.
    assert result.nominal_optimum_re <= 1e-20
    assert result.nominal_re_given_up == pytest.approx(
        result.nominal_re - result.nominal_optimum_re, rel=1e-12)
    assert 0 < result.nominal_re_given_up < 1e-5
    assert result.nominal_re == pytest.approx(
        simulated_residual_error(np.asarray(tilt_down.points_mm), result.yoke_phase_deg),
        rel=1e-6)


def test_p95_optimum_out_of_sample_stays_close_to_the_nominal(robust_p95):
    # Out of sample (seed 2, same size), in the objective it minimises (CVaR95).
    # Measured 7.57e-5 against 7.22e-5 for the nominal optimum the numpy Halton starts
    # pick: the in-sample advantage (1.044e-4 against 1.094e-4) does not carry over to
    # this sample size. (With the scipy Halton starts' nominal the p95 was 6.30e-5
    # against 9.67e-5.)
    assert (robust_p95.validation_robust_study.cvar95
            < 1.1 * robust_p95.validation_nominal_study.cvar95)


def test_mean_objective_solvers_agree_and_beat_the_nominal_mean(tilt_down):
    result = optimise_robust(tilt_down, TOLERANCES, robust_objective="mean")
    assert result.success, result.message
    assert result.fun == pytest.approx(result.robust_study.mean, rel=1e-12)
    assert result.robust_study.mean <= result.nominal_study.mean
    assert result.solutions["ipopt"].fun == pytest.approx(result.solutions["slsqp"].fun, rel=1e-9)


def test_cvar_is_the_mean_of_the_tail():
    values = np.random.default_rng(3).lognormal(size=200)
    weights = np.full(200, 1 / 200)
    ordered = np.sort(values)
    assert cvar(values, weights, 0.95) == pytest.approx(np.mean(ordered[-10:]), rel=1e-12)
    # 190.2 of 200 below the 0.951 level: the tail holds 9.8 samples' weight.
    tail = (0.8 * ordered[190] + np.sum(ordered[191:])) / 9.8
    assert cvar(values, weights, 0.951) == pytest.approx(tail, rel=1e-9)


@pytest.mark.parametrize("keywords, match", [
    ({"hardpoint_mm": -0.1}, "hardpoint_mm"),
    ({"yoke_phase_deg": -1.0}, "yoke_phase_deg"),
    ({"yoke_phase_deg": float("nan")}, "yoke_phase_deg"),
    ({"cross_angle_deg": 0.5}, "cross_angle_deg"),
    ({"samples": 1}, "samples"),
    ({"seed": -1}, "seed"),
    ({"distribution": "triangular"}, "distribution"),
])
def test_bad_tolerances_name_the_field(keywords, match):
    with pytest.raises(ValueError, match=match):
        Tolerances(**keywords)


@pytest.mark.parametrize("objective", ["p100", "p40", "q95", "p95%", 95])
def test_bad_robust_objective_names_the_field(tilt_down, objective):
    with pytest.raises(ValueError, match="robust_objective"):
        optimise_robust(tilt_down, TOLERANCES, robust_objective=objective)


def test_a_percentile_needs_a_sample_in_its_tail(tilt_down):
    with pytest.raises(ValueError, match="robust_objective = 'p99' needs at least 100 samples"):
        optimise_robust(tilt_down, Tolerances(yoke_phase_deg=1.0, samples=50),
                        robust_objective="p99")


def test_wrong_types_are_type_errors(tilt_down):
    with pytest.raises(TypeError, match="tolerances"):
        optimise_robust(tilt_down, {"hardpoint_mm": 1.0})
    with pytest.raises(TypeError, match="geometry"):
        optimise_robust(tilt_down.points_mm, TOLERANCES)


def test_result_is_json_ready(robust_p95):
    document = json.loads(json.dumps(robust_p95.to_dict()))
    assert document["robust_study"]["p95"] == robust_p95.robust_study.p95
    assert document["nominal_study"]["p95"] == robust_p95.nominal_study.p95
    assert document["tolerances"]["samples"] == 100
