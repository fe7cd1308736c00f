"""The CasADi NLP wrapper: exact derivatives through buffers, one graph per shape and thread."""

from __future__ import annotations

import threading

import numpy as np
import pytest
from solvers.problems import (
    PARAMETERS,
    rosenbrock,
    rosenbrock_gradient,
    two_constraints,
)

from sso._solvers.nlp import CompiledNLP, cached_nlp


def test_objective_and_gradient_match_the_hand_derivative():
    nlp = rosenbrock()
    for point in ([0.3, 0.7], [-1.2, 1.0], [1.0, 1.0]):
        x = np.array(point)
        value, gradient = nlp.objective_and_gradient(x, PARAMETERS)
        assert isinstance(value, float)
        assert value == pytest.approx((1 - x[0]) ** 2 + 100 * (x[1] - x[0] ** 2) ** 2, rel=1e-15)
        np.testing.assert_allclose(gradient, rosenbrock_gradient(x), rtol=1e-14, atol=1e-14)
    # The parameter enters: p = 3 triples both.
    value, gradient = nlp.objective_and_gradient(np.array([0.3, 0.7]), 3.0 * PARAMETERS)
    assert value == pytest.approx(3 * 37.7, rel=1e-14)
    np.testing.assert_allclose(gradient, 3 * rosenbrock_gradient(np.array([0.3, 0.7])), rtol=1e-14)


def test_constraints_and_jacobian():
    nlp, _ = two_constraints()
    values, jacobian = nlp.constraints_and_jacobian(np.array([0.5, 2.0]), PARAMETERS)
    np.testing.assert_allclose(values, [0.25 - 2.0, 2.5], rtol=1e-15)
    np.testing.assert_allclose(jacobian, [[1.0, -1.0], [1.0, 1.0]], rtol=1e-15)  # (2 x0, -1)
    assert rosenbrock().constraints_and_jacobian is None
    assert set(nlp.symbols) == {"x", "p", "f", "g"}


def test_results_are_fresh_arrays_not_the_buffers():
    nlp = rosenbrock()
    _, first = nlp.objective_and_gradient(np.array([0.3, 0.7]), PARAMETERS)
    kept = first.copy()
    nlp.objective_and_gradient(np.array([-1.2, 1.0]), PARAMETERS)
    np.testing.assert_array_equal(first, kept)


def test_ipopt_solver_is_built_once_per_option_set():
    nlp = rosenbrock()
    solver = nlp.ipopt({"tol": 1e-8, "max_iter": 10})
    assert nlp.ipopt({"max_iter": 10, "tol": 1e-8}) is solver
    assert nlp.ipopt({"tol": 1e-9, "max_iter": 10}) is not solver
    assert len(nlp.ipopt_solvers) == 2


def _plain_ipopt(nlp):
    """CasADi's own nlpsol of the problem, called with CasADi matrices: the reference of
    the buffered solver (options as ``nlp.ipopt({"tol": 1e-10, "max_iter": 100})``)."""
    import casadi

    return casadi.nlpsol("plain", "ipopt", nlp.symbols,
                         {"print_time": False, "ipopt": {"print_level": 0, "sb": "yes",
                                                         "tol": 1e-10, "max_iter": 100}})


def test_buffered_ipopt_answers_and_counts_each_solve_as_the_plain_call():
    # The reference is CasADi's own call of the same nlpsol (inputs and outputs as
    # CasADi matrices). The buffer's memory adds its evaluation counts over its solves;
    # each solve must report its own, as the plain call does, the second as the first.
    nlp = rosenbrock()
    solver = nlp.ipopt({"tol": 1e-10, "max_iter": 100})
    plain = _plain_ipopt(nlp)
    arguments = {"x0": [-1.2, 1.0], "p": PARAMETERS.tolist(), "lbx": [-2.0, -2.0],
                 "ubx": [2.0, 2.0]}
    expected = plain(**arguments)
    counted = ("iter_count", "n_call_nlp_f", "n_call_nlp_grad_f", "n_call_nlp_hess_l")
    for _ in range(2):
        answer = solver(**arguments)
        np.testing.assert_array_equal(answer["x"], expected["x"].full().ravel())
        assert answer["f"][0] == float(expected["f"])
        np.testing.assert_array_equal(answer["lam_x"], expected["lam_x"].full().ravel())
        assert solver.stats()["return_status"] == plain.stats()["return_status"]
        assert [solver.stats()[name] for name in counted] == [plain.stats()[name]
                                                               for name in counted]
        assert solver.stats()["n_call_nlp_f"] > 0


def test_an_input_a_buffered_solve_leaves_out_is_the_default_again():
    # The buffers keep what the last solve wrote: an input given once and then left out
    # must be back at the solver's default (here the bounds: -inf and inf), also after a
    # call that failed halfway through writing its inputs. The reference is CasADi's
    # plain call, which takes the default for every input left out.
    nlp = rosenbrock()
    solver = nlp.ipopt({"tol": 1e-10, "max_iter": 100})
    plain = _plain_ipopt(nlp)
    free = {"x0": [-1.2, 1.0], "p": PARAMETERS.tolist()}
    expected = plain(**free)["x"].full().ravel()
    np.testing.assert_allclose(expected, [1.0, 1.0], atol=1e-8)  # Rosenbrock's minimum
    boxed = solver(**free, lbx=[-2.0, -2.0], ubx=[0.5, 0.5])["x"]
    assert boxed[0] == pytest.approx(0.5, abs=1e-8)  # held by the box
    np.testing.assert_array_equal(solver(**free)["x"], expected)
    with pytest.raises(ValueError):  # lbx written, then ubx of the wrong length
        solver(**free, lbx=[0.9, 0.9], ubx=[1.0, 1.0, 1.0])
    np.testing.assert_array_equal(solver(**free)["x"], expected)


def test_buffered_ipopt_refuses_unknown_inputs_and_raises_what_casadi_raises():
    solver = rosenbrock().ipopt({"max_iter": 10})
    with pytest.raises(TypeError, match=r"unknown solver inputs \['x_start'\]"):
        solver(x_start=[0.0, 0.0])
    with pytest.raises(RuntimeError, match="LBX"):  # crossed bounds: CasADi's own check
        solver(x0=[0.0, 0.0], p=PARAMETERS, lbx=[1.0, 1.0], ubx=[0.0, 0.0])


def test_cache_builds_once_per_key_and_per_thread():
    builds: list[str] = []

    def build() -> CompiledNLP:
        builds.append(threading.current_thread().name)
        return rosenbrock()

    key = ("test_nlp_cache", 2)
    first = cached_nlp(key, build)
    assert cached_nlp(key, build) is first
    other: list[CompiledNLP] = []
    thread = threading.Thread(target=lambda: other.append(cached_nlp(key, build)), name="other")
    thread.start()
    thread.join()
    assert other[0] is not first
    assert builds == [threading.current_thread().name, "other"]
