"""Case files of kind ``driveline``: the two ways to give the joints, positions, speed from the
engine, errors naming the key, and the saved form read back."""

from __future__ import annotations

from pathlib import Path

import pytest

from sso._cases.schema import CaseError, load_case, parse_case

ROOT = Path(__file__).resolve().parents[2]
TRUCK = ROOT / "cases" / "driveline_truck_two_piece.toml"


def test_measurements_and_points_give_one_driveline() -> None:
    case = load_case(TRUCK)
    measured = case.driveline()
    document = case.to_dict()
    del document["measurements"]
    document["hardpoints"] = {"points_mm": [list(point) for point in measured.points_mm]}
    from_points = parse_case(document).driveline()
    assert from_points.geometry.beta_deg == pytest.approx(measured.geometry.beta_deg,
                                                          abs=1e-12)
    # the top speed from the engine: 2250 rpm over a top gear of 0.9
    assert measured.max_shaft_speed_rpm == pytest.approx(2500.0, rel=1e-15)
    assert [position.name for position in measured.positions] == ["laden", "wind_up"]


SHIPPED = sorted(path for path in ROOT.glob("cases/driveline_*.toml")
                 if 'kind = "driveline"' in path.read_text(encoding="utf-8"))


def test_four_drivelines_are_shipped() -> None:
    assert [path.stem for path in SHIPPED] == [
        "driveline_car_one_piece", "driveline_compound_pickup", "driveline_truck_three_piece",
        "driveline_truck_two_piece"]


@pytest.mark.parametrize("path", SHIPPED, ids=lambda path: path.stem)
def test_shipped_driveline_case_round_trips(path: Path) -> None:
    case = load_case(path)
    assert case.name == path.stem and case.description
    assert parse_case(case.to_dict(), str(path)) == case


@pytest.mark.parametrize(("change", "message"), [
    ({"measurements": {"positions": {"laden": {"pinion_angle": 1.0}}}},
     "measurements.positions.laden.pinion_angle is not a measurement"),
    ({"loads": {"gearbox_bearings_mm": [1.0]}}, "loads.gearbox_bearings_mm = [1.0] must be 2"),
    ({"tubes": {"wall_mm": [2.4]}}, "tubes.wall_mm has 1 entries"),
])
def test_bad_keys_are_named(change: dict[str, dict[str, object]], message: str) -> None:
    document = load_case(TRUCK).to_dict()
    for table, values in change.items():
        document[table].update(values)
    with pytest.raises(CaseError, match=message.replace("[", r"\[").replace("]", r"\]")):
        parse_case(document)
