"""Warnings raised inside the package name the user's line, however deep the call."""

import inspect
import warnings

import sso

PAPER_OPTION_3 = sso.ShaftSeries([30.0, 40.0, 50.0], [90.0, 90.0])


def test_a_moved_start_names_the_line_that_called_sso_optimise():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        line = inspect.currentframe().f_lineno + 1
        sso.optimise(PAPER_OPTION_3, 3, beta_bounds_deg=(10.0, 40.0), solvers="lm", starts=1)
    moved = [warning for warning in caught if warning.category is sso.StartMovedWarning]
    assert [(warning.filename, warning.lineno) for warning in moved] == [(__file__, line)]
