"""The rules compiled to machine code against the single solve's compiled kernels.

Reference: :func:`sso._solvers.lm.solve` with the shape's Gauss-Newton and Newton kernels
built (CasADi's virtual machine running the same SX functions): the library is the
same instructions compiled by the system's C compiler with every operation rounded on
its own, so each design must end with the same RE, iteration count and status, bit for
bit.
"""

import os
import shutil

import numpy as np
import pytest

from sso._shafts.options import build_problem
from sso._shafts.problem import compiled_nlp
from sso._solvers import lm, lm_native, saddle
from sso._solvers.lm_kernel import (
    NEWTON_KERNEL_AFTER,
    flat_outcome,
    kernel_of,
    newton_kernel_of,
    run_kernel_flat,
)
from sso._solvers.lm_native import (
    build_native_solver,
    native_solver_of,
    solve_native,
)
from sso._solvers.lm_rules import NEWTON, PYTHON, cholesky
from sso._solvers.multistart import measure_on_bounds
from sso._solvers.nlp import cached_shapes
from sso._solvers.run import RunLimits

pytestmark = pytest.mark.filterwarnings("ignore::sso.StartMovedWarning")

needs_compiler = pytest.mark.skipif(
    shutil.which(os.environ.get("CC") or "cc") is None,
    reason="no C compiler ($CC or cc) on this machine: the compiled path cannot be built "
           "(sso then keeps the numpy path, which the other tests check)")


def _problem(beta_deg, phase_deg, option):
    return build_problem(list(beta_deg), list(phase_deg), "exact", option, (5.0, 35.0),
                         (0.0, 180.0))


@needs_compiler
@pytest.mark.parametrize(("joints", "option"), [(3, 3), (4, 1), (5, 2)])  # 5, 3, 5 variables
def test_each_design_ends_bit_for_bit_where_the_single_solve_s_kernels_end(joints, option,
                                                                           monkeypatch):
    # Random starts of the shape, zero and nonzero minima, Newton steps through
    # indefinite Hessians (option 3 turns to Newton steps far from its zeros). The
    # single solve runs its kernels (the switch keeps it off the library; no shape that
    # earlier tests turned to it is kept).
    monkeypatch.setenv(lm_native.SWITCH_VARIABLE, "0")
    cached_shapes().clear()
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


@needs_compiler
@pytest.mark.parametrize(("joints", "option"), [(4, 3), (5, 1)])  # 7 and 4 variables
def test_a_shape_solved_often_turns_to_the_library_and_ends_where_the_kernels_end(
        joints, option, monkeypatch):
    # 4 joints of option 3 have more variables than the batch compiles (NATIVE_VARIABLES):
    # the single solve compiles them too. Reference: the same solves on the kernels
    # (CasADi's virtual machine, the Newton kernel built), bit for bit.
    rng = np.random.default_rng(80 + joints)
    problems = [_problem(rng.uniform(5.0, 35.0, joints), rng.uniform(0.0, 180.0, joints - 1),
                         option) for _ in range(30)]
    nlp = compiled_nlp(problems[0], 0)
    for _ in range(NEWTON_KERNEL_AFTER):
        newton_kernel_of(nlp)

    def solve(problem):
        return lm.solve(nlp, problem.start_rad, problem.parameters_rad,
                        RunLimits(problem.lower_rad, problem.upper_rad), 1e-12, 3000)

    nlp.lm_native, nlp.lm_solves = None, 0  # as if no earlier test had solved the shape
    monkeypatch.setenv(lm_native.SWITCH_VARIABLE, "0")
    on_kernels = [solve(problem) for problem in problems]
    monkeypatch.delenv(lm_native.SWITCH_VARIABLE)
    nlp.lm_solves = 0
    for _ in range(lm.NATIVE_AFTER - 1):
        solve(problems[0])
    assert nlp.lm_native is None  # not before NATIVE_AFTER solves of the shape
    compiled = [solve(problem) for problem in problems]
    assert isinstance(nlp.lm_native, lm_native.OneDesign)
    assert nlp.lm_native.solver.size == nlp.symbols["x"].numel()
    for kernel, library in zip(on_kernels, compiled, strict=True):
        assert ((library.fun, library.nit, library.nfev, library.status, library.message)
                == (kernel.fun, kernel.nit, kernel.nfev, kernel.status, kernel.message))
        np.testing.assert_array_equal(library.x, kernel.x)
    assert {kernel.status for kernel in on_kernels} & {1, 4}  # converged solves among them


@needs_compiler
@pytest.mark.parametrize(("joints", "option"), [(3, 3), (4, 1)])  # 5 and 4 variables
def test_the_gauss_newton_entry_ends_bit_for_bit_where_the_kernel_s_blocks_end(joints, option):
    # The exact-optimum choice's margin probes (Gauss-Newton steps only, in bounds shrunk
    # by a margin, 50 iterations at most) through the library once it is loaded.
    # Reference: the Gauss-Newton kernel's blocks on CasADi's virtual machine
    # (run_kernel_flat), the whole flat state, bit for bit; among the starts some hand
    # over to Newton steps (where both must stop) and some end by Gauss-Newton steps.
    rng = np.random.default_rng(90 + joints)
    problems = [_problem(rng.uniform(5.0, 35.0, joints), rng.uniform(0.0, 180.0, joints - 1),
                         option) for _ in range(40)]
    nlp = compiled_nlp(problems[0], 0)
    kernel = kernel_of(nlp)
    native = build_native_solver(nlp)
    assert kernel is not None and native is not None
    statuses = set()
    for index, problem in enumerate(problems):
        margin = 0.05 * (index % 4)
        lower, upper = (problem.lower_rad + margin).tolist(), (problem.upper_rad - margin).tolist()
        arguments = (problem.start_rad.tolist(), problem.parameters_rad.tolist(), lower, upper,
                     1e-12, 50)
        nlp.lm_native = None
        on_kernel = lm.gauss_newton_flat(nlp, kernel, *arguments)
        nlp.lm_native = lm_native.OneDesign(native, joints, option)
        compiled = lm.gauss_newton_flat(nlp, kernel, *arguments)
        assert compiled == on_kernel == run_kernel_flat(kernel, *arguments)
        statuses.add(flat_outcome(compiled, len(lower))[4])
    assert NEWTON in statuses and statuses - {NEWTON}, statuses


def _one_design(joints, option):
    """The shape's NLP and its library called one design at a time."""
    nlp = compiled_nlp(_problem([20.0] * joints, [90.0] * (joints - 1), option), 0)
    native = build_native_solver(nlp)
    assert native is not None
    return nlp, lm_native.OneDesign(native, joints, option)


@needs_compiler
@pytest.mark.parametrize(("joints", "option"), [(3, 3), (4, 1), (5, 2)])
def test_the_library_measures_where_a_design_ends_bit_for_bit_as_measure_on_bounds(joints,
                                                                                   option):
    # The direct path of "lm" alone takes the measure of its answer from the library's
    # call (OneDesign.solve_measured). Reference: measure_on_bounds (the closed form in
    # Python complex numbers, as every solver's answer is measured), every float the same
    # to the bit (float.hex tells -0.0 from 0.0). Ends inside the bounds and on them (wide
    # and narrow bounds), at zero and nonzero minima and after 1 or 2 iterations.
    rng = np.random.default_rng(100 + joints)
    nlp, one = _one_design(joints, option)
    ends = set()
    for index in range(120):
        beta_bounds = (5.0, 35.0) if index % 2 else (15.0, 20.0)
        problem = build_problem(list(rng.uniform(5.0, 35.0, joints)),
                                list(rng.uniform(0.0, 180.0, joints - 1)), "exact", option,
                                beta_bounds, (0.0, 180.0) if index % 2 else (60.0, 80.0))
        fixed, lower, upper = (problem.parameters_rad.tolist(), problem.lower_rad.tolist(),
                               problem.upper_rad.tolist())
        flat = [*fixed, *lower, *upper, 1e-12, (1.0, 2.0, 500.0)[index % 3]]
        ended, measured = one.solve_measured(problem.start_rad.tolist(), flat)
        x = ended[0]
        point, fun, kkt = measure_on_bounds(nlp, x, fixed, lower, upper)
        assert [value.hex() for value in measured[:-1]] == [value.hex() for value in
                                                           (*point, fun, kkt)]
        state = one.state()
        assert ended == flat_outcome(state, len(lower))
        assert state == one.solve(problem.start_rad.tolist(), flat)
        ends.add((fun <= 1e-20, any(value in (low, high)
                                    for value, low, high in zip(x, lower, upper, strict=True))))
    assert len(ends) >= 3, ends


@needs_compiler
@pytest.mark.parametrize(("joints", "option"), [(3, 1), (4, 1)])  # minima above zero
def test_the_library_s_look_for_negative_curvature_decides_as_saddle_py(joints, option):
    # Where a design succeeds above round-off zero, the library tells (the measure's last
    # entry) whether the Hessian over the variables that may move has no negative
    # curvature by the test saddle.py makes before its eigendecomposition. Reference: that
    # test in Python (_free_hessian, the closed-form Hessian, then lm_rules.cholesky with
    # the same shift), the same verdict on every design; where the library finds none,
    # saddle_direction finds no saddle point. Symmetric starts (phases at 0, 90 or 180 deg,
    # equal angles) stop on saddle points; narrow bounds leave variables on them.
    rng = np.random.default_rng(110 + joints)
    nlp, one = _one_design(joints, option)
    verdicts = set()
    for index in range(150):
        beta_deg, phase_deg = rng.uniform(5.0, 35.0, joints), rng.uniform(0.0, 180.0, joints - 1)
        if index % 5 == 0:
            beta_deg = rng.choice([10.0, 20.0, 30.0], joints)
            phase_deg = rng.choice([0.0, 90.0, 180.0], joints - 1)
        problem = build_problem(beta_deg.tolist(), phase_deg.tolist(), "exact", option,
                                ((5.0, 35.0), (15.0, 20.0))[index % 2],
                                ((0.0, 180.0), (60.0, 80.0))[index % 2])
        limits = RunLimits(problem.lower_rad, problem.upper_rad)
        fixed = problem.parameters_rad.tolist()
        flat = [*fixed, *limits.lower.tolist(), *limits.upper.tolist(), 1e-12,
                (500.0, 5.0)[index % 2]]
        (x, fun, _, _, status), measured = one.solve_measured(problem.start_rad.tolist(), flat)
        if not (status > 0 and fun > saddle.ZERO_OBJECTIVE):
            assert measured[-1] == 1.0  # no look: saddle_direction returns at once
            continue
        free, hessian = saddle._free_hessian(nlp, np.clip(np.array(x), limits.lower,
                                                          limits.upper), fixed, limits,
                                             saddle._Counts())
        none_in_python = (not free or not np.all(np.isfinite(hessian)) or cholesky(
            PYTHON, hessian, max(saddle.RELATIVE_CURVATURE * max(
                abs(hessian[entry][entry]) for entry in range(len(free))),
                saddle.ABSOLUTE_CURVATURE))[1])
        assert measured[-1] == (0.0 if none_in_python else 1.0)
        found = saddle.saddle_direction(nlp, True, fun, x, fixed, limits)
        assert found is None or not none_in_python
        verdicts.add((bool(none_in_python), found is not None))
    assert verdicts >= {(True, False), (False, True)}, verdicts


def test_a_missing_compiler_leaves_the_numpy_path(monkeypatch, tmp_path):
    # No compiler at the path given: no library, and the shape is not tried again.
    monkeypatch.setenv("CC", str(tmp_path / "no-such-compiler"))
    monkeypatch.setenv(lm_native.CACHE_VARIABLE, str(tmp_path / "cache"))
    monkeypatch.setattr(lm_native, "_solvers", {})
    nlp = compiled_nlp(_problem([20.0] * 3, [90.0] * 2, 1), 0)
    assert build_native_solver(nlp) is None
    built = []

    def nlp_of_shape():
        built.append(1)
        return nlp

    assert native_solver_of("shape", 2, nlp_of_shape) is None
    assert native_solver_of("shape", 2, nlp_of_shape) is None
    assert built == [1]
    assert not any((tmp_path / "cache").iterdir())


@needs_compiler
def test_the_library_is_kept_in_the_cache_folder_and_loaded_from_it(monkeypatch, tmp_path):
    monkeypatch.setenv(lm_native.CACHE_VARIABLE, str(tmp_path))
    nlp = compiled_nlp(_problem([20.0] * 2, [90.0], 1), 0)
    assert build_native_solver(nlp) is not None
    libraries = list(tmp_path.iterdir())
    assert len(libraries) == 1 and libraries[0].name.startswith("sso-lm-")
    written = libraries[0].stat()
    # Another process's first call: the library is found by its name, no source is made.
    monkeypatch.setattr(lm_native, "_solvers", {})
    assert native_solver_of(nlp.name, 1, lambda: pytest.fail("no source is made")) is not None
    assert list(tmp_path.iterdir()) == libraries
    # The same file (a build would have replaced it), its time marking the load.
    assert libraries[0].stat().st_ino == written.st_ino
    assert libraries[0].stat().st_mtime_ns >= written.st_mtime_ns


@needs_compiler
def test_a_build_holds_the_cache_folder_to_its_bound(monkeypatch, tmp_path):
    monkeypatch.setenv(lm_native.CACHE_VARIABLE, str(tmp_path))
    limit = 300 * 1024
    monkeypatch.setattr(lm_native, "COMPILED_CACHE_BYTES", limit)
    # Five libraries of earlier versions, 100 kB each, the first the least recently used.
    stale = []
    for index in range(5):
        path = tmp_path / f"sso-lm-{index:032x}.so"
        path.write_bytes(b"\0" * 100 * 1024)
        os.utime(path, (1e9 + index, 1e9 + index))
        stale.append(path)
    assert build_native_solver(compiled_nlp(_problem([20.0] * 2, [90.0], 1), 0)) is not None
    built = [path for path in tmp_path.iterdir() if path not in stale]
    assert len(built) == 1 and built[0].name.startswith("sso-lm-")
    # The build plus the most recently used stale libraries that fit beside it.
    kept = (limit - built[0].stat().st_size) // (100 * 1024)
    assert [path.exists() for path in stale] == [False] * (5 - kept) + [True] * kept


@needs_compiler
def test_an_unwritable_cache_folder_gives_a_private_build(monkeypatch, tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    monkeypatch.setenv(lm_native.CACHE_VARIABLE, str(blocker / "cache"))
    native = build_native_solver(compiled_nlp(_problem([20.0] * 2, [90.0], 1), 0))
    assert native is not None and native.size == 1
    assert blocker.read_text() == "not a folder"


def test_the_switch_keeps_the_numpy_path(monkeypatch):
    monkeypatch.setenv(lm_native.SWITCH_VARIABLE, "0")
    monkeypatch.setattr(lm_native, "_solvers", {})
    assert native_solver_of("shape", 2, lambda: pytest.fail("nothing is built")) is None


def test_a_shape_of_more_variables_than_compiled_leaves_the_numpy_path():
    # 4 joints of option 3: 7 free variables.
    nlp = compiled_nlp(_problem([20.0] * 4, [90.0] * 3, 3), 0)
    assert nlp.symbols["x"].numel() == lm_native.NATIVE_VARIABLES + 2
    assert build_native_solver(nlp) is None


@needs_compiler
def test_a_batch_solved_in_several_calls_of_the_library_ends_bit_for_bit_as_in_one(monkeypatch):
    # Calls of DESIGNS_PER_CALL designs let Ctrl-C through between them.
    rng = np.random.default_rng(70)
    problems = [_problem(rng.uniform(5.0, 35.0, 3), rng.uniform(0.0, 180.0, 2), 3)
                for _ in range(30)]
    native = build_native_solver(compiled_nlp(problems[0], 0))
    assert native is not None

    def solved():
        run = solve_native(native, np.array([problem.start_rad for problem in problems]),
                           np.zeros((30, 0)), problems[0].lower_rad, problems[0].upper_rad,
                           1e-12, 3000)
        return run.x, run.fun, run.nit, run.nfev, run.status

    whole = solved()
    monkeypatch.setattr(lm_native, "DESIGNS_PER_CALL", 7)
    for expected, found in zip(whole, solved(), strict=True):
        np.testing.assert_array_equal(found, expected)
