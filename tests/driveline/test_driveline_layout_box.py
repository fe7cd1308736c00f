"""The layout box: its checks, and the pinion slope and centre-bearing heights it moves.

References: a pinion turned by the shims is the driveline a fitter would measure with
the new pinion slope (:func:`points_from_measurements`, built independently from the
slope); a centre bearing raised is its joint centre moved up, written by hand.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from driveline_cases import truck_two_piece

from sso._driveline.layout import points_from_measurements, side_slope_deg
from sso._driveline.layout_box import LayoutBox, laid_out_points, pinion_slope_of

MEASURED = {"gearbox_slope_deg": 3.0, "shaft_slope_deg": [0.0, 2.5],
            "shaft_length_mm": [1200.0, 1400.0], "pinion_slope_deg": -1.5}


def test_a_pinion_turned_is_the_driveline_measured_with_that_slope() -> None:
    points = points_from_measurements(**MEASURED)
    turned = laid_out_points(points, 2.25, ())
    expected = points_from_measurements(**{**MEASURED, "pinion_slope_deg": 0.75})
    np.testing.assert_allclose(turned, expected, rtol=0.0, atol=1e-10)
    assert pinion_slope_of(turned) == pytest.approx(0.75, abs=1e-12)


def test_a_pinion_angled_in_plan_keeps_its_joint_and_takes_the_slope_exactly() -> None:
    points = points_from_measurements(**{**MEASURED, "pinion_plan_deg": 4.0})
    turned = laid_out_points(points, -1.0, ())
    assert turned[:-1] == points[:-1]
    rear = np.subtract(turned[-1], turned[-2])
    assert np.linalg.norm(rear) == pytest.approx(100.0, rel=1e-14)  # P(n+1) 100 mm behind
    assert side_slope_deg(rear / np.linalg.norm(rear)) == pytest.approx(-2.5, abs=1e-12)
    assert rear[1] == pytest.approx(points[-1][1] - points[-2][1], abs=1e-12)


def test_a_centre_bearing_raised_moves_its_joint_up_alone() -> None:
    points = points_from_measurements(**MEASURED)
    raised = laid_out_points(points, 0.0, (12.5,))
    moved = [list(point) for point in points]
    moved[2][2] += 12.5  # P0, gearbox joint, centre-bearing joint, pinion joint, P4
    np.testing.assert_allclose(raised, moved, rtol=0.0, atol=1e-12)


@pytest.mark.parametrize(("box", "message"), [
    ({"pinion_slope_deg": (3.0, 1.0)}, "pinion_slope_deg = (3, 1) deg is inverted"),
    ({"pinion_slope_deg": (-50.0, 1.0)},
     "pinion_slope_deg lower = -50 is outside the allowed range [-45, 45] deg"),
    ({"centre_bearing_height_mm": ((0.0, math.inf),)},
     "centre_bearing_height_mm[0] upper = inf must be finite"),
    ({"centre_bearing_height_mm": ((0.0, 600.0),)},
     "centre_bearing_height_mm[0] upper = 600 is outside the allowed range [-500, 500] mm"),
    ({}, "a layout box needs pinion_slope_deg or centre_bearing_height_mm"),
])
def test_a_bad_box_is_refused_naming_the_field(box: dict[str, object], message: str) -> None:
    with pytest.raises(ValueError) as raised:
        LayoutBox(**box)  # type: ignore[arg-type]
    assert message in str(raised.value)


def test_a_box_of_more_centre_bearings_than_the_driveline_has_is_refused() -> None:
    box = LayoutBox(centre_bearing_height_mm=((-5.0, 5.0), (-5.0, 5.0)))
    with pytest.raises(ValueError, match="has 2 boxes; the driveline has 1 centre bearings"):
        box.check_fits(truck_two_piece().joint_count)


def test_a_box_needs_the_phasing_search_and_a_propshaft() -> None:
    from sso._driveline.figures import analyse_driveline
    from sso._driveline.model import Driveline

    box = LayoutBox(pinion_slope_deg=(-2.0, 2.0))
    with pytest.raises(ValueError, match="layout: a layout box is chosen with the phasing"):
        analyse_driveline(truck_two_piece(), phasing=False, layout=box)
    single = Driveline(points_mm=((100.0, 0.0, 0.0), (0.0, 0.0, 0.0), (-100.0, 0.0, 5.0)),
                       tubes=(), max_shaft_speed_rpm=1000.0, torque_n_m=100.0)
    with pytest.raises(ValueError, match="one joint has no propshaft to phase or lay out"):
        analyse_driveline(single, layout=box)
