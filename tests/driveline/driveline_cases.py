"""Drivelines the tests share (values chosen by hand; none is a published case)."""

from __future__ import annotations

from sso._driveline.model import Driveline
from sso._driveline.tube import Tube

TRUCK_TUBE = Tube(outside_diameter_mm=101.6, wall_mm=2.4)


def truck_two_piece(**options: object) -> Driveline:
    """Joints at 3, 2.5 and 4 deg in side view; 1.2 and 1.4 m tubes; 2,500 rpm."""
    return Driveline.from_measurements(
        gearbox_slope_deg=3.0, shaft_slope_deg=[0.0, 2.5], shaft_length_mm=[1200.0, 1400.0],
        pinion_slope_deg=-1.5, tubes=(TRUCK_TUBE, TRUCK_TUBE), max_shaft_speed_rpm=2500.0,
        torque_n_m=3000.0, **{"centre_bearing_mm": (80.0,), **options})  # type: ignore[arg-type]


def compound_pickup(**options: object) -> Driveline:
    """One piece; two true angles of about 3.04 deg whose planes are 82 deg apart."""
    return Driveline.from_measurements(
        gearbox_slope_deg=3.04, shaft_slope_deg=[0.0], shaft_length_mm=[1500.0],
        pinion_slope_deg=-0.42, pinion_plan_deg=3.01, tubes=(Tube(88.9, 2.1),),
        max_shaft_speed_rpm=3500.0, torque_n_m=1500.0, **options)  # type: ignore[arg-type]


def planar_one_piece(**options: object) -> Driveline:
    """A car's one-piece shaft, planar, equal angles (3 deg) in a W: in phase cancels."""
    return Driveline.from_measurements(
        gearbox_slope_deg=3.0, shaft_slope_deg=[0.0], shaft_length_mm=[1400.0],
        pinion_slope_deg=3.0, tubes=(Tube(88.9, 2.1),), max_shaft_speed_rpm=5000.0,
        torque_n_m=800.0, **options)  # type: ignore[arg-type]


def compound_three_piece(**options: object) -> Driveline:
    """Three propshafts with plan offsets and an odd phasing: every figure exercised."""
    return Driveline.from_measurements(
        gearbox_slope_deg=3.5, shaft_slope_deg=[1.0, 2.0, 0.5],
        shaft_length_mm=[1300.0, 1250.0, 1450.0], shaft_offset_mm=[20.0, -35.0, 15.0],
        pinion_slope_deg=-2.0, pinion_plan_deg=1.0,
        tubes=(TRUCK_TUBE, TRUCK_TUBE, TRUCK_TUBE), max_shaft_speed_rpm=2800.0,
        torque_n_m=4000.0, centre_bearing_mm=(90.0, 70.0), yoke_phase_deg=(25.0, -40.0, 10.0),
        **options)  # type: ignore[arg-type]
