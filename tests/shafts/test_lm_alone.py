"""``sso.optimise(series, option, solvers=("lm",), starts=1)``: the direct path against the
general one.

Reference: the same call through the general path
(:func:`sso._solvers.multistart.solve_from_starts`: the run with its second-order care,
measured as every solver's run is), the direct path turned off. The records must be
equal field for field (``to_dict()``), each run's wall time (``time_s``) apart.
Problems: the paper's three options (the cases of benchmarks/batch_throughput.py),
random starts of 3 to 6 joints of every option (the work-precision benchmark's
ranges), a start outside its bounds (moved, with a warning) and symmetric starts on
which "lm" stops on a saddle point (the direct path hands those to the general path,
which leaves it).
"""

import numpy as np
import pytest

import sso
from sso._shafts import optimise as optimise_module

pytestmark = pytest.mark.filterwarnings("ignore::sso.StartMovedWarning")

PAPER = [((15.0, 20.0, 9.0), (30.0, 40.0), 1, (0.0, 40.0)),
         ((10.0, 15.0, 30.0), (90.0, 90.0), 2, (7.0, 25.0)),
         ((30.0, 40.0, 50.0), (90.0, 90.0), 3, (10.0, 40.0))]
# Symmetric starts: the gradient of RE in the phases is zero there, and the curvature of
# some phase negative, so "lm" stops at once on a saddle point (planar chains: phases at
# 0 or 90 deg).
SADDLES = [((20.0, 20.0, 20.0), (0.0, 0.0), 1, (5.0, 35.0)),
           ((20.0, 30.0, 20.0), (0.0, 0.0), 1, (5.0, 35.0)),
           ((20.0, 30.0, 20.0), (0.0, 0.0), 3, (5.0, 35.0))]


def _random_cases():
    rng = np.random.default_rng(20261126)
    return [(tuple(rng.uniform(5.0, 35.0, joints)), tuple(rng.uniform(0.0, 180.0, joints - 1)),
             option, (5.0, 35.0))
            for option in (1, 2, 3) for joints in range(3, 7) for _ in range(3)]


def _without_times(value):
    if isinstance(value, dict):
        return {key: _without_times(item) for key, item in value.items() if key != "time_s"}
    if isinstance(value, list):
        return [_without_times(item) for item in value]
    return value


def _solve(case, general, monkeypatch):
    beta_deg, phase_deg, option, beta_bounds = case
    with monkeypatch.context() as patch:
        if general:
            patch.setattr(optimise_module, "_solve_alone", lambda *arguments: None)
        return sso.optimise(sso.ShaftSeries(beta_deg, phase_deg), option, solvers=("lm",),
                            starts=1, beta_bounds_deg=beta_bounds, phase_bounds_deg=(0.0, 180.0))


@pytest.mark.parametrize("case", PAPER + _random_cases() + [
    ((40.0, 20.0, 3.0), (30.0, 40.0), 3, (5.0, 35.0))])  # two start values moved
def test_the_direct_path_gives_the_general_path_s_record(case, monkeypatch):
    taken = []
    direct = optimise_module._solve_alone

    def counted(*arguments):
        result = direct(*arguments)
        taken.append(result is not None)
        return result

    monkeypatch.setattr(optimise_module, "_solve_alone", counted)
    lean = _solve(case, False, monkeypatch)
    assert taken == [True]
    general = _solve(case, True, monkeypatch)
    assert _without_times(lean.to_dict()) == _without_times(general.to_dict())
    assert lean.fun == general.fun and lean.x == general.x


def test_a_run_that_stops_on_a_saddle_point_is_left_by_the_general_path(monkeypatch):
    for case in SADDLES:
        taken = []
        direct = optimise_module._solve_alone

        def counted(*arguments, direct=direct, taken=taken):
            result = direct(*arguments)
            taken.append(result is not None)
            return result

        with monkeypatch.context() as patch:
            patch.setattr(optimise_module, "_solve_alone", counted)
            result = _solve(case, False, monkeypatch)
        assert taken == [False]
        assert result.best.message.endswith("(after leaving a saddle point)")
        assert result.success
        general = _solve(case, True, monkeypatch)
        assert _without_times(result.to_dict()) == _without_times(general.to_dict())
