"""SciPy's SLSQP fed CasADi's exact derivatives, on NLPs with closed-form optima
(tests/solvers/problems.py)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from solvers.problems import BOX, CLOSED_FORM_CASES, PARAMETERS, rosenbrock

from sso._solvers import slsqp


@pytest.mark.parametrize("case", CLOSED_FORM_CASES, ids=lambda case: case.name)
def test_reaches_the_closed_form_optimum(case):
    nlp, limits = case.build()
    outcome = slsqp.solve(nlp, np.array(case.start), PARAMETERS, limits, 1e-12, 500)
    assert outcome.success and outcome.status == 0
    # SLSQP stops on the change of the objective; on Rosenbrock's flat valley that
    # leaves x about 1e-5 off while f is within 1e-11.
    np.testing.assert_allclose(outcome.x, case.x, atol=1e-4)
    assert outcome.fun == pytest.approx(case.fun, abs=1e-9)
    # The start's evaluation (for ftol) is counted on top of SciPy's own counts.
    assert outcome.nfev >= outcome.nit + 1 and outcome.njev >= 2


def test_bounds_are_kept():
    # The optimum sits on the lower bound x[0] = 0: SLSQP never leaves the box, and
    # stops on the bound to round-off (SciPy 1.17's SLSQP ends 9.9e-16 inside it;
    # earlier releases ended on it exactly).
    case = next(case for case in CLOSED_FORM_CASES if case.name == "bowl on a bound")
    nlp, limits = case.build()
    outcome = slsqp.solve(nlp, np.array(case.start), PARAMETERS, limits, 1e-12, 500)
    assert 0.0 <= outcome.x[0] <= 1e-12
    assert outcome.fun == pytest.approx(1.0, abs=1e-12)


def test_iteration_limit_is_reported_not_raised():
    outcome = slsqp.solve(rosenbrock(), np.array([-1.2, 1.0]), PARAMETERS, BOX, 1e-12, 1)
    assert not outcome.success
    assert outcome.status == 9  # SciPy's SLSQP exit mode 9: iteration limit
    assert outcome.message == "Iteration limit reached"


def _minimize_reference(nlp, limits, start, tolerance, max_iterations):
    """The same solve through ``scipy.optimize.minimize(method="SLSQP")``, the constraints
    as one dictionary per row (equalities ``g - lbg = 0``, then ``g - lbg >= 0`` and
    ``ubg - g >= 0``), written here independently of :mod:`sso._solvers.slsqp`."""
    from scipy.optimize import Bounds, minimize

    def fun(x):
        value, gradient = nlp.objective_and_gradient(x, PARAMETERS)
        return float(value), np.array(gradient, dtype=float).ravel()

    def row(index, sign, bound):
        def value(x):
            return sign * (np.ravel(nlp.constraints_and_jacobian(x, PARAMETERS)[0])[index]
                           - bound)

        def jacobian(x):
            return sign * np.array(nlp.constraints_and_jacobian(x, PARAMETERS)[1],
                                   dtype=float)[index]

        return value, jacobian

    equalities, inequalities = [], []
    if limits.constrained:
        for index, (lower, upper) in enumerate(zip(limits.constraint_lower,
                                                   limits.constraint_upper, strict=True)):
            if lower == upper:
                equalities.append(("eq", *row(index, 1.0, lower)))
            elif np.isfinite(lower):
                inequalities.append(("ineq", *row(index, 1.0, lower)))
        for index, (lower, upper) in enumerate(zip(limits.constraint_lower,
                                                   limits.constraint_upper, strict=True)):
            if lower != upper and np.isfinite(upper):
                inequalities.append(("ineq", *row(index, -1.0, upper)))
    constraints = [{"type": kind, "fun": value, "jac": jacobian}
                   for kind, value, jacobian in equalities + inequalities]
    ftol = max(tolerance * abs(fun(start)[0]), tolerance * tolerance * np.finfo(float).eps)
    # On the one BLAS thread sso gives SLSQP: on a machine whose OpenBLAS rounds two
    # threads' sums otherwise (seen on an AVX-512 one), the last bit differs.
    with slsqp.BLAS_LIBRARIES.limit(limits=1, user_api="blas"):
        return minimize(fun, start, jac=True, method="SLSQP",
                        bounds=Bounds(limits.lower, limits.upper), constraints=constraints,
                        options={"ftol": ftol, "maxiter": max_iterations})


@pytest.mark.parametrize("max_iterations", [500, 3])
@pytest.mark.parametrize("case", CLOSED_FORM_CASES, ids=lambda case: case.name)
def test_each_run_is_scipy_minimize_s_slsqp_step_for_step(case, max_iterations):
    # The run calls scipy.optimize.minimize(method="SLSQP") with its own gradient
    # cache and constraint rows. Reference: minimize called independently on the same
    # problem (one dictionary per constraint row): the same point, objective, iterations,
    # evaluations
    # (the start's evaluation for ftol on top), exit mode and message, bit for bit.
    nlp, limits = case.build()
    start = np.array(case.start)
    outcome = slsqp.solve(nlp, start, PARAMETERS, limits, 1e-12, max_iterations)
    reference = _minimize_reference(nlp, limits, start, 1e-12, max_iterations)
    np.testing.assert_array_equal(outcome.x, reference.x)
    assert ((outcome.fun, outcome.nit, outcome.nfev, outcome.njev, outcome.status,
             outcome.success, outcome.message)
            == (reference.fun, reference.nit, reference.nfev + 1, reference.njev + 1,
                reference.status, reference.success, reference.message))


SLSQP_BITS = """
import sso
best = sso.run_case({path!r}).optimisation.best
print(best.solver, [value.hex() for value in best.series.phase_deg], best.fun.hex())
"""


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="OpenBLAS runs one thread on one core")
def test_slsqp_gives_the_same_bits_on_one_blas_thread_as_on_the_default():
    # SciPy's OpenBLAS rounded SLSQP's linear algebra differently on two threads than on
    # one: the paper's option 3 in the paper model ended at another design in a process
    # started with OPENBLAS_NUM_THREADS=1 (as a Dask worker is). Real processes, since
    # the thread count is read when OpenBLAS loads.
    path = str(Path(__file__).resolve().parents[2] / "cases" / "paper_option3_paper.toml")
    printed = []
    for threads in ({}, {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1"}):
        environment = {name: value for name, value in os.environ.items()
                       if name not in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS")}
        done = subprocess.run([sys.executable, "-c", SLSQP_BITS.format(path=path)],
                              env={**environment, **threads}, capture_output=True,
                              text=True, timeout=300)
        assert done.returncode == 0, done.stderr
        printed.append(done.stdout)
    assert printed[0] == printed[1]
