"""The figures of many built columns at once, against the independent 3D cross-and-yoke
simulation (tests/column/cross_and_yoke.py) of each column."""

from __future__ import annotations

import numpy as np
import pytest
from cross_and_yoke import Simulated, extremes
from cross_and_yoke import residual_error as simulated_re

from sso._column.built_columns import built_angles
from sso._column.built_figures import BUILT_FIGURES, built_column_figures, limited_figures

CAR = np.array([[-950.0, 360.0, 780.0], [-717.9, 296.7, 569.0], [-660.0, 250.0, 430.0],
                [-610.0, 275.0, 300.0], [-590.0, 300.0, 190.0]])
YOKE = np.array([-80.0, -60.0])


def test_each_columns_figures_are_the_3d_simulations():
    rng = np.random.default_rng(5)
    points = CAR + rng.normal(0.0, 1.0, (3, 5, 3))
    errors = rng.normal(0.0, 2.0, (3, 2))
    beta_deg, gamma_deg = built_angles(points)
    phase_rad = np.radians(90.0 + YOKE + errors - gamma_deg)
    figures = built_column_figures(np.radians(beta_deg), phase_rad, 0.0, 540.0)
    assert figures.shape == (len(BUILT_FIGURES), 3)
    lock = np.radians(540.0)
    for index in range(3):
        simulated = Simulated(points[index], YOKE + errors[index], 0.0)
        low, high = extremes(simulated.ratio, -lock, lock)
        error_low, error_high = extremes(simulated.error, -lock, lock)
        assert figures[0, index] == pytest.approx(simulated_re(points[index],
                                                               YOKE + errors[index]), rel=1e-9)
        assert figures[1, index] == pytest.approx(100.0 * (high - low), rel=1e-9)
        assert figures[2, index] == pytest.approx(100.0 * (1 / low - 1 / high), rel=1e-9)
        assert figures[3, index] == pytest.approx(np.degrees(max(-error_low, error_high)),
                                                  rel=1e-9)
    limited = limited_figures(beta_deg, figures)
    assert set(limited) == {*BUILT_FIGURES, "largest_operating_angle_deg"}
    assert limited["largest_operating_angle_deg"].tolist() == np.max(beta_deg, axis=1).tolist()
