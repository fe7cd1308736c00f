"""One result base for every design problem: OptimizeResult-style fields, one saved form."""

import sso
from sso._solvers.result import DesignResult


def test_both_design_results_share_the_base_and_its_fields():
    # The paper's option 2 from its start, one start per solver; the numbers compared
    # are the result's own, read two ways.
    result = sso.optimise(sso.ShaftSeries([10, 15, 25], [90, 90], model="paper"), 2,
                          beta_bounds_deg=(7, 25), starts=1)
    assert isinstance(result, DesignResult)
    assert issubclass(sso.FourBarDesignResult, DesignResult)
    best = result.best
    assert (result.x, result.fun, result.nit, result.nfev, result.status, result.message) == (
        best.x, best.fun, best.nit, best.nfev, best.status, best.message)
    assert result.success is True and len(result.runs) == 2
    assert result.crosscheck is not None and result.crosscheck.agree is True
    # the saved form holds the solver part in the result's own fields, read back equal
    reloaded = type(result).from_dict(result.to_dict())
    assert reloaded.best == best and reloaded.runs == result.runs
