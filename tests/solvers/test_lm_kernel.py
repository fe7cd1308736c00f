"""The "lm" rules as CasADi functions against the same rules on plain Python floats.

Reference: :func:`sso._solvers.lm.minimise` (the rules on Python floats, the closed-form
residuals and Hessian) from the same starts: the functions are the same algorithm, so
they must end with the same status and iteration count, and an objective no worse than
the loop's beyond round-off. The mapped functions are held to one design's, bit for bit.
"""

import numpy as np
import pytest

from sso._shafts.options import build_problem
from sso._shafts.problem import compiled_nlp
from sso._solvers import lm
from sso._solvers.lm_kernel import (
    GAUSS_NEWTON_ITERATIONS,
    MAP_COLUMNS,
    iteration_functions,
    kernels_of,
    pack,
    problem_vector,
    solve_one,
    solve_states,
    unpack,
)
from sso._solvers.lm_rules import (
    NEWTON,
    NEWTON_INDEFINITE,
    PYTHON,
    RUNNING,
    SCALARS,
    newton_iteration,
)
from sso._solvers.run import RunLimits

# Random starts often lie outside random bounds: moving them is expected here.
pytestmark = pytest.mark.filterwarnings("ignore::sso.StartMovedWarning")


def _problem(beta_deg, phase_deg, option, beta_bounds_deg, phase_bounds_deg=(0.0, 180.0)):
    problem = build_problem(list(beta_deg), list(phase_deg), "exact", option, beta_bounds_deg,
                            phase_bounds_deg)
    return problem, compiled_nlp(problem, 0)


def run_kernel(nlp, start, fixed, lower, upper, tolerance, max_iterations):
    # The Gauss-Newton blocks alone, as a state.
    values = solve_one(kernels_of(nlp), start, problem_vector(fixed, lower, upper, tolerance,
                                                              max_iterations), newton=False)
    return unpack(values, len(lower))


def run_newton_blocks(nlp, state, fixed, lower, upper, tolerance, max_iterations):
    # Newton blocks from a state handed over by the Gauss-Newton blocks, to the end; a
    # state they hand back (an indefinite Hessian) takes the shifted iteration.
    blocks, shifted = (kernels_of(nlp).buffered(mode, 1) for mode in ("newton", "shifted"))
    problem = problem_vector(fixed, lower, upper, tolerance, max_iterations)
    values = pack(state)
    while unpack(values, len(lower))["status"] in (NEWTON, NEWTON_INDEFINITE):
        if unpack(values, len(lower))["status"] == NEWTON:
            values = blocks.flat(values, problem)
            continue
        values[len(values) - len(SCALARS) + SCALARS.index("status")] = float(NEWTON)
        values = shifted.flat(values, problem)
    return unpack(values, len(lower))


def _python_loop(problem, nlp, max_iterations=3000):
    # The same rules on plain floats (lm.minimise, a problem without a residual expression).
    fixed = problem.parameters_rad.tolist()
    return lm.minimise(lambda x: nlp.residuals_and_jacobian(x, fixed), problem.start_rad.tolist(),
                       problem.lower_rad.tolist(), problem.upper_rad.tolist(), 1e-12,
                       max_iterations, lambda x: nlp.objective_hessian(x, fixed))


def _evaluate(nlp, fixed):
    # The Python loop's residuals: rho = r1 - i r2.
    def evaluate(point):
        rho, jacobian = nlp.residuals_and_jacobian(point, fixed)
        return (rho.real, -rho.imag, [entry.real for entry in jacobian],
                [-entry.imag for entry in jacobian])
    return evaluate


def _with_kernel(problem, nlp, max_iterations=3000):
    outcome = lm.solve(nlp, problem.start_rad, problem.parameters_rad,
                       RunLimits(problem.lower_rad, problem.upper_rad), 1e-12, max_iterations)
    return outcome.x.tolist(), outcome.fun, outcome.nit, outcome.nfev, outcome.status


def test_kernel_ends_as_the_python_loop_on_random_problems():
    # 300 random problems of 2 to 6 joints, every option, random bounds: zero and
    # nonzero minima, active bounds, solves that end in the kernel, continue in
    # further blocks, or hand over to the loop's Newton steps.
    rng = np.random.default_rng(20261125)
    iteration_differences, same_status = [], 0
    for _ in range(300):
        joints = int(rng.integers(2, 7))
        low = rng.uniform(0.0, 20.0)
        problem, nlp = _problem(rng.uniform(0.0, 45.0, joints), rng.uniform(-30.0, 200.0,
                                                                           joints - 1),
                                int(rng.integers(1, 4)), (low, low + rng.uniform(1.0, 40.0)))
        x_loop, fun_loop, nit_loop, _, status_loop = _python_loop(problem, nlp)
        x_kernel, fun_kernel, nit_kernel, _, status_kernel = _with_kernel(problem, nlp)
        # Both succeed or both fail; a success may be told by a neighbouring test
        # (round-off decrease against the gradient tolerance) when the last digits differ.
        assert (status_kernel > 0) == (status_loop > 0)
        same_status += status_kernel == status_loop
        assert fun_kernel <= fun_loop * (1.0 + 1e-6) + 1e-20
        assert fun_loop <= fun_kernel * (1.0 + 1e-6) + 1e-20
        iteration_differences.append(abs(nit_kernel - nit_loop))
    # Round-off in the last digits may move a threshold test by an iteration or two.
    assert max(iteration_differences) <= 3
    assert sum(difference == 0 for difference in iteration_differences) >= 290
    assert same_status >= 295


def test_paper_option_3_ends_within_one_block_as_the_loop_does():
    # The paper's option-3 start (beta 30, 40, 50 deg; 50 moved onto the bound 40):
    # four steps to RE at round-off zero, then the stopping test, all in one block.
    problem, nlp = _problem([30.0, 40.0, 40.0], [90.0, 90.0], 3, (10.0, 40.0))
    state = run_kernel(nlp, problem.start_rad.tolist(), [],
                       problem.lower_rad.tolist(), problem.upper_rad.tolist(), 1e-12, 3000)
    x_loop, fun_loop, nit_loop, nfev_loop, status_loop = _python_loop(problem, nlp)
    assert ((state["status"], state["nit"], state["nfev"]) == (status_loop, nit_loop, nfev_loop)
            == (1, 4, 5))
    assert state["nit"] < GAUSS_NEWTON_ITERATIONS
    assert state["fun"] <= 1e-28 and fun_loop <= 1e-28
    np.testing.assert_allclose(state["x"], x_loop, rtol=0, atol=1e-12)


def test_a_minimum_above_zero_is_handed_to_the_newton_steps():
    # Option 1 of the paper's angles 15, 20, 9 deg: the minimum over the phases is
    # RE 1.147e-4 (not zero), where Gauss-Newton slows down: the kernel hands over.
    problem, nlp = _problem([15.0, 20.0, 9.0], [30.0, 40.0], 1, (0.0, 40.0))
    state = run_kernel(nlp, problem.start_rad.tolist(),
                       problem.parameters_rad.tolist(), problem.lower_rad.tolist(),
                       problem.upper_rad.tolist(), 1e-12, 3000)
    assert state["status"] == NEWTON
    x_loop, fun_loop, _, _, status_loop = _python_loop(problem, nlp)
    x_kernel, fun_kernel, _, _, status_kernel = _with_kernel(problem, nlp)
    assert status_kernel == status_loop == 1
    assert fun_kernel == pytest.approx(fun_loop, rel=1e-12)
    assert fun_kernel == pytest.approx(1.147051e-4, rel=1e-6)
    np.testing.assert_allclose(x_kernel, x_loop, rtol=0, atol=1e-9)


@pytest.mark.parametrize("max_iterations", [1, 2, GAUSS_NEWTON_ITERATIONS + 1])
def test_the_iteration_limit_holds_in_and_across_blocks(max_iterations):
    problem, nlp = _problem([30.0, 40.0, 40.0], [90.0, 90.0], 3, (10.0, 40.0))
    problem_1, nlp_1 = _problem([15.0, 20.0, 9.0], [30.0, 40.0], 1, (0.0, 40.0))
    for case, case_nlp in ((problem, nlp), (problem_1, nlp_1)):
        loop = _python_loop(case, case_nlp, max_iterations)
        kernel = _with_kernel(case, case_nlp, max_iterations)
        assert kernel[2:] == loop[2:]
        assert kernel[2] <= max_iterations
        assert kernel[1] == pytest.approx(loop[1], rel=1e-9)


def test_a_start_outside_the_bounds_is_moved_onto_them_first():
    problem, nlp = _problem([30.0, 40.0, 40.0], [90.0, 90.0], 3, (10.0, 40.0))
    outside = problem.start_rad.tolist()
    outside[2] = np.radians(60.0)
    state = run_kernel(nlp, outside, [], problem.lower_rad.tolist(),
                       problem.upper_rad.tolist(), 1e-12, 1)
    assert state["status"] == 0 and state["nit"] == 1
    assert all(low <= value <= high for value, low, high in
               zip(state["x"], problem.lower_rad.tolist(), problem.upper_rad.tolist(), strict=True))
    assert state["status"] != RUNNING


def test_the_newton_blocks_take_the_newton_steps_as_the_python_loop_does():
    # The paper's option-1 case again: the Gauss-Newton blocks hand over (status
    # NEWTON); the Newton blocks (CasADi's symbolic Hessian) and the Python loop (the
    # closed-form Hessian) continue from the same state by the same rules.
    problem, nlp = _problem([15.0, 20.0, 9.0], [30.0, 40.0], 1, (0.0, 40.0))
    fixed, lower, upper = (problem.parameters_rad.tolist(), problem.lower_rad.tolist(),
                           problem.upper_rad.tolist())
    handed = run_kernel(nlp, problem.start_rad.tolist(), fixed, lower, upper, 1e-12, 3000)
    assert handed["status"] == NEWTON
    compiled = run_newton_blocks(nlp, dict(handed), fixed, lower, upper, 1e-12, 3000)
    loop = lm._newton_steps(lambda x: nlp.residuals_and_jacobian(x, fixed), dict(handed),
                            lower, upper, 1e-12, 3000, lambda x: nlp.objective_hessian(x, fixed))
    assert (compiled["status"], compiled["nit"], compiled["nfev"]) == (
        loop["status"], loop["nit"], loop["nfev"])
    assert compiled["status"] == 1 and compiled["nit"] > handed["nit"]
    assert compiled["fun"] == pytest.approx(loop["fun"], rel=1e-12)
    np.testing.assert_allclose(compiled["x"], loop["x"], rtol=0, atol=1e-10)


def _indefinite_case():
    # Found by a random search: six joints of option 1 whose Newton steps begin far from
    # the minimum, where the Hessian is indefinite. The problem, its NLP, fixed values,
    # bounds, and the state where the Gauss-Newton blocks hand over.
    problem, nlp = _problem([37.4, 17.0, 16.7, 24.3, 9.7, 11.1],
                            [45.9, 75.2, -11.2, 143.1, 103.2], 1, (13.2, 25.9))
    fixed, lower, upper = (problem.parameters_rad.tolist(), problem.lower_rad.tolist(),
                           problem.upper_rad.tolist())
    handed = run_kernel(nlp, problem.start_rad.tolist(), fixed, lower, upper, 1e-12, 3000)
    return problem, nlp, fixed, lower, upper, handed


def test_the_newton_blocks_hand_an_indefinite_hessian_back():
    # The Newton blocks do not shift a Hessian past its most negative eigenvalue: they
    # stop with NEWTON_INDEFINITE and leave the state for the shifted iteration.
    problem, nlp, fixed, lower, upper, handed = _indefinite_case()
    block = kernels_of(nlp).buffered("newton", 1)
    problem_values = problem_vector(fixed, lower, upper, 1e-12, 3000)
    values = pack(handed)
    while unpack(values, len(lower))["status"] == NEWTON:
        values = block.flat(values, problem_values)
    stopped = unpack(values, len(lower))
    assert stopped["status"] == NEWTON_INDEFINITE
    assert stopped["nit"] >= handed["nit"]
    assert np.linalg.eigvalsh(np.array(nlp.objective_hessian(stopped["x"], fixed)))[0] < 0


def test_a_shifted_newton_iteration_takes_the_python_loop_s_step():
    # One shifted Newton iteration (its lowest eigenvalue by bisection) against the Python
    # loop's (LAPACK's eigenvalue), step by step from where the Gauss-Newton blocks hand
    # over, through Hessians that are not positive definite.
    problem, nlp, fixed, lower, upper, handed = _indefinite_case()
    _, iteration = iteration_functions(nlp.symbols["x"], nlp.symbols["p"], nlp.residuals,
                                       "shifted")
    problem_values = problem_vector(fixed, lower, upper, 1e-12, 3000)
    state, indefinite = dict(handed), 0
    for _ in range(8):
        if state["status"] != NEWTON:
            break
        indefinite += np.linalg.eigvalsh(np.array(nlp.objective_hessian(state["x"], fixed)))[0] < 0
        values = iteration(pack(state), problem_values).full().ravel().tolist()
        compiled = unpack(values, len(lower))
        loop = newton_iteration(PYTHON, _evaluate(nlp, fixed),
                                lambda point, gradient, free, needed: (
                                    nlp.objective_hessian(point, fixed), 1),
                                state, lower, upper, 1e-12, 3000)
        assert compiled["status"] == loop["status"]
        assert compiled["nit"] == loop["nit"]
        assert compiled["fun"] == pytest.approx(loop["fun"], rel=1e-9)
        np.testing.assert_allclose(compiled["x"], loop["x"], rtol=0, atol=1e-9)
        state = compiled
    assert indefinite >= 1


def test_a_solve_through_indefinite_hessians_ends_as_the_python_loop_does():
    problem, nlp, fixed, lower, upper, handed = _indefinite_case()
    compiled = run_newton_blocks(nlp, dict(handed), fixed, lower, upper, 1e-12, 3000)
    x_loop, fun_loop, nit_loop, _, status_loop = _python_loop(problem, nlp)
    assert compiled["status"] > 0 and status_loop > 0
    assert compiled["fun"] == pytest.approx(fun_loop, rel=1e-9)
    assert abs(compiled["nit"] - nit_loop) <= 1


@pytest.mark.parametrize(("joints", "option"), [(3, 3), (4, 1), (6, 1)])
def test_the_mapped_blocks_end_each_design_bit_for_bit_as_one_design_alone(joints, option):
    # Reference: solve_one, the blocks called on one design. solve_states runs the same
    # functions through Function.map, in parts of every MAP_COLUMNS size (the last padded):
    # each design's whole state must be the same bits.
    problem, nlp = _problem([20.0] * joints, [30.0] * (joints - 1), option, (5.0, 35.0))
    kernels = kernels_of(nlp)
    rng = np.random.default_rng(70 + joints)
    count = MAP_COLUMNS[2] + 3  # one full part of 64 columns and one padded part of 8
    size = kernels.size
    starts = np.radians(rng.uniform(0.0, 180.0, (count, size)))
    fixed = np.radians(rng.uniform(5.0, 35.0, (count, kernels.problem_size - 2 * size - 2)))
    lower, upper = problem.lower_rad.tolist(), problem.upper_rad.tolist()
    problems = np.array([problem_vector(row.tolist(), lower, upper, 1e-12, 3000)
                         for row in fixed])
    mapped = solve_states(kernels, starts, problems)
    statuses = set()
    for row in range(count):
        alone = solve_one(kernels, starts[row].tolist(), problems[row].tolist())
        assert [value.hex() for value in mapped[row].tolist()] == [value.hex() for value in alone]
        statuses.add(unpack(alone, size)["status"])
    assert RUNNING not in statuses and NEWTON not in statuses


def test_every_call_gives_the_same_bits():
    # Nothing switches on a count of calls: the tenth solve of a shape whose Newton steps
    # run in its blocks ends as the first did, bit for bit.
    problem, nlp = _problem([15.0, 20.0, 9.0], [30.0, 40.0], 1, (0.0, 40.0))
    answers = [_with_kernel(problem, nlp) for _ in range(10)]
    first = answers[0]
    assert first[4] == 1 and first[1] == pytest.approx(1.147051e-4, rel=1e-6)
    for answer in answers[1:]:
        assert [value.hex() for value in answer[0]] == [value.hex() for value in first[0]]
        assert answer[1:] == first[1:]
