"""Angles of many built columns at once, against ColumnGeometry built one by one."""

import numpy as np
import pytest

from sso._cases.schema import load_case
from sso._column.built_columns import built_angles
from sso._column.geometry import ColumnGeometry

POINTS = np.asarray(load_case("cases/column_truck_three_joints.toml").geometry().points_mm)


def test_the_arrays_give_the_angles_of_each_column_built_alone():
    rng = np.random.default_rng(11)
    points = POINTS + rng.normal(0.0, 3.0, (300, *POINTS.shape))
    beta, gamma = built_angles(points)
    for index in range(len(points)):
        alone = ColumnGeometry(points[index])
        assert beta[index] == pytest.approx(alone.beta_deg, abs=1e-11)
        assert gamma[index] == pytest.approx(alone.plane_angle_deg, abs=1e-11)


def test_a_straight_joint_borrows_its_plane_and_a_bad_sample_is_named():
    straight = POINTS.copy()
    straight[2] = straight[1] + 0.5 * (straight[1] - straight[0])  # joint 1 straight
    beta, gamma = built_angles(np.stack([POINTS, straight]))
    alone = ColumnGeometry(straight)
    assert beta[1][0] == 0.0
    assert beta[1] == pytest.approx(alone.beta_deg, abs=1e-12)
    assert gamma[1] == pytest.approx(alone.plane_angle_deg, abs=1e-12)
    bent = POINTS.copy()
    bent[2] = bent[1] - 0.5 * (bent[1] - bent[0])  # joint 1 folds back on itself
    with pytest.raises(ValueError, match=r"sample 1: points_mm\[1\]: joint 1 bends by "):
        built_angles(np.stack([POINTS, bent]))


def zigzag_mm(joints: int, offset_mm: float) -> np.ndarray:
    """Points of a planar zigzag: inner joints bent by ``2 atan(2 offset / 100)``."""
    return np.array([[0.0, 0.0, 0.0]] + [[100.0 * (index + 1), offset_mm * (2 * (index % 2) - 1),
                                          0.0] for index in range(joints + 1)])


def test_a_sample_whose_angles_float64_cannot_resolve_is_named():
    """Angles below 89 deg take the array path, but 20 joints of 77.3 deg are beyond what
    float64 resolves (20 joints may reach 75.83 deg: docs/model.md, "Numerical limits"):
    that sample is refused as ColumnGeometry refuses it; 20 of 61.9 deg are not."""
    gentle, steep = zigzag_mm(20, 30.0), zigzag_mm(20, 40.0)
    beta, _ = built_angles(np.stack([gentle, gentle]))
    assert beta[1] == pytest.approx(ColumnGeometry(gentle).beta_deg, abs=1e-11)
    assert max(beta[1]) < 89.0
    with pytest.raises(ValueError, match=r"sample 1: points_mm \(the operating angles they "
                                         r"give\): float64 cannot resolve RE of a chain of 20 "):
        built_angles(np.stack([gentle, steep]))
