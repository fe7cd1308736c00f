"""tolerance_band: the intervals and the box of phase errors under an RE limit.

Every edge is checked with code the band does not use: the 3D cross-and-yoke
simulation for yoke phasings (the column's own points, the edge phasing) and
sso.ShaftSeries.evaluate (quadrature of the speed ratio) for operating angles.
"""

from __future__ import annotations

import itertools
import json

import numpy as np
import pytest
from column_cases import load
from cross_and_yoke import residual_error as simulated_residual_error

import sso
from sso._column.band import re_against_phase_error, tolerance_band
from sso._column.geometry import ColumnGeometry
from sso._column.phasing import optimise_phasing


@pytest.fixture(scope="module")
def truck():
    geometry = ColumnGeometry(load("truck_three_joints")["points_mm"])
    return geometry, optimise_phasing(geometry)


@pytest.fixture(scope="module")
def band(truck):
    _, optimum = truck
    return tolerance_band(optimum, re_limit=2.0 * optimum.fun)


def test_yoke_phase_edges_meet_the_limit_in_the_3d_simulation(truck, band):
    geometry, optimum = truck
    points = np.asarray(geometry.points_mm)
    assert band.nominal_re == pytest.approx(optimum.fun, rel=1e-12)
    for k, interval in enumerate(band.yoke_phase):
        assert interval.name == f"yoke_phase_deg[{k}]"
        assert interval.lower_at_limit and interval.upper_at_limit
        assert interval.lower_deg < interval.nominal_deg < interval.upper_deg
        assert interval.nominal_deg == pytest.approx(optimum.yoke_phase_deg[k])
        for edge in (interval.lower_deg, interval.upper_deg):
            yoke = list(optimum.yoke_phase_deg)
            yoke[k] = edge
            assert simulated_residual_error(points, yoke) / band.re_limit == pytest.approx(1.0,
                                                                                      abs=1e-6)
    # Measured: delta_1 = 10.0 in [-20.4, 40.4] deg, delta_2 = -80.0 in [-92.4, -67.6] deg.
    assert band.yoke_phase[0].lower_deg == pytest.approx(-20.38, abs=0.01)
    assert band.yoke_phase[1].upper_deg == pytest.approx(-67.64, abs=0.01)


def test_operating_angle_edges_meet_the_limit_by_quadrature(truck, band):
    geometry, optimum = truck
    for k, interval in enumerate(band.operating_angle):
        assert interval.name == f"beta_deg[{k}]"
        assert interval.lower_at_limit and interval.upper_at_limit
        assert 0 < interval.lower_deg < interval.nominal_deg < interval.upper_deg < 90
        for edge in (interval.lower_deg, interval.upper_deg):
            beta = list(geometry.beta_deg)
            beta[k] = edge
            evaluated = sso.ShaftSeries(beta, geometry.phase_deg_from_yoke(optimum.yoke_phase_deg))
            assert evaluated.evaluate().residual_error / band.re_limit == pytest.approx(1.0,
                                                                                    abs=1e-6)


def test_box_corners_meet_the_limit_and_its_grid_stays_under(truck, band):
    geometry, optimum = truck
    points = np.asarray(geometry.points_mm)
    widths = [min(i.nominal_deg - i.lower_deg, i.upper_deg - i.nominal_deg)
              for i in band.yoke_phase]
    np.testing.assert_allclose(band.box_half_width_deg, band.box_scale * np.asarray(widths))
    assert 0 < band.box_scale < 1
    corners = [simulated_residual_error(points, np.add(optimum.yoke_phase_deg,
                                                       np.multiply(signs, band.box_half_width_deg)))
               for signs in itertools.product((-1, 1), repeat=2)]
    assert max(corners) / band.re_limit == pytest.approx(1.0, abs=1e-6)
    assert band.box_corner_max_re == pytest.approx(max(corners), rel=1e-6)
    assert band.box_grid_max_re <= band.re_limit * (1 + 1e-9)


def test_a_limit_above_every_phasing_gives_a_whole_period(truck):
    geometry, _ = truck
    # In phase RE 4.86e-3; the worst phasing stays below 6e-3 (measured 5.16e-3).
    band = tolerance_band((geometry, (0.0, 0.0)), re_limit=0.01)
    for interval in band.yoke_phase:
        assert not interval.lower_at_limit and not interval.upper_at_limit
        assert interval.upper_deg - interval.lower_deg == pytest.approx(180.0)
        assert max(interval.lower_re, interval.upper_re) < 0.01
    assert band.box_scale == 1.0
    # An angle that can fall to 0 without crossing the limit keeps 0 as its lower edge.
    assert band.operating_angle[0].lower_deg == 0.0
    assert not band.operating_angle[0].lower_at_limit
    assert band.operating_angle[0].upper_at_limit


@pytest.mark.parametrize("limit, match", [
    (1e-4, r"re_limit = 0.0001 is below the least RE any yoke phasing"),
    (1e-3, r"re_limit = 0.001 is below the design's RE"),
    (0.0, "re_limit"),
    (-1.0, "re_limit"),
    (float("nan"), "re_limit"),
])
def test_bad_limits_name_re_limit(truck, limit, match):
    geometry, _ = truck
    # The least reachable RE is 2.27e-4; the in-phase design has 4.86e-3.
    with pytest.raises(ValueError, match=match):
        tolerance_band((geometry, (0.0, 0.0)), re_limit=limit)


def test_bad_designs(truck):
    geometry, _ = truck
    with pytest.raises(TypeError, match="design"):
        tolerance_band(geometry, re_limit=1e-3)
    with pytest.raises(ValueError, match="yoke_phase_deg has 1 entries"):
        tolerance_band((geometry, (0.0,)), re_limit=1e-2)


def test_re_against_phase_error_is_the_3d_simulation(truck):
    geometry, optimum = truck
    curves = re_against_phase_error(optimum, span_deg=20.0, points=41)
    assert list(curves) == ["yoke_phase_deg[0]", "yoke_phase_deg[1]"]
    points = np.asarray(geometry.points_mm)
    for k, (errors, values) in enumerate(curves.values()):
        assert errors[0] == -20.0 and errors[-1] == 20.0 and len(errors) == 41
        assert values[20] == pytest.approx(optimum.fun, rel=1e-9)
        assert values.min() == pytest.approx(optimum.fun, rel=1e-9)  # the optimum is a minimum
        for index in (0, 33):
            yoke = list(optimum.yoke_phase_deg)
            yoke[k] += errors[index]
            assert values[index] == pytest.approx(simulated_residual_error(points, yoke), rel=1e-9)
    with pytest.raises(ValueError, match="span_deg"):
        re_against_phase_error(optimum, span_deg=0.0)
    with pytest.raises(ValueError, match="points"):
        re_against_phase_error(optimum, points=2)


def test_band_is_json_ready(band):
    document = json.loads(json.dumps(band.to_dict()))
    assert document["yoke_phase"][0]["lower_deg"] == band.yoke_phase[0].lower_deg
    assert document["box_half_width_deg"] == list(band.box_half_width_deg)
