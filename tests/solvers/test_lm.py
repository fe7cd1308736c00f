"""The single-design least-squares solver ``"lm"`` through :func:`sso.optimise`.

References: RE of the answer recomputed by the rectangle rule of the angle-by-angle
chain (``sso._shafts.objective.residual_error``, 512 angles, independent of the
chain matrix the solver uses); the paper's option-3 and option-1 cases
(docs/model.md) and IPOPT's answer on the same problem.
"""

import pytest

import sso
from sso._shafts.objective import residual_error

PAPER_START = sso.ShaftSeries([15.0, 20.0, 9.0], [5.0, 50.0], "exact")


def quadrature_re(series):
    return float(residual_error(list(series.beta_rad), list(series.phase_rad), "exact", 512))


def test_lm_is_a_listed_solver():
    assert sso.SOLVERS == ("ipopt", "slsqp", "lm")


@pytest.mark.parametrize("option", [2, 3])
def test_lm_cancels_to_round_off_and_reports_every_field(option):
    result = sso.optimise(PAPER_START, option, beta_bounds_deg=(7, 25), solvers=("lm",),
                          starts=1)
    best = result.best
    assert best.solver == "lm" and best.success and best.status == 1
    assert best.fun <= 1e-20
    assert quadrature_re(best.series) <= 1e-20
    assert best.kkt <= 1e-10
    assert best.nit >= 1 and best.nfev >= best.nit
    assert isinstance(best.message, str) and best.message


def test_lm_matches_ipopt_at_a_nonzero_minimum():
    # Option 1 keeps the angles 15, 20, 9 deg: the minimum over the phases is not zero,
    # where Gauss-Newton alone is only linear; both solvers, one start each.
    lm = sso.optimise(PAPER_START, 1, solvers=("lm",), starts=1).best
    ipopt = sso.optimise(PAPER_START, 1, solvers=("ipopt",), starts=1).best
    assert lm.success and ipopt.success
    assert lm.fun == pytest.approx(ipopt.fun, rel=1e-9)
    assert lm.fun == pytest.approx(quadrature_re(lm.series), rel=1e-9)
    assert lm.fun > 1e-5
    assert lm.kkt <= 1e-8


def test_lm_keeps_to_bounds_with_an_active_bound():
    # An upper bound of 12 deg on every angle keeps RE above zero for these starts.
    result = sso.optimise(sso.ShaftSeries([10.0, 12.0, 5.0], [0.0, 0.0]), 2,
                          beta_bounds_deg=(3, 12), solvers=("lm", "ipopt"), starts=1)
    lm = result.solutions["lm"]
    assert all(3.0 <= beta <= 12.0 for beta in lm.series.beta_deg)
    assert lm.fun == pytest.approx(result.solutions["ipopt"].fun, rel=1e-6, abs=1e-18)
    assert result.crosscheck.agree


def test_lm_is_refused_for_the_paper_model():
    with pytest.raises(ValueError, match="'lm'.*exact"):
        sso.optimise(sso.ShaftSeries([15.0, 20.0], [5.0], "paper"), solvers=("lm",))


def test_exact_shape_does_not_depend_on_bounds():
    from sso._shafts.options import build_problem
    from sso._shafts.problem import compiled_nlp

    narrow = build_problem([15.0, 20.0], [5.0], "exact", 3, (7, 25), (0, 180))
    wide = build_problem([15.0, 20.0], [5.0], "exact", 3, (0, 89.9), (0, 180))
    assert compiled_nlp(narrow, 16) is compiled_nlp(wide, 4096)


def _rejecting_newton_case():
    # Found by a random search: Gauss-Newton stalls on the bounds, and the Newton
    # steps that follow are rejected several times before one is accepted.
    from sso._shafts.options import build_problem
    from sso._shafts.problem import compiled_nlp

    problem = build_problem([9.3, 6.2, 27.6], [154.8, 9.9], "exact", 3, (5.0, 35.0),
                            (0.0, 180.0))
    return problem, compiled_nlp(problem, 0), problem.parameters_rad.tolist()


def _run_recording_points(hessian_given):
    from sso._solvers.lm import minimise

    problem, nlp, fixed = _rejecting_newton_case()
    points = []

    def residual(x):
        points.append(tuple(x))
        return nlp.residuals_and_jacobian(x, fixed)

    answer = minimise(residual, problem.start_rad.tolist(), problem.lower_rad.tolist(),
                      problem.upper_rad.tolist(), 1e-12, 3000,
                      (lambda x: nlp.objective_hessian(x, fixed)) if hessian_given else None)
    return answer, points


@pytest.mark.parametrize("hessian_given", [False, True])
def test_newton_steps_never_evaluate_a_point_twice(hessian_given):
    # A rejected Newton step leaves x where it was: its Hessian (differences of the
    # gradient, or the closed form) is kept, not evaluated again. Only a trial point
    # that the bounds project onto the previous trial point may repeat, right after it.
    (x, fun, nit, nfev, status), points = _run_recording_points(hessian_given)
    assert status == 1 and fun <= 1e-20
    earlier = set()
    for index, point in enumerate(points):
        assert point not in earlier or point == points[index - 1]
        earlier.add(point)
    assert len(points) <= nfev


def test_closed_form_and_difference_hessians_reach_the_same_minimum():
    # Option 1 of the paper's start has a nonzero, isolated minimum over the phases,
    # which the Newton steps finish; with the closed-form Hessian and with differences
    # of the gradient they stop at the same design.
    from sso._shafts.options import build_problem
    from sso._shafts.problem import compiled_nlp
    from sso._solvers.lm import minimise

    problem = build_problem(list(PAPER_START.beta_deg), list(PAPER_START.phase_deg), "exact", 1,
                            (0.0, 40.0), (0.0, 180.0))
    nlp = compiled_nlp(problem, 0)
    fixed = problem.parameters_rad.tolist()
    answers = [minimise(lambda x: nlp.residuals_and_jacobian(x, fixed),
                        problem.start_rad.tolist(), problem.lower_rad.tolist(),
                        problem.upper_rad.tolist(), 1e-12, 3000, hessian)
               for hessian in (None, lambda x: nlp.objective_hessian(x, fixed))]
    (x_difference, fun_difference, *_), (x_closed, fun_closed, *_) = answers
    assert fun_closed > 1e-5
    assert fun_closed == pytest.approx(fun_difference, rel=1e-12)
    assert max(abs(a - b) for a, b in zip(x_closed, x_difference, strict=True)) <= 1e-8


def test_a_start_at_zero_residual_with_a_singular_jacobian_stops_there():
    # found by the tests of issue 33: rho = x0 + x1 (real) is zero at the start and
    # J J^T = [[2, 0], [0, 0]] is singular, so the damping (in proportion to |rho|) is
    # zero and the step's 2x2 solve divided by zero on plain floats
    from sso._solvers.lm import minimise

    def residual(x):
        return complex(x[0] + x[1], 0.0), [complex(1.0, 0.0), complex(1.0, 0.0)]

    x, fun, nit, nfev, status = minimise(residual, [0.0, 0.0], [-1.0, -1.0], [1.0, 1.0],
                                         1e-12, 50)
    assert (x, fun, nit, nfev, status) == ([0.0, 0.0], 0.0, 0, 1, 1)
