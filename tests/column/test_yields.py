"""The yield of built columns against limits: Wilson's score interval checked against the
score test it inverts (solved numerically), and the verdict's three outcomes."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from sso._column.steering_criteria import SteeringLimits
from sso._column.yields import column_limits, deciding_samples, judge_yields, wilson_interval

Z95 = 1.959963984540054  # the standard normal's 97.5 % quantile


def _score_test_ends(passed: int, samples: int) -> tuple[float, float]:
    """The proportions p where the score statistic |k/n - p| / sqrt(p (1 - p) / n) equals
    z (Wilson 1927's definition of the interval), found by root finding: an independent
    formulation of the closed form."""
    fraction = passed / samples

    def excess(p: float) -> float:
        return abs(fraction - p) - Z95 * math.sqrt(p * (1.0 - p) / samples)

    # the score statistic is 0 at p = k/n: bracket each end away from it
    low = 0.0 if passed == 0 else brentq(excess, 1e-15, min(fraction, 1.0 - 1e-9), xtol=1e-15)
    high = 1.0 if passed == samples else brentq(excess, max(fraction, 1e-9), 1.0 - 1e-15,
                                                xtol=1e-15)
    return low, high


@pytest.mark.parametrize("passed, samples", [(990, 2000), (1051, 2000), (1, 10), (0, 50),
                                             (50, 50), (1999, 2000), (7, 9)])
def test_the_wilson_interval_is_where_the_score_test_does_not_reject(passed, samples):
    low, high = wilson_interval(passed, samples)
    expected_low, expected_high = _score_test_ends(passed, samples)
    assert low == pytest.approx(expected_low, abs=1e-12)
    assert high == pytest.approx(expected_high, abs=1e-12)
    assert 0.0 <= low <= passed / samples <= high <= 1.0


def test_a_perfect_sample_keeps_a_lower_bound_below_one():
    # 50 of 50: 1 / (1 + z^2 / n) (the closed form at k = n).
    assert wilson_interval(50, 50)[0] == pytest.approx(1.0 / (1.0 + Z95**2 / 50), rel=1e-14)


@pytest.mark.parametrize("passed, samples", [(3, 2), (-1, 5), (0, 0)])
def test_an_impossible_count_is_refused(passed, samples):
    with pytest.raises(ValueError, match="passed = .* of samples = "):
        wilson_interval(passed, samples)


def _figures(fluctuation_passing: int, samples: int = 1000) -> dict[str, np.ndarray]:
    # the first fluctuation_passing columns at 1 %, the rest at 3 %; transmission error
    # fails on the last 100 of the passing ones
    fluctuation = np.where(np.arange(samples) < fluctuation_passing, 1.0, 3.0)
    error = np.where((np.arange(samples) >= fluctuation_passing - 100)
                     & (np.arange(samples) < fluctuation_passing), 0.9, 0.1)
    return {"speed_fluctuation_percent": fluctuation, "largest_transmission_error_deg": error,
            "torque_fluctuation_percent": fluctuation,
            "largest_operating_angle_deg": np.full(samples, 20.0)}


LIMITS = column_limits(SteeringLimits(speed_fluctuation_percent=2.0, transmission_error_deg=0.5))


@pytest.mark.parametrize("passing, required, verdict, signed_off", [
    (950, 0.80, "meets", True),      # 850 of 1000 together: [0.827, 0.871]
    (950, 0.85, "not decided", False),  # straddles
    (950, 0.90, "fails", False),     # upper bound 0.871 < 0.9
    (950, None, "not judged", True),
])
def test_the_verdict_reads_the_interval_of_every_limit_together(passing, required, verdict,
                                                                signed_off):
    judged = judge_yields(_figures(passing), LIMITS, required)
    assert [item.passed for item in judged.limits] == [950, 900, 1000]
    assert judged.together.passed == 850
    assert (judged.together.low, judged.together.high) == wilson_interval(850, 1000)
    assert judged.verdict == verdict and judged.signed_off is signed_off
    assert judged.together.text == "85.0 % (95 % CI 82.7 % to 87.1 %, width 4.4 %, 1,000 samples)"


def test_a_yield_not_decided_says_how_many_samples_would_decide_it():
    judged = judge_yields(_figures(950), LIMITS, 0.85)
    # Reference: the half-width of Wilson's interval at p = 0.85, z = 1.959964 (95 %),
    # z / (1 + z^2/n) sqrt(p (1 - p) / n + z^2 / (4 n^2)), computed here by hand, falls
    # below |0.85 - 0.85| = 0 never: a yield equal to the requirement is never decided.
    assert judged.deciding_samples is None
    assert judged.verdict_text == ("not decided 85.0 % at 1,000 samples (no sample count "
                                   "decides a yield equal to the requirement)")
    judged = judge_yields(_figures(950), LIMITS, 0.86)
    z = 1.959963984540054

    def half(n):
        return z / (1 + z * z / n) * math.sqrt(0.85 * 0.15 / n + z * z / (4 * n * n))

    needed = judged.deciding_samples
    assert half(needed) < 0.01 <= half(needed - 1)
    assert needed == deciding_samples(0.85, 0.86) == 4_898
    assert judged.sentence == (
        "NOT DECIDED at 1,000 samples against the required yield 86.0 %: yield of all limits "
        "together 85.0 % (95 % CI 82.7 % to 87.1 %, width 4.4 %, 1,000 samples) straddles it; "
        "about 4,898 samples would decide it (Wilson's half-width below the distance from the "
        "yield to the requirement)")
    # at that count a yield of 85 % is shown below 86 %: the interval's upper bound
    assert wilson_interval(round(0.85 * needed), needed)[1] < 0.86
    assert judge_yields(_figures(950), LIMITS, 0.80).deciding_samples is None  # decided


def test_a_value_on_the_limit_meets_it():
    figures = _figures(500)
    figures["speed_fluctuation_percent"][:] = 2.0
    assert judge_yields(figures, LIMITS, None).limits[0].passed == 1000


@pytest.mark.parametrize("required", [0.0, 1.5, -0.1, float("nan")])
def test_a_required_yield_outside_zero_to_one_is_refused(required):
    with pytest.raises(ValueError, match="yield = "):
        judge_yields(_figures(500), LIMITS, required)


def test_the_limits_judged_are_those_the_case_sets_and_the_operating_angle():
    assert [figure for figure, *_ in LIMITS] == [
        "speed_fluctuation_percent", "largest_transmission_error_deg",
        "largest_operating_angle_deg"]
    assert [figure for figure, *_ in column_limits(SteeringLimits())] == [
        "largest_operating_angle_deg"]
