"""``sso`` on driveline case files: the shipped ones run and their reports read back; bad
ones (bad slopes, zero-length shafts, walls at the radius, speeds over critical) exit 2
with the key named and no traceback, and a fuzz of the shipped cases never tracebacks."""

from __future__ import annotations

import json
import tomllib
from pathlib import Path
from typing import Any

import pytest
from fuzzing import run_sso, toml_document
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sso._reports.kinds import write_report
from sso._run.driveline import DrivelineRun

ROOT = Path(__file__).resolve().parents[2]
PICKUP = ROOT / "cases" / "driveline_compound_pickup.toml"
SHIPPED = sorted(path for path in ROOT.glob("cases/driveline_*.toml")
                 if 'kind = "driveline"' in path.read_text(encoding="utf-8"))


def pickup(**tables: dict[str, Any]) -> dict[str, Any]:
    document = tomllib.loads(PICKUP.read_text(encoding="utf-8"))
    for table, changes in tables.items():
        document.setdefault(table, {}).update(changes)
    return document


@pytest.mark.parametrize(("tables", "message"), [
    ({"measurements": {"gearbox_slope_deg": 60.0}},
     "measurements.gearbox_slope_deg = 60 is outside the allowed range [-45, 45] deg"),
    ({"measurements": {"shaft_slope_deg": [float("nan")]}}, "measurements.shaft_slope_deg[0]"),
    ({"measurements": {"shaft_length_mm": [0.0]}},
     "shaft_length_mm[0] = 0 mm is outside the allowed range (0, inf) mm"),
    ({"tubes": {"wall_mm": [44.45]}},
     "tubes[0]: wall_mm = 44.45 is outside the allowed range (0, 44.45) mm"),
    ({"speed": {"max_shaft_speed_rpm": 20000.0}},
     "max_shaft_speed_rpm = 20000 rpm is outside the allowed range (0, 6602.99) rpm"),
    ({"speed": {"engine_speed_rpm": 3000.0}},
     "give either speed.max_shaft_speed_rpm or both"),
    ({"hardpoints": {"points_mm": [[100, 0, 0], [0, 0, 0], [-100, 0, 5]]}},
     "give either [measurements]"),
    ({"loads": {"torque_n_m": "lots"}}, "loads.torque_n_m"),
    ({"layout": {"pinion_slope_deg": [4.0, 1.0]}},
     "layout.pinion_slope_deg = (4, 1) deg is inverted (empty)"),
    ({"layout": {"pinion_slope_deg": [0.0, 60.0]}},
     "layout.pinion_slope_deg[1] = 60 is outside the allowed range [-45, 45] deg"),
    ({"layout": {"pinion_slope_deg": [1.0]}}, "layout.pinion_slope_deg"),
    ({"layout": {"centre_bearing_height_mm": [[-10.0, 10.0]]}},
     "layout.centre_bearing_height_mm has 1 boxes; the driveline has 0 centre bearings"),
    ({"layout": {"centre_bearing_height_mm": [10.0, -10.0]}},
     "layout.centre_bearing_height_mm = (10, -10) mm is inverted"),
])
def test_bad_driveline_case_exits_2_naming_the_key(tables: dict[str, Any], message: str,
                                                   tmp_path: Path) -> None:
    case = tmp_path / "bad.toml"
    case.write_text(toml_document(pickup(**tables)), encoding="utf-8")
    for command in ("validate", "run"):
        code, output = run_sso([command, str(case), "--out", str(tmp_path / "out")]
                               if command == "run" else [command, str(case)])
        assert code == 2, output
        assert message in output
        assert "Traceback" not in output
    assert not (tmp_path / "out" / "bad").exists()


def test_shipped_pickup_runs_and_its_report_reads_back(tmp_path: Path) -> None:
    code, output = run_sso(["run", str(PICKUP), "--out", str(tmp_path), "--no-plots"])
    assert code == 0, output
    folder = tmp_path / "driveline_compound_pickup"
    saved = json.loads((folder / "result.json").read_text(encoding="utf-8"))
    run = DrivelineRun.from_dict(saved)
    advice = run.result.phasing
    assert advice is not None
    # in phase the axle sees about 750 rad/s^2 at 3,500 rpm; the advice cancels it
    (torsional,) = [row for row in advice.rows if row.figure == "torsional"]
    assert torsional.given_rad_s2 == pytest.approx(750.0, rel=0.02)
    assert torsional.recommended_rad_s2 < 0.01 * torsional.given_rad_s2
    report = (folder / "report.md").read_text(encoding="utf-8")
    for words in ("gearbox", "propshaft 1", "pinion", "side-view slope", "plan-view angle",
                  "Rules", "Spicer", "Meritor", "Critical speed", "Joint life",
                  "Trade:", "in phase"):
        assert words in report
    code, output = run_sso(["report", str(folder / "result.json")])
    assert code == 0, output


def test_a_result_made_in_python_writes_its_report(tmp_path: Path) -> None:
    from driveline_cases import compound_three_piece

    from sso._driveline.figures import analyse_driveline

    result = analyse_driveline(compound_three_piece(), phasing=False)
    written = write_report(result, tmp_path / "report", formats=("json", "md", "csv"))
    assert {path.name for path in written} >= {"result.json", "report.md", "rules.csv"}
    assert "centre bearing 2" in (tmp_path / "report" / "report.md").read_text(encoding="utf-8")


values = st.one_of(st.floats(allow_nan=True, allow_infinity=True),
                   st.integers(min_value=-10**6, max_value=10**6), st.text(max_size=5),
                   st.lists(st.floats(min_value=-100.0, max_value=5000.0), max_size=4),
                   st.booleans())
KEYS = [("measurements", "gearbox_slope_deg"), ("measurements", "shaft_slope_deg"),
        ("measurements", "shaft_length_mm"), ("measurements", "pinion_slope_deg"),
        ("measurements", "pinion_plan_deg"), ("tubes", "outside_diameter_mm"),
        ("tubes", "wall_mm"), ("tubes", "youngs_modulus_gpa"), ("speed", "max_shaft_speed_rpm"),
        ("loads", "torque_n_m"), ("loads", "centre_bearing_mm"), ("phasing", "yoke_phase_deg"),
        ("rules", "end_tolerance_deg"), ("layout", "pinion_slope_deg")]


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(key=st.sampled_from(KEYS), value=values)
def test_fuzzed_driveline_cases_never_traceback(key: tuple[str, str], value: Any) -> None:
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        case = Path(folder) / "fuzz.toml"
        case.write_text(toml_document(pickup(**{key[0]: {key[1]: value}})), encoding="utf-8")
        code, output = run_sso(["evaluate", str(case), "--out", folder, "--no-plots",
                                "--quiet"])
    assert code in (0, 2), output
    assert "Traceback" not in output


def test_shipped_layout_box_is_chosen_by_run_and_reported(tmp_path: Path) -> None:
    # cases/driveline_car_one_piece.toml: pinion 3 deg as fitted, swinging to 3.8 deg in
    # jounce and 2.2 deg in rebound, a pinion box of 2 to 4 deg.
    case = ROOT / "cases" / "driveline_car_one_piece.toml"
    code, output = run_sso(["run", str(case), "--out", str(tmp_path), "--no-plots"])
    assert code == 0, output
    folder = tmp_path / "driveline_car_one_piece"
    run = DrivelineRun.from_dict(json.loads((folder / "result.json").read_text(encoding="utf-8")))
    advice, layout = run.result.phasing, run.result.layout
    assert advice is not None and layout is not None
    # the jounce excursion leaves no slack: the margin sets the pinion short of 3 deg ...
    assert advice.pinion_slope_deg is not None and 2.0 < advice.pinion_slope_deg < 3.0
    assert advice.worst_ratio_recommended < advice.worst_ratio_given
    # ... and the design position's cancellation is what it costs, said in the report
    assert any(change.rule == "torsional excitation" and change.where.startswith("design")
               for change in layout.trades)
    report = (folder / "report.md").read_text(encoding="utf-8")
    assert "Layout within its box" in report and "pinion slope" in report
    code, output = run_sso(["evaluate", str(case), "--out", str(tmp_path / "as_given"),
                            "--no-plots"])
    assert code == 0, output
    saved = json.loads((tmp_path / "as_given" / "driveline_car_one_piece" / "result.json")
                       .read_text(encoding="utf-8"))
    assert DrivelineRun.from_dict(saved).result.layout is None  # evaluate: as given
