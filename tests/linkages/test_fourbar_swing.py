"""Four-bar design with real constraints: largest rocker swing of a
crank-rocker whose transmission angle stays in [40, 120] deg."""

import math

import numpy as np
import pytest

from sso._linkages.fourbar_swing import design_fourbar, transmission_angle_range_deg
from sso._linkages.mechanisms import FourBar

# The four-bar paper's linkage (tests/data/reference/README.md: ground 12, coupler 15,
# rocker 9, crank 2) as the start; bounds chosen so the limits bind.
START = FourBar(ground=12, crank=2, coupler=15, rocker=9)
BOUNDS = {"crank_bounds": (1, 6), "coupler_bounds": (5, 20), "rocker_bounds": (5, 15)}


@pytest.fixture(scope="module")
def result():
    return design_fourbar(START, **BOUNDS, starts=8)


def test_solvers_converge_feasible_and_agree(result):
    for name in ("ipopt", "slsqp"):
        solution = result.solutions[name]
        assert solution.success, solution.message
        assert solution.constraint_violation <= 1e-8
        assert solution.kkt <= 1e-6
    assert result.crosscheck.agree, result.crosscheck.message
    assert result.success


def test_optimum_is_a_crank_rocker_within_the_transmission_band(result):
    optimum = result.optimum
    assert optimum.grashof() == "crank-rocker"
    assert optimum.ground == 12.0  # pinned by default: swing is scale-free
    low, high = transmission_angle_range_deg(optimum)
    assert low >= 40.0 - 1e-6 and high <= 120.0 + 1e-6
    # both limits bind at the optimum
    assert low == pytest.approx(40.0, abs=1e-6) and high == pytest.approx(120.0, abs=1e-6)
    # the kinematics module agrees over a dense revolution
    table = optimum.analyse(np.arange(0.0, 360.0, 0.25), crank_speed=1.0)
    assert table["transmission_angle_deg"].min() >= 40.0 - 1e-6
    assert table["transmission_angle_deg"].max() <= 120.0 + 1e-6


def test_swing_matches_the_kinematics_and_beats_the_start(result):
    assert result.optimum_swing_deg == pytest.approx(result.optimum.swing_angle_deg(), abs=1e-6)
    assert result.initial_swing_deg == pytest.approx(START.swing_angle_deg(), rel=1e-12)
    assert result.optimum_swing_deg > result.initial_swing_deg + 40.0


def test_no_grid_point_beats_the_optimum(result):
    # Brute force over the same bounds (ground 12): every feasible crank-rocker on
    # a 0.1-unit grid swings no more than the optimum, and the best comes close.
    crank, coupler, rocker = np.meshgrid(np.arange(1, 6.001, 0.1), np.arange(5, 20.001, 0.1),
                                         np.arange(5, 15.001, 0.1), indexing="ij")
    ground = 12.0
    common = coupler**2 + rocker**2
    cos_min_mu = (common - (ground - crank) ** 2) / (2 * coupler * rocker)
    cos_max_mu = (common - (ground + crank) ** 2) / (2 * coupler * rocker)
    shortest = (crank <= coupler) & (crank <= rocker) & (crank <= ground)
    longest = np.maximum(np.maximum(coupler, rocker), ground)
    grashof = crank + longest <= crank + coupler + rocker + ground - crank - longest
    feasible = (shortest & grashof & (cos_min_mu <= math.cos(math.radians(40)))
                & (cos_max_mu >= math.cos(math.radians(120))))

    def pivot_angle(pivot_to_b):
        return np.arccos(np.clip((ground**2 + rocker**2 - pivot_to_b**2) / (2 * ground * rocker),
                                 -1, 1))

    swing = np.degrees(pivot_angle(coupler + crank) - pivot_angle(coupler - crank))
    assert feasible.sum() > 1000
    assert swing[feasible].max() <= result.optimum_swing_deg + 1e-9
    assert swing[feasible].max() >= result.optimum_swing_deg - 2.0


def test_bad_bounds_are_refused():
    with pytest.raises(ValueError, match=r"crank_bounds = \(6, 1\) length units is inverted"):
        design_fourbar(START, crank_bounds=(6, 1), coupler_bounds=(5, 20), rocker_bounds=(5, 15))
    with pytest.raises(ValueError, match=r"rocker_bounds lower = 0 is outside the allowed range"):
        design_fourbar(START, crank_bounds=(1, 6), coupler_bounds=(5, 20), rocker_bounds=(0, 15))
    with pytest.raises(ValueError, match=r"transmission_angle_bounds_deg = \(0, 120\)"):
        design_fourbar(START, **BOUNDS, transmission_angle_bounds_deg=(0, 120))


def test_the_design_reads_well_and_writes_its_report_from_itself(result, tmp_path):
    import json

    import sso

    text = repr(result)
    assert len(text) <= 400 and "\n" not in text
    assert text.startswith("FourBarDesignResult(success: swing ")
    summary = result.summary()
    assert "transmission angle of the optimum: 40 .. 120 deg" in summary
    assert "cross-check of the solvers' own answers: solvers agree" in summary
    assert "<table>" in result._repr_html_()
    # the result holds no crank angles: no table.csv, whatever the formats
    written = sso.write_report(result, tmp_path / "design", formats=("json", "csv", "md"))
    assert sorted(path.name for path in written) == ["report.md", "result.json"]
    saved = json.loads((tmp_path / "design" / "result.json").read_text())
    assert saved["type"] == "FourBarDesignResult"
    assert saved["optimum"]["crank"] == result.optimum.crank
    assert sso.FourBarDesignResult.from_dict(saved) == result
