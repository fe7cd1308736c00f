"""Angles of many built columns at once, against ColumnGeometry built one by one."""

import numpy as np
import pytest

from sso.cases.schema import load_case
from sso.column.built_columns import built_angles
from sso.column.geometry import ColumnGeometry

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
