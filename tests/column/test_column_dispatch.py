"""sso.optimise, the one optimiser entry point, sends each problem to its optimiser."""

from __future__ import annotations

import numpy as np
import pytest
from column_cases import load

import sso
from sso._column.feel import OnCentreResult, optimise_on_centre
from sso._column.joint_centres import JointCentresResult
from sso._column.phasing import PhasingResult
from sso._column.splines import SplineResult, best_spline_teeth
from sso._linkages.fourbar_swing import design_fourbar

TRUCK = load("truck_three_joints")["points_mm"]


def test_a_geometry_gets_its_best_yoke_phasing():
    # The truck column (tests/data/columns/truck_three_joints.json): best phasing
    # 2.27e-4, in phase 4.9e-3 (3D simulation,
    # tests/column/test_column_phasing.py).
    result = sso.optimise(sso.ColumnGeometry(TRUCK))
    assert isinstance(result, PhasingResult)
    assert result.success, result.message
    assert result.fun == pytest.approx(2.268e-4, rel=1e-3)
    assert result.in_phase_re == pytest.approx(4.86e-3, rel=1e-2)
    assert len(result.yoke_phase_deg) == 2
    assert any(np.allclose(result.yoke_phase_deg, optimum, atol=1e-5)
               for optimum in result.equivalent_yoke_phase_deg)


def test_joint_boxes_send_a_geometry_to_the_joint_position_design():
    points = np.asarray(TRUCK)
    boxes = [[list(point - 5.0), list(point + 5.0)] for point in points[1:-1]]
    result = sso.optimise(sso.ColumnGeometry(TRUCK), joint_boxes_mm=boxes,
                          yoke_phase_deg=[0.0, 0.0], starts=2)
    assert isinstance(result, JointCentresResult)
    assert result.fun < result.initial_re


def test_a_series_still_goes_to_the_shaft_optimiser():
    series = sso.ShaftSeries([20.0, 20.0], [0.0])
    result = sso.optimise(series, 1, starts=2)
    assert isinstance(result, sso.OptimisationResult)
    assert result.fun < 1e-12  # equal angles cancel at phi = 90 deg


def test_unknown_keyword_and_positional_options_fail():
    geometry = sso.ColumnGeometry(TRUCK)
    with pytest.raises(TypeError, match="unknown_option"):
        sso.optimise(geometry, unknown_option=1)
    with pytest.raises(TypeError, match="keyword options only"):
        sso.optimise(geometry, 1)
    with pytest.raises(TypeError, match="ShaftSeries"):
        sso.optimise([20.0, 20.0])


def test_positions_go_to_the_phasing_for_every_position():
    geometry = sso.ColumnGeometry(TRUCK)
    result = sso.optimise({"up": geometry, "down": geometry}, positions_objective="worst")
    assert result.fun == pytest.approx(sso.optimise(geometry).fun, rel=1e-6)


def test_a_joint_position_result_reads_well():
    points = np.asarray(TRUCK)
    boxes = [[list(point - 5.0), list(point + 5.0)] for point in points[1:-1]]
    result = sso.optimise(sso.ColumnGeometry(TRUCK), joint_boxes_mm=boxes,
                          yoke_phase_deg=[0.0, 0.0], starts=2)
    assert len(repr(result)) <= 400 and "\n" not in repr(result)
    assert repr(result).startswith("JointCentresResult(")
    summary = result.summary()
    assert "Joint centres: " in summary and "P0" in summary and "ipopt" in summary
    assert "<table>" in result._repr_html_()


def test_a_fourbar_goes_to_the_fourbar_design():
    start = sso.FourBar(ground=12, crank=2, coupler=15, rocker=9)
    bounds = {"crank_bounds": (1, 6), "coupler_bounds": (5, 20), "rocker_bounds": (5, 15)}
    result = sso.optimise(start, **bounds, starts=2)
    assert isinstance(result, sso.FourBarDesignResult)
    assert result.x == design_fourbar(start, **bounds, starts=2).x  # same seed, same run
    with pytest.raises(TypeError, match="keyword options only"):
        sso.optimise(start, (1, 6))


def test_teeth_and_lock_send_a_geometry_to_the_splines_and_the_on_centre_phasing():
    geometry = sso.ColumnGeometry(TRUCK)
    teeth = sso.optimise(geometry, teeth=12)
    assert isinstance(teeth, SplineResult)
    assert teeth.yoke_phase_deg == best_spline_teeth(geometry, 12).yoke_phase_deg
    feel = {"straight_ahead_deg": 45.0, "lock_deg": 600.0, "starts": 0}
    centred = sso.optimise(geometry, **feel)
    assert isinstance(centred, OnCentreResult)
    assert centred.yoke_phase_deg == optimise_on_centre(geometry, **feel).yoke_phase_deg


def test_two_selecting_keywords_are_refused():
    with pytest.raises(TypeError, match="got lock_deg and teeth; give at most one of"):
        sso.optimise(sso.ColumnGeometry(TRUCK), teeth=12, lock_deg=600.0)
