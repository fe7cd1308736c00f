"""The report of a four-bar design made in Python is rendered from the result alone.

Reference values: the design of tests/reports/test_records.py (start 2 / 15 / 9 / 12,
crank 1..3, coupler 12..18, rocker 6..12): the optimum is read from the result and
checked against the four-bar's own closed forms (the rocker swing from the law of
cosines at the two limit positions, the transmission-angle extremes at theta = 0 and
180 deg), written out here independently of the solver.
"""

from __future__ import annotations

import json
import math

import pytest

import sso
from sso._reports.kinds import render_report


@pytest.fixture(scope="module")
def design() -> sso.FourBarDesignResult:
    return sso.optimise(sso.FourBar(ground=12, crank=2, coupler=15, rocker=9),
                        crank_bounds=(1.0, 3.0), coupler_bounds=(12.0, 18.0),
                        rocker_bounds=(6.0, 12.0), starts=2)


def swing_deg(crank: float, coupler: float, rocker: float, ground: float) -> float:
    """Rocker swing between the extended and folded limit positions (law of cosines)."""
    def pivot_angle(reach: float) -> float:
        return math.acos((rocker**2 + ground**2 - reach**2) / (2.0 * rocker * ground))

    return math.degrees(pivot_angle(coupler + crank) - pivot_angle(coupler - crank))


def test_the_report_shows_the_result_s_own_numbers(design, tmp_path):
    optimum = design.optimum
    assert design.optimum_swing_deg == pytest.approx(
        swing_deg(optimum.crank, optimum.coupler, optimum.rocker, optimum.ground), rel=1e-9)
    written = sso.write_report(design, tmp_path / "report")
    # no drive or plot settings in a design result: no table over crank angle, no plot
    assert sorted(path.name for path in written) == ["report.html", "report.md", "result.json"]
    markdown = (tmp_path / "report" / "report.md").read_text()
    assert f"| optimum ({design.best.solver}) | 3 | {optimum.coupler:.6g} | 6 | 12 | " \
           f"{design.optimum_swing_deg:.6g} |" in markdown
    low, high = design.optimum_transmission_angle_deg
    # cos mu = (b^2 + c^2 - (d -+ a)^2) / (2 b c) at theta = 0 and 180 deg
    b, c = optimum.coupler, optimum.rocker
    extremes = sorted(math.degrees(math.acos((b**2 + c**2 - (optimum.ground + sign
                                                              * optimum.crank) ** 2)
                                             / (2.0 * b * c))) for sign in (-1.0, 1.0))
    assert (low, high) == pytest.approx(tuple(extremes), rel=1e-9)
    assert f"| 40 | 120 | {low:.6g} to {high:.6g} |" in markdown
    assert design.crosscheck.message in markdown
    saved = json.loads((tmp_path / "report" / "result.json").read_text())
    assert sso.FourBarDesignResult.from_dict(saved) == design


def test_the_report_of_a_reloaded_design_is_the_same(design):
    reloaded = sso.FourBarDesignResult.from_dict(design.to_dict())
    assert render_report(reloaded, ("md", "html")) == render_report(design, ("md", "html"))
