"""The Gauss-Newton iterations of the ``"lm"`` solver, compiled into one CasADi function.

One iteration of :func:`sso.solvers.lm.minimise` in its Gauss-Newton mode is a
few dozen operations on top of one residual-and-Jacobian evaluation. Written in
Python, every operation costs the interpreter tens of nanoseconds. Here one
iteration is a CasADi SX function (a flat instruction list); a block chains
:data:`KERNEL_ITERATIONS` of them and is expanded into one instruction list
(built in about 15 ms for 3 joints, 70 ms for 30), which CasADi's virtual machine
runs in about the time Python takes for one iteration. Blocks run one after
another until the solve ends (RE at round-off zero, the projected gradient under
the tolerance, a failure, the iteration limit) or turns to Newton steps, which
the Python loop takes from the state the kernel hands it.

The kernel is the same algorithm, step for step: the same projected step over the
free variables, the same damping rules, the same tests in the same order, so it
ends with the Python loop's status and iteration count (up to round-off in the
last digits, which can move a threshold test by an iteration; the tests compare
both on random problems). Branches become ``if_else`` selections: every
iteration of a block is evaluated, and one after the end leaves the state as it
was.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from sso.solvers.nlp import BufferedFunction

KERNEL_ITERATIONS = 6
"""Iterations chained in one block of the kernel, which runs block after block until
the solve ends. Most exact-model solves of 3 to 6 joints take 4 or 5 steps and the
final test, which one block of 6 holds (the paper's option 3: 4 steps); an
iteration after the end still costs its instructions."""

RUNNING = 10
"""Kernel status of a solve still under way (the Python loop continues it)."""
NEWTON = 11
"""Kernel status of a solve that switches to Newton steps (the Python loop takes them)."""


@dataclass(frozen=True)
class KernelState:
    """Where the kernel left a solve: the Python loop's variables at the top of an iteration.

    Attributes
    ----------
    x : list of float
        The design vector.
    residuals : list of float
        ``r1, r2`` at ``x``.
    jacobian_entries : list of float
        ``dr1/dx_i, dr2/dx_i`` for each ``i`` in turn.
    fun : float
        ``r1^2 + r2^2``.
    nit, nfev : int
        Trial steps and residual evaluations so far.
    status : int
        A key of :data:`sso.solvers.lm.MESSAGES`, or :data:`RUNNING` /
        :data:`NEWTON` when the Python loop is to continue.
    damping, growth : float
        The damping and its growth factor on the next rejected step.
    slow_steps : int
        Accepted steps that did not halve the projected gradient.
    previous_norm, first_size : float
        The last accepted step's projected gradient and the start's ``|rho|``.
    """

    x: list[float]
    residuals: list[float]
    jacobian_entries: list[float]
    fun: float
    nit: int
    nfev: int
    status: int
    damping: float
    growth: float
    slow_steps: int
    previous_norm: float
    first_size: float

    @property
    def rho(self) -> complex:
        """``r1 - i r2``, as :func:`sso.kinematics.hooke_matrix.residual_and_jacobian_complex`
        gives it."""
        return complex(self.residuals[0], -self.residuals[1])

    @property
    def jacobian(self) -> list[complex]:
        """``d rho / dx`` in the same form."""
        entries = self.jacobian_entries
        return [complex(entries[index], -entries[index + 1])
                for index in range(0, len(entries), 2)]


_SCALARS = ("fun", "nit", "nfev", "status", "damping", "growth", "slow_steps", "previous_norm",
            "first_size")


def kernel_of(nlp: Any, constants: Mapping[str, float]) -> BufferedFunction | None:
    """The NLP's kernel, built on first use and kept on it; None without residuals.

    Parameters
    ----------
    nlp : sso.solvers.nlp.CompiledNLP
    constants : dict of str to float
        As in :func:`build_kernel`.
    """
    if nlp.lm_kernel is None and nlp.residuals is not None:
        nlp.lm_kernel = build_kernel(nlp.symbols["x"], nlp.symbols["p"], nlp.residuals,
                                     constants)
    kernel: BufferedFunction | None = nlp.lm_kernel
    return kernel


def build_kernel(x: Any, p: Any, residual: Any,
                 constants: Mapping[str, float]) -> BufferedFunction:
    """One block of :data:`KERNEL_ITERATIONS` iterations for residuals ``residual(x, p)``.

    Parameters
    ----------
    x, p : casadi.SX
        Design variables and fixed parameters (column vectors).
    residual : casadi.SX
        The two residuals (a 2-vector).
    constants : mapping of str to float
        The Python loop's constants (``accept_ratio``, ``initial_damping``,
        ``max_damping``, ``zero_residual``, ``round_off``, ``slow_level``,
        ``slow_steps``), so both share one set.

    Returns
    -------
    BufferedFunction
        ``(state, problem) -> state``: ``state`` is ``x``, ``r1, r2``, the Jacobian
        (``dr1/dx_i, dr2/dx_i`` for each ``i``) and the loop's numbers in the
        order of ``_SCALARS``, one vector; ``problem`` is ``p``, the lower and upper
        bounds, the tolerance and the iteration limit, one vector. A state with
        ``nfev = 0`` is a fresh start: ``x`` is clipped onto the bounds and
        evaluated there.
    """
    import casadi

    size = x.numel()
    evaluate = casadi.Function("lm_residual", [x, p],
                               [residual, casadi.densify(casadi.jacobian(residual, x))])
    # One iteration and the start as SX functions (each one flat instruction list),
    # chained KERNEL_ITERATIONS times in MX (a few call nodes, built in milliseconds
    # at any size), then expanded into a single instruction list.
    state_in = casadi.SX.sym("state", 3 * size + 2 + len(_SCALARS))
    problem_in = casadi.SX.sym("problem", p.numel() + 2 * size + 2)
    x_in, r_in, jacobian_in, scalars_in = casadi.vertsplit(
        state_in, [0, size, size + 2, 3 * size + 2, state_in.numel()])
    parameters, lower, upper, settings = casadi.vertsplit(
        problem_in, [0, p.numel(), p.numel() + size, p.numel() + 2 * size, problem_in.numel()])
    given: dict[str, Any] = dict(zip(_SCALARS, casadi.vertsplit(scalars_in), strict=True))
    given.update(x=x_in, r=r_in, J=casadi.reshape(jacobian_in, 2, size))

    def packed(state: dict[str, Any]) -> Any:
        return casadi.vertcat(state["x"], state["r"], casadi.vec(state["J"]),
                              *(casadi.SX(state[name]) for name in _SCALARS))

    iteration = casadi.Function(
        "lm_iteration", [state_in, problem_in],
        [packed(_iteration(casadi, evaluate, given, parameters, lower, upper, settings[0],
                           settings[1], constants))], {"cse": True})
    start = casadi.Function(
        "lm_start", [state_in, problem_in],
        [packed(_start(casadi, evaluate, given, parameters, lower, upper, constants))],
        {"cse": True})
    state = casadi.MX.sym("state", state_in.numel())
    problem = casadi.MX.sym("problem", problem_in.numel())
    chained = start(state, problem)
    for _ in range(KERNEL_ITERATIONS):
        chained = iteration(chained, problem)
    return BufferedFunction(casadi.Function("lm_kernel", [state, problem], [chained]).expand())


def _start(casadi: Any, evaluate: Any, given: dict[str, Any], parameters: Any, lower: Any,
           upper: Any, constants: Mapping[str, float]) -> dict[str, Any]:
    """The given state, or with ``nfev = 0`` a fresh one: ``x`` clipped onto the bounds
    and evaluated there, the damping at its initial value."""
    if_else = casadi.if_else
    fresh = given["nfev"] == 0
    point = casadi.fmin(casadi.fmax(given["x"], lower), upper)
    r, jacobian = evaluate(point, parameters)
    fun = casadi.dot(r, r)
    fresh_state = {
        "x": point, "r": r, "J": jacobian, "fun": fun, "nit": 0, "nfev": 1, "status": RUNNING,
        "damping": constants["initial_damping"], "growth": 2.0, "slow_steps": 0,
        "previous_norm": casadi.inf, "first_size": casadi.fmax(casadi.sqrt(fun), 1e-300),
    }
    return {name: if_else(fresh, value, given[name]) for name, value in fresh_state.items()}


def run_kernel(kernel: BufferedFunction, start: list[float], parameters: list[float],
               lower: list[float], upper: list[float], tolerance: float,
               max_iterations: int) -> KernelState:
    """Blocks of the kernel from ``start`` (clipped onto the bounds) until the solve ends or
    is handed to the Python loop."""
    size = len(start)
    problem = [*parameters, *lower, *upper, tolerance, float(max_iterations)]
    (state,) = kernel(start + [0.0] * (2 * size + 2 + len(_SCALARS)), problem)
    status_index = 3 * size + 2 + _SCALARS.index("status")
    while state[status_index] == RUNNING:  # each block takes KERNEL_ITERATIONS more steps
        (state,) = kernel(state, problem)
    values = state.tolist()
    fun, nit, nfev, status, damping, growth, slow_steps, previous_norm, first_size = (
        values[3 * size + 2:])
    return KernelState(values[:size], values[size:size + 2], values[size + 2:3 * size + 2],
                       fun, int(nit), int(nfev), int(status), damping, growth, int(slow_steps),
                       previous_norm, first_size)


def _iteration(casadi: Any, evaluate: Any, state: dict[str, Any], parameters: Any, lower: Any,
               upper: Any, tolerance: Any, max_iterations: Any,
               constants: Mapping[str, float]) -> dict[str, Any]:
    """One iteration of the Python loop's Gauss-Newton mode, every branch a selection."""
    if_else = casadi.if_else
    x, r, jacobian, fun = state["x"], state["r"], state["J"], state["fun"]
    status, nit, nfev = state["status"], state["nit"], state["nfev"]
    running = status == RUNNING
    round_off = constants["round_off"]

    # The top of the loop: the iteration limit, finiteness, the two stopping tests.
    status = if_else(running * (nit >= max_iterations), 0, status)
    running = status == RUNNING
    total = fun + casadi.sum1(casadi.sum2(casadi.fabs(jacobian)))
    finite = (total == total) * (casadi.fabs(total) < casadi.inf)
    status = if_else(running * (1 - finite), -2, status)
    running = status == RUNNING
    gradient = 2.0 * (jacobian.T @ r)
    projected = casadi.fmin(casadi.fmax(x - gradient, lower), upper)
    norm = casadi.mmax(casadi.fabs(x - projected))
    status = if_else(running * (norm <= tolerance), 1, status)
    running = status == RUNNING
    status = if_else(running * (fun <= constants["zero_residual"]), 4, status)
    running = status == RUNNING

    # The damped Gauss-Newton step over the free variables.
    free = ((upper > lower) * (1 - (x <= lower) * (gradient > 0))
            * (1 - (x >= upper) * (gradient < 0)))
    first, second = jacobian[0, :].T * free, jacobian[1, :].T * free
    a11, a12, a22 = casadi.dot(first, first), casadi.dot(first, second), casadi.dot(second, second)
    size = casadi.sqrt(fun)
    mu = (state["damping"] * casadi.fmax(0.5 * (a11 + a22), 1e-30)
          * casadi.fmin(1.0, size / state["first_size"]))
    a11, a22 = a11 + mu, a22 + mu
    determinant = a11 * a22 - a12 * a12
    y1 = (a22 * r[0] - a12 * r[1]) / determinant
    y2 = (a11 * r[1] - a12 * r[0]) / determinant
    step = -(first * y1 + second * y2)
    trial = casadi.fmin(casadi.fmax(x + step, lower), upper)
    move = trial - x
    # fmin and fmax drop a NaN, which would put a NaN step component onto a bound; in
    # the loop it stays NaN, counts for no move and makes the step rejected.
    finite = step == step
    all_finite = casadi.sum1(finite) == step.numel()
    largest_move = casadi.mmax(finite * casadi.fabs(move))
    largest_value = casadi.mmax(casadi.fabs(x))
    status = if_else(running * (largest_move <= round_off * (1.0 + largest_value)), 3, status)
    running = status == RUNNING
    model = r + jacobian @ move
    predicted = fun - casadi.dot(model, model)
    trial_r, trial_jacobian = evaluate(trial, parameters)
    trial_fun = casadi.dot(trial_r, trial_r)
    actual = fun - trial_fun
    accept = all_finite * (predicted > 0) * (actual >= constants["accept_ratio"] * predicted)
    negligible = (all_finite * (casadi.fabs(actual) <= round_off * fun)
                  * (predicted <= round_off * fun))

    ratio = actual / predicted
    accepted_damping = state["damping"] * casadi.fmax(1.0 / 3.0, 1.0 - (2.0 * ratio - 1.0) ** 3)
    slow = (trial_fun > constants["slow_level"]) * (norm > 0.5 * state["previous_norm"])
    slow_steps = state["slow_steps"] + slow
    accepted_status = if_else(negligible, 2,
                              if_else(slow_steps >= constants["slow_steps"], NEWTON, RUNNING))
    rejected_damping = state["damping"] * state["growth"]
    rejected_status = if_else(negligible, 2,
                              if_else(rejected_damping > constants["max_damping"], -1, RUNNING))

    moves = running * accept
    stays = running * (1 - accept)

    def kept(on_accept: Any, unchanged: Any) -> Any:
        return if_else(moves, on_accept, unchanged)

    return {
        "x": kept(trial, x),
        "r": kept(trial_r, r),
        "J": kept(trial_jacobian, jacobian),
        "fun": kept(trial_fun, fun),
        "nit": nit + running,
        "nfev": nfev + running,
        "status": if_else(running, if_else(accept, accepted_status, rejected_status), status),
        "damping": if_else(moves, accepted_damping,
                           if_else(stays, rejected_damping, state["damping"])),
        "growth": if_else(moves, 2.0, if_else(stays, 2.0 * state["growth"], state["growth"])),
        "slow_steps": kept(slow_steps, state["slow_steps"]),
        "previous_norm": kept(norm, state["previous_norm"]),
        "first_size": state["first_size"],
    }
