"""The robust part of a column run: each design's figures, and the curves its plots draw.

Reference values: the shipped case cases/column_truck_three_positions.toml analysed as
built (``sso evaluate``: no solver runs). The RE at every position is checked against
the independent 3D cross-and-yoke simulation (tests/column/cross_and_yoke.py); the
band, the feel and the phase-error curves against the public functions on their own.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from column.cross_and_yoke import residual_error as simulated_re

import sso
from sso._cases.schema import load_case, parse_case
from sso._run.column import ColumnRun, run_column
from sso._run.column_robust import has_robust_part

CASE = Path(__file__).resolve().parents[2] / "cases" / "column_truck_three_positions.toml"


@pytest.fixture(scope="module")
def analysed() -> ColumnRun:
    return run_column(load_case(CASE), optimising=False)


def test_the_design_as_built_has_every_figure_the_case_asks_for(analysed):
    robust = analysed.robust
    (design,) = robust.designs
    assert design.role == "as_built" and design.yoke_phase_deg == (10.0, -80.0)
    for name, geometry in robust.positions.geometries.items():
        assert design.positions.position_re[name] == pytest.approx(
            simulated_re(np.asarray(geometry.points_mm), np.asarray(design.yoke_phase_deg)),
            rel=1e-6)
    assert design.positions.worst_re == max(design.positions.position_re.values())
    assert design.nominal_re == analysed.assembly("as_built").residual_error
    band = sso.tolerance_band((analysed.geometry, design.yoke_phase_deg),
                              robust.band_re_limit)
    assert design.band == band and design.band_note is None
    feel = robust.feel
    assert design.feel == sso.steering_feel((analysed.geometry, design.yoke_phase_deg),
                                            **feel.settings)
    # the stored sample is the study's: its p95 is the study's p95
    samples = robust.tolerances.samples_re["as_built"]
    assert len(samples) == robust.tolerances.tolerances.samples
    assert np.percentile(samples, 95.0) == pytest.approx(design.study.p95, rel=1e-12)


def test_no_solver_ran_in_an_analysis(analysed):
    robust = analysed.robust
    assert robust.positions.result is None and robust.tolerances.result is None
    assert robust.feel.result is None and robust.feel.note is None
    assert robust.tolerances.nominal_equivalents == ()


def test_the_curves_the_plots_draw_are_saved(analysed):
    robust = analysed.robust
    design = robust.designs[0]
    curves = sso.re_against_phase_error((analysed.geometry, design.yoke_phase_deg))
    for name, (errors, values) in curves.items():
        assert robust.phase_error.errors_deg == tuple(errors)
        assert robust.phase_error.curves["as_built"][name] == tuple(values)
    # at zero error each curve passes through the design's RE
    middle = len(robust.phase_error.errors_deg) // 2
    assert robust.phase_error.errors_deg[middle] == 0.0
    for values in robust.phase_error.curves["as_built"].values():
        assert values[middle] == pytest.approx(design.nominal_re, rel=1e-12)
    feel = robust.feel
    assert len(feel.ratio["as_built"]) == len(feel.wheel_deg)
    assert feel.wheel_deg[0] == -(feel.lock_deg + feel.window_deg)
    # the speed ratio's mean over a turn is 1 (output and input turn together)
    assert 0.9 < min(feel.ratio["as_built"]) <= 1.0 <= max(feel.ratio["as_built"]) < 1.1


def test_a_plain_column_has_no_robust_part():
    case = parse_case({"kind": "column", "hardpoints": {"points_mm": [
        [0, 0, 0], [300, 0, 0], [600, 80, 0], [900, 120, 160]]}}, "plain")
    assert not has_robust_part(case)
    assert run_column(case, optimising=False).robust is None
