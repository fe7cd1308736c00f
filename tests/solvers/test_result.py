"""One result base for every design problem: OptimizeResult-style fields, one JSON form."""

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
    document = result.solver_dict()
    assert document["success"] is result.success is True
    assert document["best"] == best.to_dict()
    assert len(document["runs"]) == 2
    assert document["crosscheck"]["agree"] is True
