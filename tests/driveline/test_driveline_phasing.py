"""The yoke phasing recommended for the excitation limits (issue 36, acceptance)."""

from __future__ import annotations

import pytest
from driveline_cases import compound_pickup, planar_one_piece

from sso._driveline.excitation import excitations
from sso._driveline.phasing import recommend_phasing


def test_compound_pickup_phase_cancels_the_axle_excitation() -> None:
    # Two true angles of 3.04 deg whose planes are 82.06 deg apart: in phase the pinion's
    # peak acceleration at 3,500 rpm is about 750 rad/s^2 (the figure); the phase
    # that lines up the two planes' effects (delta = gamma) cancels it.
    driveline = compound_pickup()
    in_phase = excitations(driveline.geometry, (0.0,), 3500.0).torsional_rad_s2
    assert in_phase == pytest.approx(750.0, rel=0.02)
    advice = recommend_phasing(driveline)
    (phase,) = advice.yoke_phase_deg
    assert phase == pytest.approx(driveline.geometry.plane_angle_deg[0], abs=0.5)
    phased = excitations(driveline.geometry, advice.yoke_phase_deg, 3500.0).torsional_rad_s2
    assert phased < 0.01 * in_phase


def test_planar_equal_angles_in_phase_is_recommended() -> None:
    advice = recommend_phasing(planar_one_piece())
    (phase,) = advice.yoke_phase_deg
    assert abs(phase) < 1e-3
    assert advice.trades == ()
