"""Every shaft's peak angular acceleration against an independent 3D vector model.

Reference: ``driveline_vector_model.py`` (rotation matrices, each cross's constraint
solved numerically by Brent's method, spectral derivatives; written for these tests).
"""

from __future__ import annotations

import numpy as np
import pytest
from driveline_cases import CHECKED
from driveline_vector_model import VectorDriveline

from sso._column.geometry import ColumnGeometry
from sso._driveline.excitation import excitations


@pytest.mark.parametrize("name", sorted(CHECKED))
def test_joint_angles_and_peak_accelerations_match_the_vector_model(name: str) -> None:
    driveline = CHECKED[name]()
    model = VectorDriveline([list(p) for p in driveline.points_mm],
                            list(driveline.phasing_deg))
    np.testing.assert_allclose(driveline.geometry.beta_deg, model.joint_angles_deg(),
                               rtol=0, atol=1e-6)
    found = excitations(driveline.geometry, driveline.phasing_deg,
                        driveline.max_shaft_speed_rpm)
    drive, coast = model.peaks(driveline.max_shaft_speed_rpm)
    # A cancelled shaft's peak is zero up to each model's round-off: the vector model's
    # root finding leaves about 1e-9 of the largest peak.
    floor = 1e-8 * max(drive.max(), coast.max())
    np.testing.assert_allclose(found.drive_peak_rad_s2, drive, rtol=1e-4, atol=floor)
    np.testing.assert_allclose(found.coast_peak_rad_s2, coast, rtol=1e-4, atol=floor)


def test_single_power_take_off_joint_matches_the_vector_model() -> None:
    points = [[100.0, 0.0, 0.0], [0.0, 0.0, 0.0], [-100.0, 20.0, -30.0]]
    geometry = ColumnGeometry(points)
    model = VectorDriveline(points, [])
    found = excitations(geometry, (), 1800.0)
    drive, coast = model.peaks(1800.0)
    np.testing.assert_allclose(found.drive_peak_rad_s2, drive, rtol=1e-4)
    np.testing.assert_allclose(found.coast_peak_rad_s2, coast, rtol=1e-4)
