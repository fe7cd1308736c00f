"""Secondary couples and bearing loads.

References: Dana, 'Cardan shafts for industrial applications' pp. 47-48 (closed forms
of the radial bearing loads of a two-joint shaft in Z and W layouts); the equilibrium of
every body of a three-piece shaft, with the cross moments from the independent vector
model's pins.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from driveline_cases import compound_three_piece
from driveline_vector_model import VectorDriveline, unit

from sso._column.geometry import ColumnGeometry
from sso._driveline.loads import BearingGeometry, load_state


def two_joint_shaft(layout: str, beta1_deg: float, beta2_deg: float,
                    length_mm: float) -> ColumnGeometry:
    """Planar shaft in side view: Z (gearbox and pinion parallel) or W (bent back)."""
    b1, b2 = math.radians(beta1_deg), math.radians(beta2_deg)
    gearbox = np.array([-math.cos(b1), 0.0, -math.sin(b1)])
    shaft = np.array([-1.0, 0.0, 0.0])
    angle = b2 if layout == "Z" else -b2
    pinion = np.array([-math.cos(angle), 0.0, -math.sin(angle)])
    first, second = np.zeros(3), length_mm * shaft
    return ColumnGeometry([first - 100 * gearbox, first, second, second + 100 * pinion])


@pytest.mark.parametrize("layout", ["Z", "W"])
def test_bearing_loads_match_danas_closed_forms(layout: str) -> None:
    # Dana pp. 47-48. Input yoke in the joint's plane (Dana's 0 deg; our theta = 90 deg):
    # A = T cos b1 b (tan b1 -/+ tan b2) / (L a), B the same with a + b for b (- for Z,
    # + for W). Input yoke normal to it (Dana's 90 deg; our theta = 0): A = B = T tan b1 / a,
    # E = F = T sin b2 / (f cos b1).
    beta1, beta2, length = 6.0, 4.2, 1000.0
    a, b, e, f, torque = 150.0, 60.0, 50.0, 120.0, 1000.0
    geometry = two_joint_shaft(layout, beta1, beta2, length)
    bearings = BearingGeometry(a, b, e, f, ())
    t1, t2 = math.tan(math.radians(beta1)), math.tan(math.radians(beta2))
    c1 = math.cos(math.radians(beta1))
    sign = -1.0 if layout == "Z" else 1.0
    in_plane = load_state(geometry, (0.0,), bearings, torque, math.pi / 2).bearing_force_n
    far = torque * c1 * (b / 1000) * (t1 + sign * t2) / ((length / 1000) * (a / 1000))
    near = torque * c1 * ((a + b) / 1000) * (t1 + sign * t2) / ((length / 1000) * (a / 1000))
    assert np.linalg.norm(in_plane["gearbox far (A)"]) == pytest.approx(abs(far), rel=1e-3)
    assert np.linalg.norm(in_plane["gearbox near (B)"]) == pytest.approx(abs(near), rel=1e-3)
    normal = load_state(geometry, (0.0,), bearings, torque, 0.0).bearing_force_n
    for name in ("gearbox far (A)", "gearbox near (B)"):
        assert np.linalg.norm(normal[name]) == pytest.approx(torque * t1 / (a / 1000), rel=1e-3)
    for name in ("pinion near (E)", "pinion far (F)"):
        assert np.linalg.norm(normal[name]) == pytest.approx(
            torque * math.sin(math.radians(beta2)) / ((f / 1000) * c1), rel=1e-3)


def test_bearing_loads_balance_every_body_of_a_three_piece_shaft() -> None:
    # Independent statics: the cross moment from the vector model's pins (normal p x q,
    # torque matched), then every shaft's forces and moments must sum to zero.
    driveline = compound_three_piece()
    geometry, torque = driveline.geometry, driveline.torque_n_m
    theta = 0.7
    state = load_state(geometry, driveline.phasing_deg, driveline.bearings, torque, theta)
    model = VectorDriveline([list(p) for p in driveline.points_mm], list(driveline.phasing_deg))
    angles = model.shaft_angles(np.array([0.0, theta / 2, theta]))[:, -1]
    points = np.asarray(driveline.points_mm) / 1000
    axes = model.axes
    carried = torque
    moments = []
    for k, (p, q) in enumerate(model.pins(theta, angles)):
        normal = unit(np.cross(p, q))
        moment = carried / np.dot(normal, axes[k]) * normal
        carried = float(np.dot(moment, axes[k + 1]))
        moments.append(moment)
    np.testing.assert_allclose(state.joint_moment_n_m, moments, rtol=0, atol=1e-9 * torque)
    forces = state.joint_force_n
    bearings = state.bearing_force_n
    a, b = (value / 1000 for value in driveline.gearbox_bearings_mm)
    e, f = (value / 1000 for value in driveline.pinion_bearings_mm)
    joint = points[1:-1]
    # gearbox shaft: torque in, -moment and -force at joint 1, bearings A and B
    where_a, where_b = joint[0] - (a + b) * axes[0], joint[0] - b * axes[0]
    force_sum = -forces[0] + bearings["gearbox far (A)"] + bearings["gearbox near (B)"]
    thrust = -np.dot(force_sum, axes[0]) * axes[0]  # the gearbox's thrust bearing, on the axis
    moment_sum = (torque * axes[0] - moments[0] + np.cross(joint[0], -forces[0])
                  + np.cross(where_a, bearings["gearbox far (A)"])
                  + np.cross(where_b, bearings["gearbox near (B)"]) + np.cross(where_b, thrust))
    assert np.linalg.norm(force_sum + thrust) < 1e-8 * torque
    assert np.linalg.norm(moment_sum) < 1e-8 * torque
    # propshafts 1 and 2 with centre bearings, propshaft 3 without (slip spline: no axial force)
    for shaft in (1, 2, 3):
        front, rear = joint[shaft - 1], joint[shaft]
        force_sum = forces[shaft - 1] - forces[shaft]
        moment_sum = (moments[shaft - 1] - moments[shaft] + np.cross(front, forces[shaft - 1])
                      - np.cross(rear, forces[shaft]))
        if shaft < 3:
            where = rear - driveline.centre_bearing_mm[shaft - 1] / 1000 * axes[shaft]
            reaction = bearings[f"centre bearing {shaft}"]
            assert abs(np.dot(reaction, axes[shaft])) < 1e-9 * torque  # radial only
            force_sum = force_sum + reaction
            moment_sum = moment_sum + np.cross(where, reaction)
        else:
            assert abs(np.dot(forces[2], axes[3])) < 1e-9 * torque
        assert np.linalg.norm(force_sum) < 1e-8 * torque
        assert np.linalg.norm(moment_sum) < 1e-8 * torque
    # pinion: +moment and +force at the last joint, the mesh holds its torque, bearings E, F
    last = joint[-1]
    axis = axes[-1]
    force_sum = forces[-1] + bearings["pinion near (E)"] + bearings["pinion far (F)"]
    thrust = -np.dot(force_sum, axis) * axis
    moment_sum = (moments[-1] - carried * axis + np.cross(last, forces[-1])
                  + np.cross(last + e * axis, bearings["pinion near (E)"])
                  + np.cross(last + (e + f) * axis, bearings["pinion far (F)"])
                  + np.cross(last + e * axis, thrust))
    assert np.linalg.norm(force_sum + thrust) < 1e-8 * torque
    assert np.linalg.norm(moment_sum) < 1e-8 * torque
