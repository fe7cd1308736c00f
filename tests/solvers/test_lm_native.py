"""The rules compiled to machine code against the single solve's compiled kernels.

Reference: :func:`sso._solvers.lm.solve` with the shape's Gauss-Newton and Newton kernels
built (CasADi's virtual machine running the same SX functions): the library is the
same instructions compiled by the system's C compiler with every operation rounded on
its own, so each design must end with the same RE, iteration count and status, bit for
bit.
"""

import numpy as np
import pytest

from sso._shafts.options import build_problem
from sso._shafts.problem import compiled_nlp
from sso._solvers import lm, lm_native
from sso._solvers.lm_kernel import NEWTON_KERNEL_AFTER, newton_kernel_of
from sso._solvers.lm_native import (
    NATIVE_AFTER_DESIGNS,
    build_native_solver,
    native_solver_of,
    solve_native,
)
from sso._solvers.run import RunLimits

pytestmark = pytest.mark.filterwarnings("ignore::sso.StartMovedWarning")


def _problem(beta_deg, phase_deg, option):
    return build_problem(list(beta_deg), list(phase_deg), "exact", option, (5.0, 35.0),
                         (0.0, 180.0))


@pytest.mark.parametrize(("joints", "option"), [(3, 3), (4, 1), (5, 2)])
def test_each_design_ends_bit_for_bit_where_the_single_solve_s_kernels_end(joints, option):
    # Random starts of the shape, zero and nonzero minima, Newton steps through
    # indefinite Hessians (option 3 turns to Newton steps far from its zeros).
    rng = np.random.default_rng(60 + joints)
    beta_deg, phase_deg = rng.uniform(5.0, 35.0, (40, joints)), rng.uniform(0.0, 180.0,
                                                                           (40, joints - 1))
    problems = [_problem(beta_deg[row], phase_deg[row], option) for row in range(40)]
    nlp = compiled_nlp(problems[0], 0)
    for _ in range(NEWTON_KERNEL_AFTER):
        newton_kernel_of(nlp)
    native = build_native_solver(nlp)
    assert native is not None
    run = solve_native(native, np.array([problem.start_rad for problem in problems]),
                       np.array([problem.parameters_rad for problem in problems]),
                       problems[0].lower_rad, problems[0].upper_rad, 1e-12, 3000)
    assert run is not None
    for row, problem in enumerate(problems):
        single = lm.solve(nlp, problem.start_rad, problem.parameters_rad,
                          RunLimits(problem.lower_rad, problem.upper_rad), 1e-12, 3000)
        assert (run.fun[row], run.nit[row], run.status[row]) == (single.fun, single.nit,
                                                                 single.status)
        np.testing.assert_array_equal(run.x[row], single.x)


def test_a_missing_compiler_leaves_the_numpy_path(monkeypatch):
    # No compiler at the path given: no library, and the shape is not tried again.
    monkeypatch.setenv("CC", "/nonexistent/cc")
    monkeypatch.setattr(lm_native, "_solvers", {})
    monkeypatch.setattr(lm_native, "_designs_asked", {})
    nlp = compiled_nlp(_problem([20.0] * 3, [90.0] * 2, 1), 0)
    assert build_native_solver(nlp) is None
    built = []

    def nlp_of_shape():
        built.append(1)
        return nlp

    assert native_solver_of("shape", NATIVE_AFTER_DESIGNS, nlp_of_shape) is None
    assert native_solver_of("shape", NATIVE_AFTER_DESIGNS, nlp_of_shape) is None
    assert built == [1]


def test_the_library_is_built_once_a_shape_has_been_asked_for_enough_designs(monkeypatch):
    monkeypatch.setattr(lm_native, "_solvers", {})
    monkeypatch.setattr(lm_native, "_designs_asked", {})
    nlp = compiled_nlp(_problem([20.0] * 2, [90.0], 1), 0)
    assert native_solver_of("shape", NATIVE_AFTER_DESIGNS - 1, lambda: nlp) is None
    native = native_solver_of("shape", 1, lambda: nlp)
    assert native is not None and native.size == 1
    assert native_solver_of("shape", 1, lambda: nlp) is native
