"""sso.optimise: bad input, solver failures reported in the result, laziness."""

import json
import math
import subprocess
import sys

import numpy as np
import pytest

import sso

PAPER_OPTION_3 = sso.ShaftSeries([30, 40, 50], [90, 90], model="paper")
# The same start moved inside the paper's bounds (10, 40) by hand, so no warning.
PAPER_OPTION_3_INSIDE = sso.ShaftSeries([30, 40, 40], [90, 90], model="paper")
PAPER_OPTION_2 = sso.ShaftSeries([10, 15, 25], [90, 90], model="paper")


@pytest.mark.parametrize(
    "kwargs, error, message",
    [
        ({"option": 4}, ValueError, r"option = 4 is not one of 1, 2, 3, 'phase', 'angle', 'both'"),
        ({"option": "phases"}, ValueError, r"option = 'phases' is not one of"),
        ({"solvers": ("ipopt", "fmincon")}, ValueError,
         r"solvers\[1\] = 'fmincon' is not one of ipopt, slsqp"),
        ({"solvers": ()}, ValueError, r"solvers is empty"),
        ({"beta_bounds_deg": (40, 10)}, ValueError,
         r"beta_bounds_deg = \(40, 10\) deg is inverted"),
        ({"beta_bounds_deg": (10, 90)}, ValueError,
         r"beta_bounds_deg upper = 90 is outside the allowed range \[0, 90\) deg"),
        ({"beta_bounds_deg": [(10, 40), (10, 40)]}, ValueError,
         r"beta_bounds_deg = .* must be one \(lower, upper\) pair or 3 pairs"),
        ({"beta_bounds_deg": (math.nan, 40)}, ValueError,
         r"beta_bounds_deg lower = nan must be finite"),
        ({"phase_bounds_deg": [(0, 180), (90, 0)]}, ValueError,
         r"phase_bounds_deg\[1\] = \(90, 0\) deg is inverted"),
        ({"starts": 0}, ValueError, r"starts = 0 is outside the allowed range \[1, 10000\]"),
        ({"input_speed_rpm": math.inf}, ValueError, r"input_speed_rpm = inf must be finite"),
        ({"input_speed_rpm": -25}, ValueError,
         r"input_speed_rpm = -25 is outside the allowed range"),
        ({"solver_tol": 0}, ValueError, r"solver_tol = 0 is outside the allowed range \(0, 1\)"),
        ({"max_iterations": 2.5}, ValueError, r"max_iterations = 2.5 must be a whole number"),
        ({"beta_bound_deg": (0, 40)}, TypeError, r"unexpected keyword argument 'beta_bound_deg'"),
    ],
)
def test_bad_input_is_refused_with_a_clear_error(kwargs, error, message):
    with pytest.raises(error, match=message):
        sso.optimise(PAPER_OPTION_3, **{"option": 3, **kwargs})


def test_option_one_needs_two_joints():
    with pytest.raises(ValueError, match=r"option = 1 \(phases\) needs at least 2 joints"):
        sso.optimise(sso.ShaftSeries([20.0]), option=1)


def test_series_must_be_a_shaft_series():
    with pytest.raises(TypeError, match="problem must be an sso.ShaftSeries, .*, not list"):
        sso.optimise([30, 40, 50])


def test_option_names_are_accepted():
    result = sso.optimise(PAPER_OPTION_2, option="angle", beta_bounds_deg=(7, 25), starts=1)
    assert (result.option, result.option_name) == (2, "angle")


def test_start_outside_bounds_is_moved_with_warning():
    with pytest.warns(sso.StartMovedWarning,
                      match=r"start beta_deg\[2\] = 50 deg .* moved onto 40"):
        result = sso.optimise(PAPER_OPTION_3, 3, beta_bounds_deg=(10, 40), starts=1)
    assert result.start_series.beta_deg == (30.0, 40.0, 40.0)


def test_per_joint_bounds_and_pinned_joint_are_honoured():
    result = sso.optimise(sso.ShaftSeries([20, 30, 12]), 3,
                          beta_bounds_deg=[(20, 20), (5, 35), (10, 15)], starts=2)
    beta = result.best.series.beta_deg
    assert beta[0] == 20.0
    assert 5.0 <= beta[1] <= 35.0 and 10.0 <= beta[2] <= 15.0
    assert result.best.fun <= 1e-20  # exact cancellation is reachable inside these bounds
    assert result.crosscheck.agree, result.crosscheck.message


def test_one_solver_failing_leaves_the_other_standing():
    # Real failures: an iteration limit IPOPT meets on this problem before SLSQP
    # does (paper-model option 2 from its start: IPOPT 19 iterations, SLSQP 28).
    result = sso.optimise(PAPER_OPTION_2, 2, beta_bounds_deg=(7, 25), starts=1,
                          max_iterations=20)
    ipopt, slsqp = result.solutions["ipopt"], result.solutions["slsqp"]
    assert ipopt.success and ipopt.status == 0
    assert not slsqp.success
    assert slsqp.status == 9 and "Iteration limit" in slsqp.message
    assert result.best is ipopt
    assert not result.crosscheck.agree
    assert "slsqp failed (Iteration limit reached)" in result.crosscheck.message
    assert not result.success


def test_both_solvers_failing_is_reported_not_raised():
    result = sso.optimise(PAPER_OPTION_3_INSIDE, 3, beta_bounds_deg=(10, 40), starts=1,
                          max_iterations=2)
    assert not result.solutions["ipopt"].success
    assert result.solutions["ipopt"].message == "Maximum_Iterations_Exceeded"
    assert result.solutions["ipopt"].status == -1
    assert not result.solutions["slsqp"].success
    assert math.isfinite(result.best.fun)
    assert result.best.fun < result.initial.residual_error
    assert not result.success


def test_single_solver_has_no_crosscheck():
    result = sso.optimise(PAPER_OPTION_2, 2, beta_bounds_deg=(7, 25), solvers="slsqp", starts=1)
    assert result.crosscheck is None
    assert list(result.solutions) == ["slsqp"]
    assert result.success


def test_to_dict_is_json_ready():
    result = sso.optimise(PAPER_OPTION_2, 2, beta_bounds_deg=(7, 25), starts=2)
    record = json.loads(json.dumps(result.to_dict()))
    assert record["best"]["fun"] == result.best.fun
    assert record["crosscheck"]["agree"] is True
    assert record["samples"] == result.samples == 16
    assert len(record["runs"]) == 4


def test_same_seed_same_answer():
    first = sso.optimise(PAPER_OPTION_3_INSIDE, 3, beta_bounds_deg=(10, 40), starts=4)
    second = sso.optimise(PAPER_OPTION_3_INSIDE, 3, beta_bounds_deg=(10, 40), starts=4)
    assert first.best.x == second.best.x
    assert first.local_minima == second.local_minima


def test_import_is_light():
    # import sso must not import matplotlib, dask, casadi or scipy; evaluating a
    # design must not import casadi (no NLP is built for an evaluation).
    code = (
        "import sys, sso\n"
        "heavy = ['matplotlib', 'dask', 'casadi', 'scipy']\n"
        "print([name for name in heavy if name in sys.modules])\n"
        "sso.ShaftSeries([30, 40], [90]).evaluate(25)\n"
        "print([name for name in heavy if name in sys.modules])\n"
    )
    output = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True,
                            text=True).stdout.splitlines()
    assert output == ["[]", "[]"]


def test_screened_starts_find_what_every_solver_from_every_start_finds():
    # Exact model, option 1 (a nonzero minimum, so every start is screened): the
    # least-squares screen then one run per solver from its best start reaches the RE
    # that IPOPT and SLSQP reach from all eight starts (within 1e-12 absolute).
    series = sso.ShaftSeries([15.0, 20.0, 9.0], [30.0, 40.0])
    screened = sso.optimise(series, 1)
    exhaustive = sso.optimise(series, 1, screen_starts=False)
    assert [run.solver for run in screened.runs] == ["lm"] * 8 + ["ipopt", "slsqp"]
    assert len(exhaustive.runs) == 16
    assert screened.crosscheck.agree and exhaustive.crosscheck.agree
    assert abs(screened.fun - exhaustive.fun) <= 1e-12
    best_start = min(screened.runs[:8], key=lambda run: run.fun).start_index
    assert all(run.start_index == best_start for run in screened.runs[8:])


def test_screening_stops_at_a_global_minimum():
    # Option 3 can cancel (RE = 0): the user's start already reaches round-off zero.
    # Then IPOPT and SLSQP each solve from that start with their own iterations, and the
    # design is chosen within the set of exact optima ("lm" bisecting the margin).
    result = sso.optimise(sso.ShaftSeries([30.0, 40.0, 35.0], [90.0, 90.0]), 3,
                          beta_bounds_deg=(10, 40))
    assert [(run.solver, run.role) for run in result.runs] == [
        ("lm", "screen"), ("ipopt", "solve"), ("slsqp", "solve"), ("lm", "selection")]
    assert all(result.solutions[name].nit > 0 for name in ("ipopt", "slsqp"))
    assert result.fun <= 1e-20 and result.crosscheck.agree


def test_the_module_named_optimise_does_not_shadow_the_function():
    # sso._shafts.optimise is a module; sso.optimise stays the lazily exported function
    # (the dispatcher that sends a shaft series on to sso._shafts.optimise.optimise).
    import importlib

    importlib.import_module("sso._shafts.optimise")
    dispatcher = importlib.import_module("sso._column.dispatch")
    assert callable(sso.optimise) and sso.optimise is dispatcher.optimise
    result = sso.optimise(PAPER_OPTION_2, 2, beta_bounds_deg=(7, 25), solvers="slsqp", starts=1)
    assert result.success


def test_one_solver_from_one_start_runs_alone_and_a_pair_is_screened():
    # A single solver from a single start is that solver's own run (the per-solver
    # benchmarks rely on it); the cross-checked pair from one start is screened too.
    series = sso.ShaftSeries([20.0, 30.0, 25.0], [10.0, 80.0])
    alone = sso.optimise(series, 3, solvers=("ipopt",), starts=1)
    pair = sso.optimise(series, 3, starts=1)
    assert [run.solver for run in alone.runs] == ["ipopt"]
    assert [run.solver for run in pair.runs] == ["lm", "ipopt", "slsqp", "lm"]
    assert pair.best.role == "selection" and alone.best.role == "solve"
    assert alone.fun <= 1e-20 and pair.fun <= 1e-20 and pair.crosscheck.agree


def test_many_starts_above_zero_are_screened_in_one_batch():
    # Option 1 cannot cancel here (minimum RE 1.147e-4, the paper's option-1 case), so
    # the user's start stops above zero and the other 80 starts (more than
    # BATCH_SCREEN_STARTS) are screened in one batched least-squares solve: they
    # share the batch's wall time equally. The best of them must equal the best of
    # the same starts solved one by one with "lm" (independent single runs, within
    # 1e-12 absolute), and the solvers then run from it.
    from sso._limits import BATCH_SCREEN_STARTS, DEFAULT_SEED
    from sso._shafts.options import build_problem
    from sso._solvers.starts import start_points

    starts = 81
    assert starts - 1 >= BATCH_SCREEN_STARTS
    series = sso.ShaftSeries([15.0, 20.0, 9.0], [30.0, 40.0])
    result = sso.optimise(series, 1, starts=starts, solvers=("lm",))
    screening = result.runs[:starts]
    assert [run.start_index for run in screening] == list(range(starts))
    assert len({run.time_s for run in screening[1:]}) == 1
    assert all(run.success for run in screening)
    problem = build_problem(series.beta_deg, series.phase_deg, "exact", 1, (0.0, 40.0),
                            (0.0, 180.0))
    points = start_points(problem.start_rad, problem.lower_rad, problem.upper_rad, starts,
                          DEFAULT_SEED)
    one_by_one = []
    for point in points:
        beta_deg, phase_deg = problem.design_deg(np.degrees(point))
        single = sso.optimise(sso.ShaftSeries(beta_deg, phase_deg), 1, solvers=("lm",),
                              starts=1, beta_bounds_deg=(0.0, 40.0))
        one_by_one.append(single.fun)
    assert abs(min(run.fun for run in screening) - min(one_by_one)) <= 1e-12
    assert result.fun == pytest.approx(1.1470510032e-4, rel=1e-9)
    assert result.success


def test_many_starts_stop_at_the_first_zero_without_a_batch():
    # Option 3 cancels from the user's start: 200 starts cost one screening run.
    result = sso.optimise(sso.ShaftSeries([30.0, 40.0, 35.0], [90.0, 90.0]), 3,
                          beta_bounds_deg=(10, 40), starts=200)
    assert [run.solver for run in result.runs] == ["lm", "ipopt", "slsqp", "lm"]
    assert result.fun <= 1e-20 and result.crosscheck.agree
