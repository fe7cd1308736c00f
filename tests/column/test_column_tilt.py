"""A tilt position: P0 turned about a pivot axis, against SciPy's rotation (another
formulation: a rotation vector turned into a quaternion)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from sso.column.tilt import tilted_points

POINTS = ((-1850.0, 420.0, 1650.0), (-1690.3, 328.7, 1239.3), (-1612.9, 259.6, 873.8),
          (-1385.7, 260.3, 250.9))


@pytest.mark.parametrize("angle_deg, axis, through", [
    (7.5, (0.0, 1.0, 0.0), POINTS[1]),
    (-31.0, (0.3, -2.0, 0.4), (-1700.0, 300.0, 1200.0)),
    (90.0, (1.0, 1.0, 1.0), (0.0, 0.0, 0.0)),
])
def test_p0_turns_about_the_axis_through_the_point_as_scipy_turns_it(angle_deg, axis, through):
    unit = np.asarray(axis) / np.linalg.norm(axis)
    rotation = Rotation.from_rotvec(np.radians(angle_deg) * unit)
    expected = np.asarray(through) + rotation.apply(np.asarray(POINTS[0]) - through)
    turned = tilted_points(POINTS, angle_deg, axis, through)
    assert np.asarray(turned[0]) == pytest.approx(expected, abs=1e-9)  # mm
    assert turned[1:] == POINTS[1:]


def test_no_tilt_gives_the_points_as_given_and_a_zero_axis_is_refused():
    assert tilted_points(POINTS, 0.0, (0.0, 1.0, 0.0), POINTS[1]) == POINTS
    with pytest.raises(ValueError, match=r"axis = \[0.0, 0.0, 0.0\] has no direction"):
        tilted_points(POINTS, 5.0, (0.0, 0.0, 0.0), POINTS[1])
