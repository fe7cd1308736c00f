"""Tolerances and optimise_robust: RE over a seeded sample of built columns.

The sample's RE is checked against the independent 3D cross-and-yoke simulation of
each built column (perturbed points, perturbed yoke phasing); the percentiles
against numpy on the same values; CVaR against its definition on sorted samples; the
exact optima against the 3D simulation of the nominal column.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from column_cases import load
from cross_and_yoke import residual_error as simulated_residual_error

import sso
from sso._column.geometry import ColumnGeometry
from sso._column.robust_phasing import optimise_robust
from sso._column.scenarios import cvar
from sso._column.tolerances import Tolerances

ROOT = Path(__file__).resolve().parents[2]
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


@pytest.fixture(scope="module")
def mid():
    # The mid position cannot cancel (cos 19.9 < cos 9.2 cos 13.3): one optimum, RE 2.27e-4.
    return ColumnGeometry(load("truck_three_positions")["positions"]["mid"]["points_mm"])


def _exact_optima_p95(geometry, tolerances, phasings):
    """p95 RE over the sample of each phasing, after checking in the 3D simulation that
    it cancels the nominal column (RE at round-off zero)."""
    sample = tolerances.sample(geometry)
    points = np.asarray(geometry.points_mm)
    for yoke in phasings:
        assert simulated_residual_error(points, yoke) <= 1e-12, yoke
    return [float(np.percentile(sample.residual_error(yoke), 95)) for yoke in phasings]


def test_a_column_that_cancels_gets_the_exact_optimum_of_lowest_p95(tilt_down, robust_p95):
    # Where RE = 0 is reached on a set (here the two isolated phasings of three joints,
    # mod 180 deg, from the closed form), the phasing is chosen within the set as
    # sso.optimise chooses for a shaft series with tolerances: by the lowest p95 RE.
    result = robust_p95
    assert result.success, result.message
    assert result.exact_choice is not None
    assert result.exact_optimum_criterion.startswith("lowest p95 RE over the built columns")
    points = np.asarray(tilt_down.points_mm)
    # an exact optimum: no nominal RE given up (3D simulation, 1e-12)
    assert simulated_residual_error(points, result.yoke_phase_deg) <= 1e-12
    assert result.nominal_re <= 1e-12 and abs(result.nominal_re_given_up) <= 1e-12
    sample = TOLERANCES.sample(tilt_down)
    p95 = np.percentile(sample.residual_error(result.yoke_phase_deg), 95)
    assert result.robust_study.p95 == pytest.approx(p95, rel=1e-12)
    exact = result.exact_choice.optimisation.exact_optima
    assert exact.p95_residual_error == pytest.approx(p95, rel=1e-9)
    # the least p95 of every exact optimum (closed form, each checked in 3D)
    every = _exact_optima_p95(tilt_down, TOLERANCES, result.nominal.equivalent_yoke_phase_deg)
    assert len(every) == 2
    assert p95 == pytest.approx(min(every), rel=1e-9)
    # measured: 5.944e-5 against 8.312e-5 for the exact optimum sso.optimise(geometry)
    # chooses without tolerances (nearest the textbook correction), on the same sample
    assert p95 == pytest.approx(5.944e-5, rel=1e-3)
    assert result.nominal_study.p95 == pytest.approx(8.312e-5, rel=1e-3)
    assert result.nominal.yoke_phase_deg == pytest.approx((60.576, 66.698), abs=1e-3)
    assert result.crosscheck is not None and result.crosscheck.agree, result.crosscheck.message
    assert result.best.x == pytest.approx(result.yoke_phase_deg, abs=1e-9)


def test_the_exact_optimum_of_lowest_p95_keeps_its_advantage_out_of_sample(robust_p95):
    # A fresh sample (seed 2, same size): measured p95 5.580e-5 against 8.807e-5 for the
    # exact optimum chosen without tolerances.
    assert robust_p95.validation_robust_study.p95 == pytest.approx(5.580e-5, rel=1e-3)
    assert robust_p95.validation_nominal_study.p95 == pytest.approx(8.807e-5, rel=1e-3)


def test_the_shipped_tolerance_case_chooses_an_exact_optimum_no_worse_than_without():
    # cases/column_truck_three_positions.toml: its hardpoints (tilt_down), [tolerances]
    # (1 mm, 1 deg, normal, 200 columns, seed 1, p95) and [solver] options, as sso run
    # passes them. Reference p95s: numpy.percentile of the sample's RE at each phasing,
    # the sample's RE being the 3D simulation of each built column
    # (test_sample_re_is_the_3d_simulation_of_each_built_column).
    from sso._cases.schema import load_case

    case = load_case(ROOT / "cases" / "column_truck_three_positions.toml")
    geometry, tolerances = case.geometry(), case.tolerances()
    options = case.solver_options()
    chosen = optimise_robust(geometry, tolerances, robust_objective="p95", **options)
    without = sso.optimise(geometry, solvers=options["solvers"], seed=options["seed"])
    assert without.exact_optimum_criterion.startswith("nearest the textbook correction")
    assert simulated_residual_error(np.asarray(geometry.points_mm),
                                    chosen.yoke_phase_deg) <= 1e-12
    chosen_p95, without_p95 = _exact_optima_p95(geometry, tolerances,
                                                (chosen.yoke_phase_deg, without.yoke_phase_deg))
    assert chosen_p95 <= without_p95 * (1.0 + 1e-9)
    # measured: both 6.520e-5 (this seed's solvers reach the better exact optimum first;
    # the other, delta = (60.58, 66.70) deg, has p95 8.730e-5 on this sample)
    assert chosen_p95 == pytest.approx(6.520e-5, rel=1e-3)
    every = _exact_optima_p95(geometry, tolerances, without.equivalent_yoke_phase_deg)
    assert sorted(every) == pytest.approx([6.520e-5, 8.730e-5], rel=1e-3)
    assert chosen_p95 == pytest.approx(min(every), rel=1e-9)
    assert chosen.robust_study.p95 == pytest.approx(chosen_p95, rel=1e-9)
    # the API's default seed: without tolerances the other exact optimum is chosen
    default = sso.optimise(geometry)
    assert _exact_optima_p95(geometry, tolerances, [default.yoke_phase_deg])[0] == (
        pytest.approx(8.730e-5, rel=1e-3))
    assert sso.optimise(geometry, tolerances=tolerances).robust_study.p95 == pytest.approx(
        6.520e-5, rel=1e-3)


def test_p95_objective_where_the_column_cannot_cancel_lowers_the_cvar(mid):
    # No set of exact optima: the CVaR95 over the sample is minimised over all phasings.
    # Measured: 4.5329e-4 against 4.5476e-4 of the nominal optimum (docs/robust.md: on
    # the mid position it gains little).
    result = optimise_robust(mid, TOLERANCES, robust_objective="p95")
    assert result.success, result.message
    assert result.exact_choice is None and result.exact_optimum_criterion is None
    assert result.crosscheck is not None and result.crosscheck.agree, result.crosscheck.message
    assert result.solutions["ipopt"].fun == pytest.approx(result.solutions["slsqp"].fun, rel=1e-9)
    sample = TOLERANCES.sample(mid)
    robust_values = sample.residual_error(result.yoke_phase_deg)
    nominal_values = sample.residual_error(result.nominal.yoke_phase_deg)
    weights = np.full(len(robust_values), 1 / len(robust_values))
    assert result.fun == pytest.approx(cvar(robust_values, weights, 0.95), rel=1e-9)
    assert result.robust_study.cvar95 <= cvar(nominal_values, weights, 0.95)
    assert result.robust_study.cvar95 == pytest.approx(4.5329e-4, rel=1e-3)
    assert result.nominal_study.cvar95 == pytest.approx(4.5476e-4, rel=1e-3)
    assert result.nominal_re == pytest.approx(
        simulated_residual_error(np.asarray(mid.points_mm), result.yoke_phase_deg), rel=1e-6)
    assert result.nominal_re_given_up >= 0.0


def test_mean_objective_solvers_agree_and_beat_the_nominal_mean(mid):
    result = optimise_robust(mid, TOLERANCES, robust_objective="mean")
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
