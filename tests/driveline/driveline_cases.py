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


def car_z(**options: object) -> Driveline:
    """A car's one-piece shaft in a Z: gearbox and pinion parallel (both 2 deg nose up), the
    shaft falling 1 deg and running 25 mm to the left; yokes turned 30 deg."""
    return Driveline.from_measurements(
        gearbox_slope_deg=2.0, shaft_slope_deg=[-1.0], shaft_length_mm=[1350.0],
        shaft_offset_mm=[25.0], pinion_slope_deg=2.0, tubes=(Tube(76.2, 1.65),),
        max_shaft_speed_rpm=4500.0, torque_n_m=700.0, yoke_phase_deg=(30.0,),
        **options)  # type: ignore[arg-type]


def car_w(**options: object) -> Driveline:
    """A car's one-piece shaft in a W: gearbox 3 deg nose up, pinion 2 deg nose down."""
    return Driveline.from_measurements(
        gearbox_slope_deg=3.0, shaft_slope_deg=[0.5], shaft_length_mm=[1350.0],
        pinion_slope_deg=-2.0, tubes=(Tube(76.2, 1.65),), max_shaft_speed_rpm=4500.0,
        torque_n_m=700.0, **options)  # type: ignore[arg-type]


def long_shaft_near_critical(**options: object) -> Driveline:
    """A 2.2 m one-piece tube run at 99 % of its critical speed (6,052 rpm)."""
    tube = Tube(76.2, 1.65)
    speed = 0.99 * tube.critical_speed_rpm(2200.0)
    return Driveline.from_measurements(
        gearbox_slope_deg=2.5, shaft_slope_deg=[0.0], shaft_length_mm=[2200.0],
        shaft_offset_mm=[40.0], pinion_slope_deg=1.5, tubes=(tube,), max_shaft_speed_rpm=speed,
        torque_n_m=600.0, **options)  # type: ignore[arg-type]


def phased_compound_two_piece(**options: object) -> Driveline:
    """A two-piece shaft with plan offsets on both propshafts and unequal yoke phasings."""
    return Driveline.from_measurements(
        gearbox_slope_deg=4.0, shaft_slope_deg=[1.5, 3.0], shaft_length_mm=[1100.0, 1500.0],
        shaft_offset_mm=[-30.0, 45.0], pinion_slope_deg=0.5, gearbox_plan_deg=-1.0,
        tubes=(TRUCK_TUBE, TRUCK_TUBE), max_shaft_speed_rpm=3000.0, torque_n_m=2500.0,
        centre_bearing_mm=(70.0,), yoke_phase_deg=(-55.0, 20.0), **options)  # type: ignore[arg-type]


CHECKED = {"truck two-piece": truck_two_piece, "compound pickup": compound_pickup,
           "compound three-piece": compound_three_piece, "car Z": car_z, "car W": car_w,
           "long shaft near critical": long_shaft_near_critical,
           "phased compound two-piece": phased_compound_two_piece}
"""The drivelines checked against the independent vector model, by name."""
