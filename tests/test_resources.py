"""The memory estimate counts joints and starts, and guards sso.optimise and optimise_batch.

Reference peaks are the resident-set peaks listed in MEASURED_MULTISTART_PEAKS_MB,
measured in fresh processes by ``python -m benchmarks.memory_estimate`` (which also
measures optimise_batch's).
"""

from __future__ import annotations

import numpy as np
import pytest

import sso
from sso._resources import (
    batch_estimate,
    batch_least_squares_mb,
    multistart_estimate,
)
from sso._shafts.batch import _parts

# (joints, free angles, starts) -> peak resident memory of the whole process, MB, for
# sso.optimise of the exact model (IPOPT and SLSQP, the starts screened by "lm") with
# RE = 0 out of reach (40 deg and 5 deg joints, option 1, so every start is screened),
# or one start of option 3; measured on the development machine with
# benchmarks/memory_estimate.py (64 joints from 1,000 starts: at least 1,719 MB, the
# largest resident size seen while it ran).
MEASURED_MULTISTART_PEAKS_MB = {
    (2, 3, 1): 54.5,
    (64, 127, 1): 64.5,
    (6, 5, 100): 124.0,
    (6, 5, 1000): 125.8,
    (16, 15, 400): 126.8,
    (32, 31, 100): 129.2,
    (32, 31, 400): 232.4,
    (64, 63, 1000): 1719.0,
    (6, 5, 10_000): 194.7,
}


@pytest.mark.parametrize(("shape", "peak_mb"), sorted(MEASURED_MULTISTART_PEAKS_MB.items()))
def test_the_multistart_estimate_is_within_a_factor_of_two_of_the_measured_peak(shape,
                                                                                  peak_mb):
    joints, free, starts = shape
    estimate = multistart_estimate(joints, free, 0, starts, 2, screened=True).memory_mb
    assert peak_mb / 2 <= estimate <= 2 * peak_mb, (shape, estimate, peak_mb)




def test_sso_optimise_refuses_64_joints_from_10000_starts_with_the_estimate():
    # 64 joints, option 3 (127 free angles), screened: 60 + 10 MB for the process and the
    # NLP and 10,000 x (135 x 127^2 + 4.5 x 127^3 + 8,000) bytes of screening: 108,819 MB.
    series = sso.ShaftSeries([40.0] + [5.0] * 63, [90.0] * 63)
    with pytest.raises(ValueError, match=r"multi-start run \(64 joints, 127 free angles, "
                                         r"10000 starts x 2 solvers\): about 108,819 MB and "
                                         r"20,000 solves, above the memory limit of 1,000 MB"):
        sso.optimise(series, 3, starts=10_000, memory_limit_mb=1000)


def test_the_environment_s_limit_is_read_on_every_call_of_a_run_that_fitted(monkeypatch):
    # One start of "lm", 3 joints of option 3 (5 free angles), not screened: 60 MB for the
    # process + 10 MB for the NLP + 0.01 MB for the kept run = 70.01 MB, which fits the
    # default limit and 71 MB but not 70 MB; a fit is kept per shape and limit, never
    # for a limit set afterwards.
    series = sso.ShaftSeries([30.0, 40.0, 35.0], [90.0, 90.0])

    def solve():
        return sso.optimise(series, 3, solvers="lm", starts=1, beta_bounds_deg=(10.0, 40.0))

    monkeypatch.delenv("SSO_MEMORY_LIMIT_MB", raising=False)
    assert solve().success
    monkeypatch.setenv("SSO_MEMORY_LIMIT_MB", "71")
    assert solve().success
    monkeypatch.setenv("SSO_MEMORY_LIMIT_MB", "70")
    with pytest.raises(ValueError, match=r"multi-start run \(3 joints, 5 free angles, 1 starts "
                                         r"x 1 solvers\): about 70 MB and 1 solves, above the "
                                         r"memory limit of 70 MB"):
        solve()
    monkeypatch.setenv("SSO_MEMORY_LIMIT_MB", "lots")
    with pytest.raises(ValueError, match="SSO_MEMORY_LIMIT_MB"):
        solve()
    monkeypatch.delenv("SSO_MEMORY_LIMIT_MB")
    assert solve().success


def test_optimise_batch_solves_in_parts_that_fit_with_the_same_answers():
    rng = np.random.default_rng(3)
    beta, phase = rng.uniform(5.0, 30.0, (300, 10)), rng.uniform(0.0, 180.0, (300, 9))
    whole = sso.optimise_batch(beta, phase, option=3)
    # Room for 100 starts of 19 free angles above the process: three parts.
    limit = batch_estimate(0, 10, 19).memory_mb + 100 * batch_least_squares_mb(1, 19)
    assert [part.stop - part.start for part in _parts(300, 10, 19, limit)] == [100, 100, 100]
    parted = sso.optimise_batch(beta, phase, option=3, memory_limit_mb=limit)
    for field in ("fun", "beta_deg", "phase_deg", "nit", "status", "kkt"):
        np.testing.assert_array_equal(getattr(parted, field), getattr(whole, field))


def test_optimise_batch_refuses_when_not_one_start_fits():
    with pytest.raises(ValueError, match=r"batch \(1 starts of 10 joints, 19 free angles\): "
                                         r"about 50 MB and 1 solves, above the memory limit "
                                         r"of 50\.01 MB; .*raise the limit to at least 50 MB"):
        sso.optimise_batch(np.full((3, 10), 20.0), np.zeros((3, 9)), memory_limit_mb=50.01)
    with pytest.raises(ValueError, match="memory_limit_mb = -1 is outside the allowed range"):
        sso.optimise_batch(np.full((3, 10), 20.0), np.zeros((3, 9)), memory_limit_mb=-1)


def test_a_million_starts_of_ten_joints_are_split_to_fit_the_limit():
    # The call (10^6 starts x 10 joints ended in MemoryError after 22 s): the
    # estimate is about 84 GB, so at 1,000 MB it runs in 88 parts of 11,371 starts.
    assert batch_estimate(10**6, 10, 19).memory_mb == pytest.approx(83_592, rel=1e-4)
    parts = _parts(10**6, 10, 19, 1000.0)
    assert parts[0] == slice(0, 11_371) and parts[-1].stop >= 10**6 and len(parts) == 88
    assert all(batch_estimate(part.stop - part.start, 10, 19).memory_mb <= 1000.0
               for part in parts)
