"""A fitter's slopes, offsets and lengths against the same driveline written as points.

Reference: the points written by hand from the conventions of
``docs/concepts/driveline-conventions.md``; joint angles from the vector model.
"""

from __future__ import annotations

import math

import numpy as np
from driveline_vector_model import VectorDriveline, unit

from sso._driveline.model import Driveline
from sso._driveline.tube import Tube


def test_slopes_and_offsets_give_the_joint_angles_of_the_equivalent_points() -> None:
    # The same driveline written as 3D points by hand (x forward, y left, z up, mm):
    # gearbox nose 3 deg up, propshaft 1 level 1200 mm running 20 mm to the left, propshaft 2
    # falling 2 deg (front higher) over 1400 mm with 30 mm to the right, pinion 1 deg nose
    # down, turned 1.5 deg with its rear to the left.
    measured = Driveline.from_measurements(
        gearbox_slope_deg=3.0, shaft_slope_deg=[0.0, 2.0], shaft_length_mm=[1200.0, 1400.0],
        shaft_offset_mm=[20.0, -30.0], pinion_slope_deg=-1.0, pinion_plan_deg=1.5,
        tubes=(Tube(90.0, 2.0), Tube(90.0, 2.0)), max_shaft_speed_rpm=3000.0,
        torque_n_m=1000.0, centre_bearing_mm=(60.0,))
    run1 = math.sqrt(1200.0**2 - 20.0**2)
    run2 = math.sqrt(1400.0**2 - 30.0**2)
    joint1 = np.zeros(3)
    joint2 = joint1 + [-run1, 20.0, 0.0]
    joint3 = joint2 + [-run2 * math.cos(math.radians(2)), -30.0,
                       -run2 * math.sin(math.radians(2))]
    ahead = joint1 + 100 * unit(np.array([1.0, 0.0, math.tan(math.radians(3))]))
    behind = joint3 + 100 * unit(np.array([-1.0, math.tan(math.radians(1.5)),
                                           math.tan(math.radians(1.0))]))
    points = [ahead, joint1, joint2, joint3, behind]
    expected = VectorDriveline([list(p) for p in points], [0.0, 0.0]).joint_angles_deg()
    np.testing.assert_allclose(measured.geometry.beta_deg, expected, rtol=0, atol=1e-9)
    np.testing.assert_allclose(measured.points_mm, points, rtol=0, atol=1e-9)
    # the side-view slopes read back as the fitter gave them
    slopes = [math.degrees(math.atan2(-d[2], -d[0])) for d in measured.geometry.shaft_directions]
    np.testing.assert_allclose(slopes, [3.0, 0.0, 2.0, -1.0], rtol=0, atol=1e-12)
