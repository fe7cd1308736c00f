"""Every public result is its own record: made through the public API, reported with
``sso.write_report``, and read back from its ``result.json`` into an equal object."""

from __future__ import annotations

import json
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import jsonschema
import numpy as np
import pytest

import sso
from sso._cli.saved_results import result_schema, shipped_schema
from sso._display import REPR_LIMIT
from sso._record import RECORD_VERSION, Record

# The column of tests/data/columns/truck_three_positions.json (tilt down), three joints.
TILT_DOWN = ((0.0, 0.0, 0.0), (0.0, 0.0, 300.0), (40.0, 25.0, 620.0), (130.0, 60.0, 850.0),
             (230.0, 60.0, 1050.0))
TILT_UP = ((0.0, 0.0, 0.0), (0.0, 0.0, 300.0), (45.0, 20.0, 630.0), (130.0, 62.0, 860.0),
           (230.0, 60.0, 1050.0))
SERIES = sso.ShaftSeries([10.0, 15.0, 12.0], [80.0, 95.0])


def column() -> sso.ColumnGeometry:
    return sso.ColumnGeometry(TILT_DOWN)


def phasing() -> sso.PhasingResult:
    return sso.optimise(column(), starts=2)


def tolerances() -> sso.Tolerances:
    return sso.Tolerances(hardpoint_mm=0.5, yoke_phase_deg=0.5, samples=20, seed=3)


CASES = Path(__file__).resolve().parents[2] / "cases"

# The tilt-down column with its positions, tolerances, band and feel, on splines.
COLUMN_CASE = f"""
kind = "column"
name = "tilt_down"

[hardpoints]
points_mm = {[list(point) for point in TILT_DOWN]}

[hardpoints.positions]
down = {[list(point) for point in TILT_DOWN]}
up = {[list(point) for point in TILT_UP]}

[splines]
teeth = [24, 24]

[tolerances]
hardpoint_mm = 0.5
yoke_phase_deg = 0.5
samples = 20

[band]
re_limit = 1e-3

[feel]
straight_ahead_deg = 45.0
lock_deg = 600.0

[solver]
starts = 2
"""


def column_run() -> sso.ColumnRun:
    """What ``sso run`` of a column case returns (the command saves it as result.json)."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "tilt_down.toml"
        path.write_text(COLUMN_CASE)
        run = sso.run_case(path)
    assert isinstance(run, sso.ColumnRun)
    return run


MAKERS: dict[str, Callable[[], Any]] = {
    "ColumnRun": column_run,
    "DrivelineRun": lambda: sso.run_case(CASES / "driveline_compound_pickup.toml"),
    "DrivelineResult": lambda: sso.analyse_driveline(sso.Driveline.from_measurements(
        gearbox_slope_deg=3.0, shaft_slope_deg=[0.0, 2.5], shaft_length_mm=[1200.0, 1400.0],
        pinion_slope_deg=-1.5, tubes=(sso.Tube(101.6, 2.4), sso.Tube(101.6, 2.4)),
        max_shaft_speed_rpm=2500.0, torque_n_m=3000.0, centre_bearing_mm=(80.0,))),
    "ShaftSeriesRun": lambda: sso.run_case(CASES / "paper_option3_exact.toml"),
    "MechanismRun": lambda: sso.run_case(CASES / "mechanisms" / "fourbar_swing_design.toml"),
    "OptimisationResult": lambda: sso.optimise(SERIES, 1, starts=2),
    "PhasingResult": phasing,
    "SplineResult": lambda: sso.optimise(column(), teeth=24),
    "CancelVerdict": lambda: sso.can_cancel(column().beta_deg),
    "ToleranceBand": lambda: sso.tolerance_band(phasing(), re_limit=2.0 * phasing().fun + 1e-6),
    "SampleStudy": lambda: sso.optimise(column(), tolerances=tolerances(), starts=2).robust_study,
    "SteeringFeel": lambda: sso.steering_feel((column(), (10.0, -60.0)),
                                              straight_ahead_deg=20.0, lock_deg=540.0),
    "OnCentreResult": lambda: sso.optimise(column(), straight_ahead_deg=45.0, lock_deg=600.0,
                                             starts=2),
    "PositionsResult": lambda: sso.optimise(
        {"tilt_down": column(), "tilt_up": sso.ColumnGeometry(TILT_UP)}, starts=2),
    "RobustResult": lambda: sso.optimise(column(), tolerances=tolerances(), starts=2),
    "JointCentresResult": lambda: sso.optimise(
        column(), joint_boxes_mm=[[[x - 5.0, y - 5.0, z - 5.0], [x + 5.0, y + 5.0, z + 5.0]]
                                  for x, y, z in TILT_DOWN[1:-1]], starts=2),
    "SteeringRange": lambda: sso.steering_range((column(), (10.0, -60.0)), lock_deg=540.0),
    "SteeringAssessment": lambda: sso.assess_steering(
        column(), [("as_built", "as built", (0.0, 0.0)), ("best", "best", phasing().x)],
        lock_deg=540.0),
    "ExcitationTable": lambda: sso.excitation_table(SERIES, [1000.0, 2500.0], vehicle="car"),
    "SweepResult": lambda: sso.sweep({"design": {"beta_deg": [20.0]}},
                                     {"design.beta_deg[0]": [10.0, 20.0]}, action="evaluate",
                                     workers=1, plots=False, progress=False),
    "ToleranceResult": lambda: sso.tolerance_study(SERIES, beta_tolerance_deg=0.5, samples=30,
                                                   seed=1),
    "ColumnToleranceResult": lambda: sso.tolerance_study((column(), (10.0, -60.0)),
                                                         tolerances=tolerances(), workers=1),
    "FourBarDesignResult": lambda: sso.optimise(
        sso.FourBar(ground=12, crank=2, coupler=15, rocker=9), crank_bounds=(1.0, 3.0),
        coupler_bounds=(12.0, 18.0), rocker_bounds=(6.0, 12.0), starts=2),
    "MechanismTable": lambda: sso.FourBar(ground=12, crank=4, coupler=15, rocker=9).analyse(
        np.arange(0.0, 360.0, 30.0), crank_speed=1.0),
    "BatchResult": lambda: sso.optimise_batch([[10.0, 15.0], [20.0, 5.0]], [[90.0], [45.0]],
                                              option=3),
}


def public_result_classes() -> set[str]:
    """Every class in ``sso.__all__`` that is a record."""
    return {name for name in sso.__all__ if isinstance(getattr(sso, name), type)
            and issubclass(getattr(sso, name), Record)}


def test_every_public_result_class_has_a_maker_here():
    assert public_result_classes() == set(MAKERS)


@pytest.mark.parametrize("name", sorted(MAKERS))
def test_result_is_its_own_record(name, tmp_path):
    result = MAKERS[name]()
    assert type(result).__name__ == name
    written = sso.write_report(result, tmp_path / "report", formats=("json", "md", "html"))
    assert {path.name for path in written} >= {"result.json", "report.md", "report.html"}
    saved = json.loads((tmp_path / "report" / "result.json").read_text())
    assert saved["version"] == RECORD_VERSION and saved["type"] == name
    reloaded = type(result).from_dict(saved)
    assert reloaded == result
    assert reloaded.to_dict() == result.to_dict()
    assert reloaded.summary() == result.summary()
    # one line of at most 400 characters; the summary and the notebook view exist
    assert "\n" not in repr(result) and len(repr(result)) <= REPR_LIMIT
    assert result.summary().strip() and result._repr_html_().startswith("<div>")
    markdown = (tmp_path / "report" / "report.md").read_text()
    assert markdown.startswith("# ")
    jsonschema.Draft202012Validator(shipped_schema()).validate(saved)


def test_the_shipped_result_schema_is_the_generated_one():
    # If this fails, regenerate: python -m sso._cli.saved_results --output sso/result.schema.json
    assert shipped_schema() == json.loads(json.dumps(result_schema()))
    jsonschema.Draft202012Validator.check_schema(shipped_schema())


def test_a_reloaded_optimisation_recomputes_nothing():
    result = sso.optimise(SERIES, 1, starts=2)
    reloaded = sso.OptimisationResult.from_dict(result.to_dict())
    # the evaluations were saved and are read back, not evaluated again
    assert "initial" in reloaded.__dict__ and "optimum" in reloaded.__dict__
    assert reloaded.optimum.residual_error == result.optimum.residual_error


def test_the_set_of_exact_optima_is_saved_without_its_callable(tmp_path):
    # Option 3 of three joints cancels (RE at round-off zero on a set of designs):
    # sso.optimise chooses within the set by the largest margin to the bounds.
    result = sso.optimise(sso.ShaftSeries([20.0, 30.0, 25.0], [0.0, 90.0]), 3, starts=2)
    exact = result.exact_optima
    assert exact is not None and exact.extent_of is not None
    sso.write_report(result, tmp_path / "report", formats=("json", "md"))
    saved = json.loads((tmp_path / "report" / "result.json").read_text())
    assert "extent_of" not in saved["exact_optima"]
    reloaded = sso.OptimisationResult.from_dict(saved)
    assert reloaded == result
    assert reloaded.exact_optima is not None and reloaded.exact_optima.extent_of is None
    # the extent is the one computed before saving, read back, not searched again
    assert reloaded.exact_optima.extent == exact.extent
    assert len(exact.extent) == len(exact.variables) == 5
    for (low, high), chosen in zip(exact.extent, exact.chosen, strict=True):
        assert low <= chosen <= high
    markdown = (tmp_path / "report" / "report.md").read_text()
    assert "### Exact optima" in markdown  # in the numerics section
    assert f"The reported optimum was found by {result.found_by}." in markdown
    assert "| solver | run |" in markdown
