"""A sweep point's row built in steps: warnings and time kept, an exception an error row."""

from __future__ import annotations

import time
import warnings

import pytest

import sso
from sso._studies.point_row import PointRow, design_columns, solver_columns


def _warn_and_give(value):
    warnings.warn("first note", UserWarning, stacklevel=1)
    return value


def test_steps_keep_their_values_warnings_and_time():
    row = PointRow({"point": 3, "option": 2})
    assert row.attempt(lambda: _warn_and_give(41)) == 41
    row.fill(lambda: {"residual_error": 0.5})
    row.fill(lambda: _warn_and_give({"success": True}))
    row.notes.insert(0, "from the case")
    assert row.busy_s > 0.0 and not row.failed
    finished = row.finish()
    assert finished == {"point": 3, "option": 2, "residual_error": 0.5, "success": True,
                        "status": "ok", "warnings": "from the case | first note",
                        "time_s": row.busy_s}


def test_a_step_that_raises_makes_an_error_row_and_is_timed():
    row = PointRow({"point": 0})

    def slow_failure():
        time.sleep(0.01)
        raise ValueError("beta_deg[0] = 95 is outside the allowed range [0, 90) deg")

    assert row.attempt(slow_failure) is None
    assert row.failed and row.busy_s >= 0.01
    row.fill(lambda: _warn_and_give({"residual_error": 1.0}))  # a later step still runs
    finished = row.finish()
    assert finished["status"] == "failed"
    assert finished["error"] == ("ValueError: beta_deg[0] = 95 is outside the allowed range "
                                 "[0, 90) deg")
    assert "warnings" not in finished and finished["time_s"] == row.busy_s


def test_a_step_that_is_not_an_exception_still_propagates():
    row = PointRow({"point": 0})
    with pytest.raises(KeyboardInterrupt):
        row.attempt(lambda: (_ for _ in ()).throw(KeyboardInterrupt()))


def test_result_columns_name_the_figures_the_design_and_the_solver():
    series = sso.ShaftSeries([20.0, 30.0], [90.0])
    evaluation = series.evaluate(30.0)
    columns = design_columns(evaluation, series.beta_deg, series.phase_deg)
    assert columns == {
        "residual_error": evaluation.residual_error,
        "residual_error_rpm2": evaluation.residual_error_rpm2,
        "fluctuation": evaluation.fluctuation,
        "max_output_accel_rad_s2": evaluation.max_output_accel_rad_s2,
        "design_beta_deg": [20.0, 30.0], "design_phase_deg": [90.0]}
    assert solver_columns("lm", 1e-30, 4, True, "done", 1e-16, 0.25) == {
        "lm_residual_error": 1e-30, "lm_status": 4, "lm_success": True, "lm_message": "done",
        "lm_kkt_per_rad": 1e-16, "lm_time_s": 0.25}
