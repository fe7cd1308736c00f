"""A column whose yoke phasing cancels on a set of exact optima: the phasing chosen within
the set (nearest the textbook correction) and the set's extent per intermediate shaft,
checked with the independent 3D cross-and-yoke simulation (tests/column/cross_and_yoke.py):
each end's witness is an exact optimum there; at a phasing inside the reported extent the
simulated speed ratio can be made constant by the other yokes; just outside it, it
cannot."""

from __future__ import annotations

import numpy as np
import pytest
from cross_and_yoke import residual_error as simulated_residual_error
from cross_and_yoke import shaft_axes, speed_ratio
from scipy.optimize import least_squares

import sso
from sso._column.geometry import ColumnGeometry

# Four joints that can cancel (the continuum of tests/column/test_column_phasing.py).
POINTS = np.asarray([[0, 0, 0], [300, 0, 0], [600, 80, 0], [900, 120, 60], [1200, 100, 150],
                     [1500, 60, 170]], dtype=float)
ANGLES = np.pi * np.arange(64) / 64


def _least_re_with(shaft: int, value_deg: float, start: np.ndarray) -> float:
    """The least simulated RE over the other yokes with yoke ``shaft`` held at ``value_deg``."""
    reference = np.cross(shaft_axes(POINTS)[0], [0.3, -0.5, 0.8])
    reference /= np.linalg.norm(reference)

    def residuals(others: np.ndarray) -> np.ndarray:
        yoke = np.insert(others, shaft, value_deg)
        return speed_ratio(POINTS, yoke, ANGLES, reference) - 1.0

    found = least_squares(residuals, np.delete(start, shaft), xtol=1e-15, ftol=1e-15,
                          gtol=1e-15)
    return simulated_residual_error(POINTS, np.insert(found.x, shaft, value_deg))


def _deviation_deg(yoke: np.ndarray, gamma: np.ndarray) -> float:
    """Largest |phi - 90| of a phasing, mod 180 deg (phi = 90 + delta - gamma)."""
    return float(np.max(np.abs(np.mod(yoke - gamma + 90.0, 180.0) - 90.0)))


def test_the_phasing_is_chosen_nearest_the_textbook_correction_and_the_extent_is_the_sets():
    geometry = ColumnGeometry(POINTS)
    result = sso.optimise(geometry)
    assert result.success, result.message
    assert simulated_residual_error(POINTS, result.yoke_phase_deg) <= 1e-12
    assert result.exact_optimum_criterion.startswith("nearest the textbook correction")
    gamma = np.asarray(geometry.plane_angle_deg)
    chosen = _deviation_deg(np.asarray(result.yoke_phase_deg), gamma)
    # No other exact optimum found lies nearer (within the bisection's 0.1 deg).
    for yoke in result.equivalent_yoke_phase_deg:
        assert chosen <= _deviation_deg(np.asarray(yoke), gamma) + 0.1
    extent = result.exact_optimum_extent_deg
    witnesses = result.exact_optimum_extent_witnesses_deg
    ends = result.optimisation.exact_optima.extent_search.ends
    assert len(extent) == len(witnesses) == len(ends) == 3
    start = np.asarray(result.yoke_phase_deg)
    for shaft, ((low, high), pair, found) in enumerate(zip(extent, witnesses, ends,
                                                             strict=True)):
        assert -90.0 <= low < 90.0 and low <= high <= low + 180.0
        assert np.mod(start[shaft] - low, 180.0) <= high - low + 1e-9  # the chosen is inside
        for end, witness, kept in zip((low, high), pair, found, strict=True):
            # the model phases span two periods: every end is sought modulo 180 deg, the
            # furthest reached (a lower estimate), and its witness is an exact optimum by
            # the 3D simulation with that shaft's yoke at the end (mod 180 deg), its model
            # phases inside the bounds (-90, 270) deg
            assert not kept.at_bound
            assert simulated_residual_error(POINTS, witness) <= 1e-12, (shaft, end, witness)
            offset = np.mod(witness[shaft] - end + 90.0, 180.0) - 90.0
            assert abs(offset) <= 1e-9, (shaft, end, witness)
            assert all(-90.0 <= phase <= 270.0 for phase in kept.witness)
    bounded = [(shaft, low, high) for shaft, (low, high) in enumerate(extent)
               if high - low < 180.0]
    assert len(bounded) == 3, extent  # this column's set holds no shaft's every phasing
    for shaft, low, high in bounded:
        for inside in (low + 0.2, high - 0.2):
            assert _least_re_with(shaft, inside, start) <= 1e-12, (shaft, inside)
        # measured: pinned least squares from 40 random starts at every 2 deg of each
        # model phase found exact optima only within these arcs
        for outside in (low - 1.0, high + 1.0):
            assert _least_re_with(shaft, outside, start) > 1e-9, (shaft, outside)
    assert "exact optima: a set of dimension 1" in result.summary()


def test_a_column_that_cannot_cancel_reports_no_set():
    points = np.asarray([[0, 0, 0], [300, 0, 0], [600, 80, 0], [900, 120, 160]], dtype=float)
    result = sso.optimise(ColumnGeometry(points))
    assert result.fun > 1e-6
    assert result.exact_optimum_criterion is None and result.exact_optimum_extent_deg is None
    assert "exact optima" not in result.summary()


@pytest.fixture(scope="module")
def column_run():
    from sso._cases.schema import parse_case
    from sso._run.column import run_column

    case = parse_case({"kind": "column", "hardpoints": {"points_mm": POINTS.tolist()},
                       "solver": {"starts": 4}}, "cancelling")
    return run_column(case, optimising=True)


def test_the_column_report_states_the_criterion_and_the_extent(column_run, tmp_path):
    phasing = column_run.phasing
    assert phasing.optimisation.exact_optima.dimension == 1
    assert len(phasing.exact_optimum_extent_deg) == 3
    sso.write_report(column_run, tmp_path / "report", formats=("md",))
    text = (tmp_path / "report" / "report.md").read_text()
    assert "RE = 0 is reached on a set of exact optima of dimension 1" in text
    assert "nearest the textbook correction" in text
    assert "Each end is the furthest phasing at which an exact optimum was found" in text
    assert "| intermediate shaft | end | delta (deg) | witness delta (deg) | witness RE |" in text
    reloaded = type(column_run).from_dict(column_run.to_dict()).phasing
    assert reloaded.exact_optimum_extent_deg == phasing.exact_optimum_extent_deg
    assert (reloaded.exact_optimum_extent_witnesses_deg
            == phasing.exact_optimum_extent_witnesses_deg)
