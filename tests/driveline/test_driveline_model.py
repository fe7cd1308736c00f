"""Bad driveline input: each refused with the field and its allowed range."""

from __future__ import annotations

import pytest
from driveline_cases import truck_two_piece

from sso._driveline.model import Driveline, NamedPosition
from sso._driveline.tube import Tube

MEASURED = dict(gearbox_slope_deg=3.0, shaft_slope_deg=[0.0], shaft_length_mm=[1200.0],
                pinion_slope_deg=3.0, tubes=(Tube(80.0, 2.0),), max_shaft_speed_rpm=3000.0,
                torque_n_m=800.0)


@pytest.mark.parametrize(("change", "message"), [
    ({"shaft_length_mm": [0.0]}, r"shaft_length_mm\[0\] = 0 mm is outside"),
    ({"gearbox_slope_deg": 50.0}, r"gearbox_slope_deg = 50 deg is outside"),
    ({"shaft_slope_deg": [float("nan")]}, r"shaft_slope_deg\[0\]"),
    ({"shaft_offset_mm": [1300.0]}, r"shaft_offset_mm\[0\] = 1300 mm is outside"),
    ({"max_shaft_speed_rpm": -5.0}, r"max_shaft_speed_rpm = -5 is outside"),
    ({"torque_n_m": 0.0}, r"torque_n_m = 0 is outside"),
    ({"tubes": ()}, r"tubes has 0 entries"),
    ({"yoke_phase_deg": (0.0, 1.0)}, r"yoke_phase_deg has 2 entries"),
    ({"application": "marine"}, r"application = 'marine' is not one of"),
    ({"positions": {"laden": {"pinion_slope_deg": 60.0}}},
     r"positions\['laden'\]: pinion_slope_deg = 60 deg"),
    ({"positions": {"laden": {"pinion_angle": 1.0}}}, r"'pinion_angle' is not a measurement"),
    ({"gearbox_slope_deg": 0.0, "pinion_slope_deg": 0.0},
     r"the measurements, as the points P0 .. P\(n\+1\) they give: points_mm are collinear"),
])
def test_bad_measurements_name_the_field(change: dict[str, object], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        Driveline.from_measurements(**{**MEASURED, **change})  # type: ignore[arg-type]


def test_tube_wall_at_the_radius_is_refused() -> None:
    with pytest.raises(ValueError, match=r"wall_mm = 40 is outside the allowed range \(0, 40\)"):
        Tube(outside_diameter_mm=80.0, wall_mm=40.0)


def test_two_piece_needs_its_centre_bearing_ahead_of_the_rear_joint() -> None:
    with pytest.raises(ValueError, match=r"centre_bearing_mm has 0 entries"):
        truck_two_piece(centre_bearing_mm=())
    with pytest.raises(ValueError, match=r"centre_bearing_mm\[0\] = 1300 is outside"):
        truck_two_piece(centre_bearing_mm=(1300.0,))


def test_positions_keep_the_joint_count() -> None:
    driveline = truck_two_piece()
    with pytest.raises(ValueError, match=r"positions\['jounce'\] has 1 joints"):
        Driveline(points_mm=driveline.points_mm, tubes=driveline.tubes,
                  max_shaft_speed_rpm=2500.0, torque_n_m=100.0, centre_bearing_mm=(80.0,),
                  positions=(NamedPosition("jounce", ((1, 0, 0), (0, 0, 0), (-1, 0, 0.1))),))
