"""``optimise_batch`` against ``sso.optimise`` (quadrature objective, IPOPT and SLSQP)."""

import dataclasses
import warnings

import numpy as np
import pytest

import sso
from sso._kinematics import hooke_matrix
from sso._shafts.batch import optimise_batch

CASES = {  # option: beta bounds (deg), as in cases/paper_option*_exact.toml
    1: (0.0, 40.0),
    2: (7.0, 25.0),
    3: (10.0, 40.0),
}


def random_starts(seed, count, n_joints=3):
    rng = np.random.default_rng(seed)
    return rng.uniform(5.0, 40.0, (count, n_joints)), rng.uniform(0.0, 180.0, (count, n_joints - 1))


@pytest.mark.parametrize("option", [1, 2, 3])
def test_each_start_matches_sso_optimise_from_that_start(option):
    beta_deg, phase_deg = random_starts(option, 5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sso.StartMovedWarning)
        batch = optimise_batch(beta_deg, phase_deg, option=option,
                               beta_bounds_deg=CASES[option])
        for row in range(len(beta_deg)):
            single = sso.optimise(sso.ShaftSeries(beta_deg[row], phase_deg[row]), option,
                                  beta_bounds_deg=CASES[option], solvers=("slsqp",), starts=1)
            assert batch.fun[row] == pytest.approx(single.fun, rel=0, abs=1e-12)
    assert np.all(batch.success)
    # The reported RE is the closed form at the reported design.
    np.testing.assert_allclose(batch.fun, hooke_matrix.residual_error(
        np, list(np.radians(batch.beta_deg).T), list(np.radians(batch.phase_deg).T)),
        rtol=1e-12, atol=1e-20)  # the deg round trip moves the last bits of x


def test_paper_cases_match_the_default_sso_optimise():
    # The paper's three starts (cases/paper_option*_exact.toml) against sso.optimise
    # with both solvers and four starts.
    starts = {1: ([15.0, 20.0, 9.0], [30.0, 40.0]), 2: ([10.0, 15.0, 30.0], [90.0, 90.0]),
              3: ([30.0, 40.0, 50.0], [90.0, 90.0])}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sso.StartMovedWarning)
        for option, (beta_deg, phase_deg) in starts.items():
            bounds = (0.0, 180.0) if option == 1 else CASES[option]
            batch_beta = np.minimum(beta_deg, 40.0) if option == 3 else beta_deg
            batch = optimise_batch(batch_beta, phase_deg, option=option, beta_bounds_deg=bounds
                                   if option != 1 else (0.0, 40.0))
            single = sso.optimise(sso.ShaftSeries(batch_beta, phase_deg), option,
                                  beta_bounds_deg=bounds if option != 1 else (0.0, 40.0), starts=4)
            assert batch.fun[0] == pytest.approx(single.fun, rel=0, abs=1e-12)


def test_option_3_reaches_zero_residual_inside_the_bounds():
    beta_deg, phase_deg = random_starts(11, 200)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sso.StartMovedWarning)
        result = optimise_batch(beta_deg, phase_deg, option=3, beta_bounds_deg=(10.0, 40.0))
    assert np.all(result.success)
    assert np.all(result.beta_deg >= 10.0) and np.all(result.beta_deg <= 40.0)
    assert np.all(result.phase_deg >= 0.0) and np.all(result.phase_deg <= 180.0)
    # Every start that a single solver takes to zero reaches it here as well.
    reachable = result.fun <= 1e-10
    assert np.mean(reachable) >= 0.98
    for row in np.flatnonzero(~reachable):
        single = sso.optimise(sso.ShaftSeries(result.beta_deg[row], result.phase_deg[row]), 3,
                              beta_bounds_deg=(10.0, 40.0), solvers=("slsqp",), starts=1)
        assert single.fun == pytest.approx(result.fun[row], rel=1e-9)


def test_a_start_whose_first_step_lands_on_a_saddle_corner_still_reaches_zero():
    # Start 50 of benchmarks/batch_throughput.py: the first Gauss-Newton step is
    # projected onto beta = 10, 10, 10 deg, phase = 0, 0 deg, a stationary point with
    # RE = 1.05e-3 and negative curvature in the phases; SLSQP from this start
    # reaches RE = 2.7e-15.
    result = optimise_batch([39.000949151682875, 11.695693855183503, 39.35075069424323],
                            [66.9027724008308, 105.9998420481538], option=3,
                            beta_bounds_deg=(10.0, 40.0))
    assert result.success[0] and result.fun[0] <= 1e-20


def test_a_stationary_point_on_a_bound_with_zero_multiplier_is_left():
    # Option 1 from this start first stops at phase = 90, 0 deg (RE = 1.43e-5): the
    # gradient of the phase on its bound is 2e-13, round-off, and the curvature
    # inwards is negative. SLSQP from the same start reaches RE = 9.6e-19.
    result = optimise_batch([27.707961026705515, 24.975889413228618, 13.72364195297121],
                            [104.16981642303143, 53.81355732869628], option=1)
    assert result.success[0] and result.fun[0] <= 1e-20


def test_fixed_angles_stay_fixed_and_speeds_follow_the_residual():
    beta_deg, phase_deg = random_starts(21, 4)
    phase_result = optimise_batch(beta_deg, phase_deg, option=1)
    np.testing.assert_array_equal(phase_result.beta_deg, beta_deg)
    angle_result = optimise_batch(np.minimum(beta_deg, 40.0), phase_deg, option=2)
    np.testing.assert_array_equal(angle_result.phase_deg, 90.0)
    for result in (phase_result, angle_result):
        for row in range(4):
            evaluation = sso.ShaftSeries(result.beta_deg[row], result.phase_deg[row]).evaluate(30.0)
            assert result.speed_min_rpm[row] * 30 / 25 == pytest.approx(evaluation.speed_min_rpm,
                                                                         rel=1e-9)
            assert result.speed_max_rpm[row] * 30 / 25 == pytest.approx(evaluation.speed_max_rpm,
                                                                         rel=1e-9)


def test_result_exports():
    beta_deg, phase_deg = random_starts(31, 3)
    result = optimise_batch(beta_deg, phase_deg, option="both", input_speed_rpm=30.0)
    columns = result.to_columns()
    assert list(columns)[:6] == ["fun", "beta_deg_1", "beta_deg_2", "beta_deg_3", "phase_deg_1",
                                 "phase_deg_2"]
    assert all(len(column) == 3 for column in columns.values())
    data = result.to_dict()
    assert data["option"] == 3 and data["input_speed_rpm"] == 30.0
    assert data["fun"]["data"] == result.fun.tolist()
    assert type(result).from_dict(data) == result
    with pytest.raises(dataclasses.FrozenInstanceError):
        result.fun = None  # frozen


@pytest.mark.parametrize("call, message", [
    (lambda: optimise_batch([[10.0, 20.0]], [[90.0]], model="paper"),
     "model = 'paper' has no closed form"),
    (lambda: optimise_batch([[10.0, 20.0]], [[90.0]], model="other"), "model = 'other'"),
    (lambda: optimise_batch([[10.0, 95.0]], [[90.0]]),
     r"beta_deg\[0, 1\] = 95 is outside the allowed range \[0, 90\) deg"),
    (lambda: optimise_batch([[10.0, np.nan]], [[90.0]]), r"beta_deg\[0, 1\] = nan must be finite"),
    (lambda: optimise_batch([[10.0, 20.0]], [[90.0, 1.0]]),
     r"phase_deg has shape \(1, 2\); the starts of beta_deg need \(1, 1\)"),
    (lambda: optimise_batch([[10.0]], [[]], option=1), "option = 1 .* needs at least 2 joints"),
    (lambda: optimise_batch([[10.0, 20.0]], [[90.0]], option=4), "option = 4 is not one of"),
    (lambda: optimise_batch([[10.0, 20.0]], [[90.0]], beta_bounds_deg=(30.0, 20.0)),
     "beta_bounds_deg = .* is inverted"),
    (lambda: optimise_batch([[10.0, 20.0]], [[90.0]], input_speed_rpm=-1.0),
     "input_speed_rpm = -1 is outside"),
    (lambda: optimise_batch([[10.0, 20.0]], [[90.0]], max_iterations=0),
     "max_iterations = 0 is outside"),
    (lambda: optimise_batch([[10.0, 20.0]], [[90.0]], solver_tol=2.0), "solver_tol = 2 is outside"),
])
def test_bad_input_names_the_field(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_non_numeric_starts_are_type_errors():
    with pytest.raises(TypeError, match="beta_deg = '10' must be an array of numbers"):
        optimise_batch("10", [[90.0]])
    with pytest.raises(TypeError, match="phase_deg must be an array of numbers, not of bool"):
        optimise_batch([[10.0, 20.0]], [[True]])


def test_unknown_keyword_fails():
    with pytest.raises(TypeError):
        optimise_batch([[10.0, 20.0]], [[90.0]], tolerence=1e-9)  # type: ignore[call-arg]


@pytest.mark.filterwarnings("ignore::sso.StartMovedWarning")
@pytest.mark.parametrize("option", [1, 2, 3])
def test_a_design_gets_the_same_answer_in_any_batch(option):
    # Sweeps batch their points in chunks of any size: each design's answer must not
    # depend on the designs beside it (bit for bit, the status and counts too).
    rng = np.random.default_rng(40 + option)
    beta_deg, phase_deg = rng.uniform(3.0, 44.0, (24, 3)), rng.uniform(-20.0, 200.0, (24, 2))
    whole = optimise_batch(beta_deg, phase_deg, option=option, beta_bounds_deg=(5.0, 35.0))
    for size in (1, 5, 7):
        parts = [optimise_batch(beta_deg[row:row + size], phase_deg[row:row + size],
                                option=option, beta_bounds_deg=(5.0, 35.0))
                 for row in range(0, 24, size)]
        for name in ("fun", "beta_deg", "phase_deg", "status", "nit", "nfev", "kkt"):
            np.testing.assert_array_equal(np.concatenate([getattr(part, name) for part in parts]),
                                          getattr(whole, name))


@pytest.mark.parametrize("joints", [3, 4])
@pytest.mark.parametrize("option", [1, 2, 3])
def test_every_design_gets_the_single_solve_s_answer_bit_for_bit(option, joints):
    # Reference: sso.optimise with "lm" alone and one start, the same functions run for
    # one design: the batch maps them over the designs, so each row is the single
    # solve's answer exactly (design, RE, counts, status, optimality measure).
    rng = np.random.default_rng(50 + option)
    beta_deg = rng.uniform(5.0, 35.0, (30, joints))
    phase_deg = rng.uniform(0.0, 180.0, (30, joints - 1))
    batch = optimise_batch(beta_deg, phase_deg, option=option, beta_bounds_deg=(5.0, 35.0))
    assert np.all(batch.success)
    for row in range(30):
        single = sso.optimise(sso.ShaftSeries(beta_deg[row], phase_deg[row]), option,
                              solvers=("lm",), starts=1, beta_bounds_deg=(5.0, 35.0)).best
        assert (single.fun, single.nit, single.nfev, single.status, single.kkt) == (
            batch.fun[row], batch.nit[row], batch.nfev[row], batch.status[row], batch.kkt[row])
        assert single.series.beta_deg == tuple(batch.beta_deg[row])
        assert single.series.phase_deg == tuple(batch.phase_deg[row])
