"""Tolerance studies of a column: each sample a built column, its figures against the
independent 3D cross-and-yoke simulation (tests/column/cross_and_yoke.py), the draw as
documented, the command line and bad input."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from column.cross_and_yoke import Simulated, extremes
from column.cross_and_yoke import residual_error as simulated_re

import sso
from sso.cases.schema import load_case

ROOT = Path(__file__).resolve().parents[2]
TRUCK = ROOT / "cases" / "column_truck_three_joints.toml"
CASE = load_case(TRUCK)
GEOMETRY = CASE.geometry()
YOKE = (10.0, -80.0)


def test_each_sample_is_a_built_column_as_the_3d_simulation_turns_it():
    tolerances = sso.Tolerances(hardpoint_mm=2.0, yoke_phase_deg=1.5, seed=7)
    result = sso.tolerance_study((GEOMETRY, YOKE), tolerances=tolerances, samples=40,
                                 progress=False, workers=1)
    assert isinstance(result, sso.ColumnToleranceResult) and result.samples == 40
    # The draw as documented: hardpoint errors (samples, n + 2, 3), then phase errors.
    rng = np.random.default_rng(7)
    offsets = rng.normal(0.0, 2.0, (40, 5, 3))
    phase_errors = rng.normal(0.0, 1.5, (40, 2))
    assert result.yoke_phase_error_deg == pytest.approx(phase_errors, abs=0)
    for index in range(0, 40, 8):
        points = np.asarray(GEOMETRY.points_mm) + offsets[index]
        yoke = np.asarray(YOKE) + phase_errors[index]
        assert result.residual_error[index] == pytest.approx(simulated_re(points, yoke),
                                                             rel=1e-9)
    for index in (3, 29):  # the steering figures over +-900 deg of the wheel
        points = np.asarray(GEOMETRY.points_mm) + offsets[index]
        simulated = Simulated(points, np.asarray(YOKE) + phase_errors[index], 0.0)
        low, high = extremes(simulated.ratio, -np.radians(900.0), np.radians(900.0))
        error_low, error_high = extremes(simulated.error, -np.radians(900.0), np.radians(900.0))
        assert result.speed_fluctuation_percent[index] == pytest.approx(100 * (high - low),
                                                                        rel=1e-9)
        assert result.torque_fluctuation_percent[index] == pytest.approx(
            100 * (1 / low - 1 / high), rel=1e-9)
        assert result.largest_transmission_error_deg[index] == pytest.approx(
            np.degrees(max(-error_low, error_high)), rel=1e-9)
    nominal = sso.steering_range((GEOMETRY, YOKE))
    assert result.nominal["speed_fluctuation_percent"] == nominal.speed_fluctuation_percent
    assert result.nominal["residual_error"] == pytest.approx(
        simulated_re(np.asarray(GEOMETRY.points_mm), np.asarray(YOKE)), rel=1e-9)


def test_the_numbers_do_not_depend_on_chunks_or_processes():
    tolerances = sso.Tolerances(hardpoint_mm=1.0, yoke_phase_deg=1.0, distribution="uniform",
                                seed=2)
    one = sso.tolerance_study((GEOMETRY, YOKE), tolerances=tolerances, samples=60,
                              chunk_size=60, workers=1, progress=False)
    many = sso.tolerance_study((GEOMETRY, YOKE), tolerances=tolerances, samples=60,
                               chunk_size=7, workers=2, progress=False)
    for name in ("residual_error", "speed_fluctuation_percent",
                 "largest_transmission_error_deg"):
        assert np.array_equal(getattr(one, name), getattr(many, name))
    assert np.all(np.abs(one.yoke_phase_error_deg) <= 1.0)


def test_a_column_case_is_studied_as_built_with_its_steering_range():
    result = sso.tolerance_study(TRUCK, samples=30, seed=4, progress=False, workers=1)
    assert result.yoke_phase_deg == tuple(CASE.values["phasing.yoke_phase_deg"])
    assert (result.hardpoint_mm, result.yoke_phase_tolerance_deg) == (0.5, 1.0)  # defaults
    assert (result.lock_deg, result.seed) == (900.0, 4)
    assert "as built in case 'column_truck_three_joints'" in result.study_of


@pytest.mark.parametrize("keywords, match", [
    ({"tolerances": sso.Tolerances(hardpoint_mm=400.0 / 4)},
     r"hardpoint_mm = 100 mm is too large for this column: sample \d+: "),
    ({"beta_tolerance_deg": 0.5}, r"beta_tolerance_deg: a column's tolerance study takes "
                                  r"tolerances=sso.Tolerances"),
    ({"samples": 0}, r"samples = 0 is outside the allowed range \[1, 2000000\]"),
    ({"seed": -1}, r"seed = -1 is outside the allowed range"),
])
def test_bad_input_names_the_field(keywords, match):
    with pytest.raises(ValueError, match=match):
        sso.tolerance_study((GEOMETRY, YOKE), progress=False, workers=1, **keywords)


def test_a_shaft_series_refuses_a_columns_tolerances():
    with pytest.raises(ValueError, match=r"tolerances = sso.Tolerances\(...\) is a column's"):
        sso.tolerance_study(sso.ShaftSeries([10.0, 12.0], [90.0]),
                            tolerances=sso.Tolerances(hardpoint_mm=1.0))
