"""A driveline case run: ``sso evaluate`` analyses as assembled, ``sso run`` also phases."""

from __future__ import annotations

from pathlib import Path

import pytest

from sso._cases.schema import load_case
from sso._run.driveline import DrivelineRun, run_driveline

PICKUP = Path(__file__).resolve().parents[2] / "cases" / "driveline_compound_pickup.toml"


def test_evaluate_and_run() -> None:
    case = load_case(PICKUP)
    evaluated = run_driveline(case, optimising=False)
    assert evaluated.mode == "evaluate" and evaluated.result.phasing is None
    assert evaluated.verdict.startswith("1 rule checks fail (first: torsional excitation")
    run = run_driveline(case, optimising=True)
    assert run.result.phasing is not None
    (delta,) = run.result.phasing.yoke_phase_deg
    # the cancelling phasing is the plane angle between the two joints (82.06 deg)
    assert delta == pytest.approx(82.06, abs=0.05)
    assert DrivelineRun.from_dict(run.to_dict()) == run
