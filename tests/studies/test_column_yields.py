"""A column tolerance study judged against limits: which tolerance matters, ranked from
the study's own samples, and the largest one halved and re-sampled, counted again by
another path (sso.ColumnGeometry and sso.steering_range per built column)."""

from __future__ import annotations

import numpy as np
import pytest

import sso
from sso._studies.column_yields import input_columns, input_names

CAR = sso.ColumnGeometry([[-950.0, 360.0, 780.0], [-717.9, 296.7, 569.0],
                          [-660.0, 250.0, 430.0], [-610.0, 275.0, 300.0],
                          [-590.0, 300.0, 190.0]])
YOKE = (-80.0, -60.0)  # the car column's best assembly on its 36-tooth splines
LIMITS = sso.SteeringLimits(speed_fluctuation_percent=2.0, transmission_error_deg=0.5)


@pytest.fixture(scope="module")
def study():
    return sso.tolerance_study((CAR, YOKE), samples=2000, progress=False, workers=1,
                               tolerances=sso.Tolerances(hardpoint_mm=0.5, yoke_phase_deg=1.0),
                               limits=LIMITS, required_yield=0.9)


def test_the_tolerances_are_named_in_the_order_they_are_drawn():
    offsets = np.arange(2 * 5 * 3, dtype=float).reshape(2, 5, 3)
    phases = np.array([[100.0, 101.0], [102.0, 103.0]])
    names = input_names(5, 2)
    columns = input_columns(offsets, phases)
    assert names[:4] == ("P0 x", "P0 y", "P0 z", "P1 x") and names[-2:] == ("delta_1",
                                                                              "delta_2")
    assert columns[names.index("P2 y")].tolist() == offsets[:, 2, 1].tolist()
    assert columns[names.index("delta_2")].tolist() == [101.0, 103.0]
    assert all(np.shares_memory(column, offsets) for column in columns[:15])  # views


def test_the_contributions_are_ranked_and_the_draws_left_as_drawn(study):
    rng = np.random.default_rng(0)  # the documented draw of seed 0
    rng.normal(0.0, 0.5, (2000, 5, 3))
    assert np.array_equal(study.yoke_phase_error_deg, rng.normal(0.0, 1.0, (2000, 2)))
    assert [found.figure for found in study.sensitivity] == [
        "speed_fluctuation_percent", "largest_transmission_error_deg"]
    for found in study.sensitivity:
        indices = [item.index for item in found.contributions]
        assert indices == sorted(indices, reverse=True) and len(indices) == 5 * 3 + 2
        assert 0.0 <= sum(indices) <= 1.0
        assert found.interactions == pytest.approx(1.0 - sum(indices), abs=1e-12)
    # every built column meets the operating-angle limit: it needs no sensitivity
    assert study.yields.limits[2].passed == 2000


def test_the_largest_contributor_halved_is_re_sampled(study):
    (halved,) = study.halved
    assert halved.tolerance == study.sensitivity[0].contributions[0].tolerance
    assert halved.largest_in == tuple(found.label for found in study.sensitivity
                                      if found.contributions[0].tolerance == halved.tolerance)
    rng = np.random.default_rng(0)
    offsets = rng.normal(0.0, 0.5, (2000, 5, 3))
    phase_errors = rng.normal(0.0, 1.0, (2000, 2))
    point, axis = int(halved.tolerance[1]), "xyz".index(halved.tolerance[-1])
    offsets[:, point, axis] *= 0.5
    points = np.asarray(CAR.points_mm)
    passed = 0
    for index in range(2000):
        built = sso.ColumnGeometry(points + offsets[index])
        figures = sso.steering_range((built, np.asarray(YOKE) + phase_errors[index]),
                                     lock_deg=540.0)
        passed += (figures.speed_fluctuation_percent <= 2.0
                   and figures.largest_transmission_error_deg <= 0.5
                   and max(built.beta_deg) <= 35.0)
    assert halved.yields.together.passed == passed
    assert (halved.tolerance_value, halved.unit) == (0.25, "mm")
    assert halved.yields.required == 0.9
