"""The effective angle: the phase-aware form against the pins carried through the 3D
geometry, and the signed-square rule.

References: the phase-aware second-order form (each joint's squared angle as a phasor at
twice its driving arm's angle from its plane), computed here with rotation matrices alone;
the signed-square rule by hand (3, 2.5, 4 deg).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from driveline_cases import CHECKED, compound_pickup, truck_two_piece
from driveline_vector_model import VectorDriveline, rotation, unit

from sso._driveline.excitation import effective_angle_deg, signed_square_deg


def transported_phases(points: list[list[float]], yoke_phase_deg: list[float]) -> list[float]:
    """Each joint's driving pin angle from its plane: the pin carried across each joint by
    the bend's own rotation (the uniform part of the motion), turned a quarter turn to the
    cross's other arm (the driven yoke's pin) and then by the yoke phasing."""
    axes = [unit(np.subtract(b, a)) for a, b in zip(points[:-1], points[1:], strict=True)]
    pin = unit(np.cross(axes[0], axes[1]))
    angles = []
    for k in range(1, len(axes)):
        before, after = axes[k - 1], axes[k]
        in_plane = unit(after - np.dot(after, before) * before)
        angles.append(math.atan2(np.dot(pin, np.cross(before, in_plane)), np.dot(pin, in_plane)))
        bend = unit(np.cross(before, after))
        pin = rotation(bend, math.acos(np.clip(np.dot(before, after), -1, 1))) @ pin
        pin = rotation(after, math.pi / 2) @ pin
        if k < len(axes) - 1:
            pin = rotation(after, math.radians(yoke_phase_deg[k - 1])) @ pin
    return angles


@pytest.mark.parametrize("name", sorted(CHECKED))
def test_phase_aware_effective_angle_matches_the_transported_pins(name: str) -> None:
    # theta_e^2 = |sum beta_k^2 exp(2 i g_k)| with g_k from the geometry alone.
    driveline = CHECKED[name]()
    points = [list(p) for p in driveline.points_mm]
    phases = transported_phases(points, list(driveline.phasing_deg))
    beta = VectorDriveline(points, list(driveline.phasing_deg)).joint_angles_deg()
    expected = math.sqrt(abs(sum(b**2 * np.exp(2j * g) for b, g in zip(beta, phases,
                                                                        strict=True))))
    assert effective_angle_deg(driveline.geometry, driveline.phasing_deg) == pytest.approx(
        expected, rel=0, abs=1e-6)


def test_signed_square_rule_on_a_planar_truck() -> None:
    # 3, 2.5, 4 deg, in phase: sqrt(|9 - 6.25 + 16|) = 4.3301 deg; shaft 2 at 90 deg flips
    # the third sign: sqrt(|9 - 6.25 - 16|).
    driveline = truck_two_piece()
    assert signed_square_deg(driveline.geometry, (0.0, 0.0)) == pytest.approx(
        math.sqrt(9 - 6.25 + 16), abs=1e-9)
    assert signed_square_deg(driveline.geometry, (0.0, 90.0)) == pytest.approx(
        math.sqrt(abs(9 - 6.25 - 16)), abs=1e-9)
    for phasing in ((0.0, 0.0), (0.0, 90.0), (90.0, 90.0)):
        assert effective_angle_deg(driveline.geometry, phasing) == pytest.approx(
            signed_square_deg(driveline.geometry, phasing), abs=1e-9)
    assert signed_square_deg(compound_pickup().geometry, (0.0,)) is None
