"""The fitter's table names one assembly (issue 35, item 4): on a column with tolerances
the teeth come from the tolerance-aware optimum, and no row shows the nominal optimum's
delta beside them; on a column judged by RE alone, the optimum the teeth lie nearest."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import sso
from sso._reports.column_fitter_report import fitter_blocks, recommended_origin
from sso._reports.summary import Paragraph, Table

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def car_run():
    return sso.run_case(ROOT / "cases" / "column_car_limits.toml")


def test_a_tolerance_aware_recommendation_names_its_own_optimum(car_run):
    run = car_run
    robust = {design.role: design for design in run.robust.designs}
    # The situation: the teeth are searched for the robust objective, so the
    # recommended assembly is not the nominal optimum's teeth.
    assert run.splines.objective != "RE"
    assert run.splines.yoke_phase_deg == robust["robust_splines"].yoke_phase_deg
    assert not np.allclose(robust["robust"].yoke_phase_deg, run.phasing.yoke_phase_deg,
                           atol=0.1)
    text, table, nominal = fitter_blocks(run)
    assert isinstance(text, Paragraph) and isinstance(table, Table)
    assert text.text.startswith(
        f"Recommended assembly: {run.assembly('splines').label}, yoke phasing -80.000, "
        "-60.000 deg. Its optimum: the tolerance-aware (least CVaR95 of RE), delta")
    assert "[tolerances]" in text.text and "not this phasing rounded" in text.text
    assert table.header[3] == "its optimum: tolerance-aware (least CVaR95 of RE), delta (deg)"
    for shaft, row in enumerate(table.rows):
        # every cell of a row is of the recommended assembly or of its own optimum
        assert float(row[3]) == pytest.approx(robust["robust"].yoke_phase_deg[shaft], abs=5e-4)
        assert int(row[5]) == run.splines.tooth_offset[shaft]
        assert float(row[6]) == run.splines.yoke_phase_deg[shaft]
        assert f"{run.phasing.yoke_phase_deg[shaft]:.3f}" not in row[3:]  # (gamma may equal it)
    # the nominal optimum is named apart, as not recommended
    assert nominal.text.startswith("Not recommended, for comparison: the nominal optimum")
    assert f"{run.phasing.yoke_phase_deg[0]:.3f}" in nominal.text


def test_teeth_for_re_name_the_continuous_optimum_they_lie_nearest():
    run = sso.run_case(ROOT / "cases" / "column_truck_three_joints.toml")
    origin = recommended_origin(run)
    assert run.splines.objective == "RE"
    assert origin.label == "best yoke phasing (continuous)"
    assert origin.yoke_phase_deg == run.phasing.yoke_phase_deg
    # within half a tooth (5 deg on 36 teeth) of the teeth, as an exact best must be here
    assert np.max(np.abs(np.subtract(origin.yoke_phase_deg, run.splines.yoke_phase_deg))) < 5.0
    blocks = fitter_blocks(run)
    assert len(blocks) == 2  # one optimum: nothing set apart
