"""The figures an engineer signs lead a column run's summary and report, and the trade
of the design recommended is said (issue 35, items 5 and 6).

The situation: cases/column_truck_trade.toml, a truck's three-joint driveline
with its yokes in phase, at 500 to 2,500 rpm. Its best 36-tooth phasing cuts the
torsional excitation at 2,500 rpm but raises the drive inertial excitation. The
excitation at 2,500 rpm is checked here against the SAE AE-7 small-angle form
written out from the hardpoints with numpy alone (operating angles from the shafts'
directions, bend planes from their cross products, the phasor sum of
sso/_column/excitation.py's module notes), not through sso's geometry or excitation
code.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import sso
from sso._reports.column_report import column_blocks
from sso._reports.markdown import render_markdown
from sso._reports.summary import NUMERICS_HEADING
from sso._run.signed_figures import SignedFigure

ROOT = Path(__file__).resolve().parents[2]
DRIVELINE = ROOT / "cases" / "column_truck_trade.toml"
TOP_RPM = 2500.0


def sae_excitation_rad_s2(points_mm: list[list[float]], yoke_phase_deg: list[float],
                          rpm: float) -> dict[str, float]:
    """Drive, coast and torsional excitation, rad/s^2, from the hardpoints alone."""
    points = np.asarray(points_mm, dtype=float)
    shafts = np.diff(points, axis=0)
    shafts /= np.linalg.norm(shafts, axis=1)[:, None]
    joints = len(shafts) - 1
    beta_deg = [math.degrees(math.acos(np.clip(shafts[k] @ shafts[k + 1], -1.0, 1.0)))
                for k in range(joints)]
    normals = [np.cross(shafts[k], shafts[k + 1]) for k in range(joints)]
    normals = [normal / np.linalg.norm(normal) for normal in normals]
    # gamma_k: about intermediate shaft k, from bend plane k to bend plane k+1 (right hand)
    gamma_deg = [math.degrees(math.atan2(np.cross(normals[k], normals[k + 1]) @ shafts[k + 1],
                                         normals[k] @ normals[k + 1]))
                 for k in range(joints - 1)]
    # model phase phi_k = 90 + delta_k - gamma_k; joint j's phasor beta_j^2 exp(2 i Phi_j)
    phases = [math.radians(90.0 + delta - gamma)
              for delta, gamma in zip(yoke_phase_deg, gamma_deg, strict=True)]
    accumulated = np.concatenate([[0.0], np.cumsum(phases)])
    phasors = np.asarray(beta_deg) ** 2 * np.exp(2j * accumulated)
    number = np.arange(1, joints + 1)
    omega_squared = (rpm * 2.0 * math.pi / 60.0) ** 2
    angles = {"drive": abs(np.sum((joints - number) * phasors)),
              "coast": abs(np.sum((number - 1) * phasors)), "torsional": abs(np.sum(phasors))}
    return {name: omega_squared * math.sin(math.radians(math.sqrt(value))) ** 2
            for name, value in angles.items()}


@pytest.fixture(scope="module")
def driveline():
    return sso.run_case(DRIVELINE)


def test_the_driveline_trades_drive_for_torsional_excitation(driveline):
    points = [list(point) for point in driveline.case.values["hardpoints.points_mm"]]
    given = sae_excitation_rad_s2(points, [0.0, 0.0], TOP_RPM)
    recommended = sae_excitation_rad_s2(
        points, list(driveline.assembly(driveline.recommended).yoke_phase_deg), TOP_RPM)
    figures = {figure.name: figure for figure in driveline.signed_figures}
    for kind, name in (("drive", "drive inertial excitation"),
                       ("torsional", "torsional excitation")):
        figure = figures[f"{name} at 2500 rpm"]
        assert figure.as_given == pytest.approx(given[kind], rel=1e-9)
        assert figure.recommended == pytest.approx(recommended[kind], rel=1e-9)
    # the case's description: drive 150 -> 807, torsional 439 -> 30 rad/s2
    assert round(given["drive"]) == 150 and round(recommended["drive"]) == 807
    assert round(given["torsional"]) == 439 and round(recommended["torsional"]) == 30
    worse = [figure.name for figure in driveline.signed_figures if figure.worse]
    assert worse == ["drive inertial excitation at 2500 rpm"]


def test_summary_and_report_lead_with_signed_figures_and_say_the_trade(driveline):
    trade = ("Trade: the design recommended makes worse drive inertial excitation at 2500 rpm "
             "150.3 to 806.7 rad/s2 (5.37 times)")
    summary = driveline.summary()
    first, second = summary.splitlines()[:2]
    assert first.startswith("Case column_truck_trade (column, optimise): OK: speed-ratio "
                            "fluctuation (lock to lock) 0.6428 to 0.04498 %; largest "
                            "transmission error (lock to lock) 0.1812 to 0.009469 deg;")
    assert "torsional excitation at 2500 rpm 438.8 to 30.38 rad/s2; RE " in first
    assert first.index("fluctuation") < first.index("RE ")
    assert second == trade
    report = render_markdown(column_blocks(driveline, ()))
    verdict = report.split("## Verdict", 1)[1]
    assert verdict.split("\n\n")[1].startswith("OK: speed-ratio fluctuation (lock to lock)")
    assert verdict.split("\n\n")[2] == trade
    numerics = report.split(f"## {NUMERICS_HEADING}", 1)
    assert "Optimization terminated successfully" not in numerics[0]  # solver words below
    assert driveline.verdict in numerics[1]


def test_no_trade_where_nothing_gets_worse():
    better = SignedFigure("torsional excitation at 2500 rpm", "rad/s2", 438.8, 30.4)
    rounding = SignedFigure("drive inertial excitation at 100 rpm", "rad/s2", 11.16, 11.1601)
    assert not better.worse and not rounding.worse  # +0.001 %, under WORSE_FRACTION
    assert SignedFigure("coast", "rad/s2", 100.0, 112.0).growth() == "+12 %"


def test_the_assembly_on_the_splines_is_one_row_of_the_steering_table():
    # cases/column_truck_three_positions.toml recommends the positions' phasing on the
    # splines, which is also one of its robust designs (issue 35, item 8: the row twice).
    run = sso.run_case(ROOT / "cases" / "column_truck_three_positions.toml")
    labels = [design.label for design in run.steering.designs]
    assert len(labels) == len(set(labels))
    assert labels.count("one phasing for every position (worst), on the splines "
                        "(whole teeth)") == 1
