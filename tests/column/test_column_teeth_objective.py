"""The fitter's teeth are those of the objective the case optimised (positions, tolerances).

Reference: the independent 3D cross-and-yoke simulation (``cross_and_yoke``: pin axes
kept perpendicular by the cross, no joint law, no chain matrix), evaluated position by
position at the hardpoints read from the case file itself (``tomllib``), and a brute
force over every assembly of two 36-tooth splines.
"""

from __future__ import annotations

import itertools
import json
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest
from cross_and_yoke import residual_error as simulated_residual_error

import sso
from sso._cli.app import main

CASES = Path(__file__).resolve().parents[2] / "cases"
THREE_POSITIONS = CASES / "column_truck_three_positions.toml"


def _positions() -> dict[str, np.ndarray]:
    case = tomllib.loads(THREE_POSITIONS.read_text(encoding="utf-8"))
    return {name: np.array(points, dtype=float)
            for name, points in case["hardpoints"]["positions"].items()}


def _worst_simulated(yoke_phase_deg) -> float:
    return max(simulated_residual_error(points, np.asarray(yoke_phase_deg, dtype=float))
               for points in _positions().values())


@pytest.fixture(scope="module")
def three_position_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("run")
    assert main(["run", str(THREE_POSITIONS), "--out", str(out), "--no-plots", "--quiet"]) == 0
    folder = out / "column_truck_three_positions"
    return (sso.ColumnRun.from_dict(json.loads((folder / "result.json").read_text(
        encoding="utf-8"))), (folder / "report.md").read_text(encoding="utf-8"))


def test_the_instructed_teeth_give_the_worst_position_re_the_report_shows(three_position_run):
    run, report = three_position_run
    assert run.recommended == "splines"
    splines = run.splines
    assert splines.objective == "worst-position RE"
    # the fitter's instructions, as data: teeth and tooth offsets per shaft
    instructions = splines.instructions
    yoke = [item.tooth_offset * 360.0 / item.teeth for item in instructions]
    worst = _worst_simulated(yoke)
    assert splines.residual_error == pytest.approx(worst, rel=1e-9)
    optimum = run.optimum
    assert optimum.objective == "worst-position RE"
    assert optimum.objective_at_teeth == pytest.approx(worst, rel=1e-9)
    assert optimum.objective_continuous == pytest.approx(
        run.robust.positions.result.worst_re, rel=1e-12)
    # the report shows that value (6 digits) beside the continuous one, and the same
    # instructions
    shown = re.search(r"Best on the splines for the worst-position RE: (\S+) at the teeth, "
                      r"against (\S+) for the continuous phasing of that objective", report)
    assert shown is not None
    assert float(shown.group(1)) == pytest.approx(worst, rel=1e-5)
    for item in instructions:
        assert item.text in report
    # the teeth of RE at the hardpoints alone are kept, apart
    assert run.nominal_splines.objective == "RE"


def test_the_shared_phasing_on_splines_is_the_best_assembly_by_brute_force():
    geometries = {name: sso.ColumnGeometry(points) for name, points in _positions().items()}
    shared = sso.optimise(geometries, positions_objective="worst")
    teeth = shared.on_splines(36)
    assert teeth.objective == "worst-position RE"
    assert teeth.residual_error == pytest.approx(_worst_simulated(teeth.yoke_phase_deg),
                                                 rel=1e-9)
    assert teeth.continuous_residual_error == pytest.approx(shared.worst_re, rel=1e-12)
    # every assembly of two 36-tooth splines (offsets 10 deg apart; a pin axis is a line,
    # so 18 per shaft), by the simulation: none is better
    grid = np.arange(-8, 10) * 10.0
    values = [_worst_simulated(pair) for pair in itertools.product(grid, grid)]
    assert teeth.residual_error <= min(values) * (1.0 + 1e-9)


def test_the_tolerance_aware_phasing_on_splines_has_its_objective_at_the_teeth():
    # The case's [tolerances] (1 mm, 1 deg, 200 columns, seed 1, p95) on its hardpoints.
    # Reference: every built column simulated in 3D (points + its hardpoint errors, yoke
    # phasing + its yoke errors), and the objective as its definition says: the mean of
    # RE over the worst 5 % of the built columns (10 of 200, equal weights).
    case = tomllib.loads(THREE_POSITIONS.read_text(encoding="utf-8"))
    geometry = sso.ColumnGeometry(case["hardpoints"]["points_mm"])
    tolerances = sso.Tolerances(hardpoint_mm=1.0, yoke_phase_deg=1.0, samples=200, seed=1)
    robust = sso.optimise(geometry, tolerances=tolerances, robust_objective="p95")
    teeth = robust.on_splines(36)
    # "p95" asks for the CVaR at level 0.95: the mean of the worst 5 %, named CVaR95
    assert teeth.objective == ("CVaR95 of RE over the built columns (the mean of the worst "
                               "5 %)")
    sample = tolerances.sample(geometry)
    points = np.asarray(geometry.points_mm)

    def tail_mean(yoke):
        values = np.sort([simulated_residual_error(points + offsets, np.add(yoke, errors))
                          for offsets, errors in zip(sample.hardpoint_offsets_mm,
                                                     sample.yoke_phase_errors_deg,
                                                     strict=True)])
        return float(np.mean(values[-10:]))

    assert teeth.residual_error == pytest.approx(tail_mean(teeth.yoke_phase_deg), rel=1e-9)
    assert teeth.continuous_residual_error == pytest.approx(robust.fun, rel=1e-9)
    # no neighbouring assembly (one tooth either way on either shaft) is better
    for shaft, step in itertools.product(range(2), (-10.0, 10.0)):
        neighbour = list(teeth.yoke_phase_deg)
        neighbour[shaft] += step
        assert teeth.residual_error <= tail_mean(neighbour) * (1.0 + 1e-9)
