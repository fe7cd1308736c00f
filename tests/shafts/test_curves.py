"""The designs a report compares carry their speed curves."""

from __future__ import annotations

import math

import numpy as np
import pytest

import sso
from sso._shafts.curves import ComparedDesign, compared_design


def test_one_joint_swings_between_cos_beta_and_its_inverse():
    # docs/model.md, checks: one joint at beta turns the output between w cos(beta) and
    # w / cos(beta), twice per revolution.
    series = sso.ShaftSeries([30.0])
    design = compared_design("initial", "one joint", series, series.evaluate(40.0))
    assert design.input_angle_deg[0] == 0.0 and design.input_angle_deg[-1] == 360.0
    assert design.input_angle_deg.shape == design.output_speed_rpm.shape == (361,)
    cos_beta = math.cos(math.radians(30.0))
    assert design.output_speed_rpm.min() == pytest.approx(40.0 * cos_beta, rel=1e-12)
    assert design.output_speed_rpm.max() == pytest.approx(40.0 / cos_beta, rel=1e-12)
    assert design.output_speed_rpm.min() == pytest.approx(design.evaluation.speed_min_rpm,
                                                          rel=1e-12)


def test_a_compared_design_checks_its_role_and_its_curve():
    series = sso.ShaftSeries([10.0, 20.0], [90.0])
    evaluation = series.evaluate(25.0)
    with pytest.raises(ValueError, match="role = 'best'"):
        ComparedDesign("best", "x", series, evaluation, np.zeros(3), np.zeros(3))
    with pytest.raises(ValueError, match="differ in length"):
        ComparedDesign("initial", "x", series, evaluation, np.zeros(3), np.zeros(4))
