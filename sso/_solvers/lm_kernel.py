"""The ``"lm"`` solver's iterations compiled into one CasADi function.

One iteration of the rules (:mod:`sso._solvers.lm_rules`) is a few dozen operations
on top of one residual-and-Jacobian evaluation. Written in Python, every operation
costs the interpreter tens of nanoseconds. Here the rules are evaluated on CasADi
symbols: one iteration is an SX function (a flat instruction list); a block chains
:data:`KERNEL_ITERATIONS` of them and is expanded into one instruction list
(built in about 15 ms for 3 joints, 70 ms for 30), which CasADi's virtual machine
runs in about the time Python takes for one iteration. Blocks run one after
another until the solve ends (RE at round-off zero, the projected gradient under
the tolerance, a failure, the iteration limit) or turns to Newton steps, which
the Newton kernel takes once a shape has asked for it often enough (the Python loop
before). A Newton step whose damped Hessian is not positive definite is taken by a
separate compiled step that shifts it past its most negative eigenvalue (found by
bisection, :func:`sso._solvers.lm_rules.bisected_lowest_eigenvalue`): its instructions
are spent only on such a step, not on every Newton iteration.

The kernel and the Python loop are the same rules, step for step, so the kernel
ends with the Python loop's status and iteration count (up to round-off in the
last digits, which can move a threshold test by an iteration; the tests compare
both on random problems). Branches are ``if_else`` selections: every iteration of a
block is evaluated, and one after the end leaves the state as it was.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from functools import cache
from typing import Any

from sso._solvers.lm_rules import (
    EIGENVALUE_HALVINGS,
    NEWTON,
    NEWTON_INDEFINITE,
    RUNNING,
    SCALARS,
    Operations,
    eigenvalue_bracket,
    fresh_state,
    gauss_newton_iteration,
    halve_eigenvalue_bracket,
    newton_iteration,
)
from sso._solvers.nlp import BufferedFunction

SWITCH_VARIABLE = "SSO_NATIVE_LM"
"""Environment variable: ``0`` keeps the ``"lm"`` iterations on CasADi's virtual machine (the
single solve) and on numpy (:func:`sso.optimise_batch`) instead of the library compiled to
machine code (:mod:`sso._solvers.lm_native`)."""

KERNEL_ITERATIONS = 6
"""Iterations chained in one block of the kernel, which runs block after block until
the solve ends. Most exact-model solves of 3 to 6 joints take 4 or 5 steps and the
final test, which one block of 6 holds (the paper's option 3: 4 steps); an
iteration after the end still costs its instructions."""

NEWTON_KERNEL_ITERATIONS = 4
"""Newton iterations chained in one block of the Newton kernel."""

NEWTON_KERNEL_AFTER = 8
"""Solves of one shape whose Newton steps the Python loop takes before the Newton kernel
is built for it: its build (tens of milliseconds) costs more than one solve's Newton
steps, so a shape solved once or twice (one case of the command line) never pays it."""

NEWTON_KERNEL_VARIABLES = 12
"""The Newton kernel is built for at most this many variables (6 joints of option 3 have
11): its Hessian and Cholesky factor grow with the square and the cube of their count,
and so do its build time and memory; larger problems take their Newton steps in the
Python loop."""


def kernel_of(nlp: Any) -> BufferedFunction | None:
    """The NLP's kernel, built on first use and kept on it; None without residuals.

    Parameters
    ----------
    nlp : sso._solvers.nlp.CompiledNLP
    """
    if nlp.lm_kernel is None and nlp.residuals is not None:
        nlp.lm_kernel = build_kernel(nlp.symbols["x"], nlp.symbols["p"], nlp.residuals)
    kernel: BufferedFunction | None = nlp.lm_kernel
    return kernel


@dataclass(frozen=True)
class NewtonKernels:
    """The compiled Newton steps of one shape.

    Attributes
    ----------
    blocks : BufferedFunction
        :data:`NEWTON_KERNEL_ITERATIONS` Newton iterations; a state whose damped Hessian
        is not positive definite is left with status
        :data:`sso._solvers.lm_rules.NEWTON_INDEFINITE`.
    shifted : BufferedFunction
        One Newton iteration whose Hessian is shifted past its most negative eigenvalue
        where it is not positive definite (the step the Python loop takes there), from
        a state of status ``NEWTON``.
    """

    blocks: BufferedFunction
    shifted: BufferedFunction


def newton_kernel_of(nlp: Any) -> NewtonKernels | None:
    """The NLP's Newton kernels, kept on it; None without residuals, with more than
    :data:`NEWTON_KERNEL_VARIABLES` variables, or while fewer than
    :data:`NEWTON_KERNEL_AFTER` solves of the shape have asked for them."""
    if nlp.lm_newton_kernel is None and nlp.residuals is not None:
        nlp.lm_newton_requests += 1
        if (nlp.lm_newton_requests >= NEWTON_KERNEL_AFTER
                and nlp.symbols["x"].numel() <= NEWTON_KERNEL_VARIABLES):
            symbols = (nlp.symbols["x"], nlp.symbols["p"], nlp.residuals)
            nlp.lm_newton_kernel = NewtonKernels(build_kernel(*symbols, mode="newton"),
                                                 build_kernel(*symbols, mode="shifted"))
    kernels: NewtonKernels | None = nlp.lm_newton_kernel
    return kernels


MODES = ("gauss_newton", "newton", "shifted")
"""The iterations a kernel can chain: Gauss-Newton, Newton (handing back a Hessian that its
damping leaves indefinite), Newton shifted past the most negative eigenvalue."""


def build_kernel(x: Any, p: Any, residual: Any, mode: str = "gauss_newton"
                 ) -> BufferedFunction:
    """One block of iterations for residuals ``residual(x, p)``.

    :data:`KERNEL_ITERATIONS` Gauss-Newton iterations; with ``mode = "newton"``
    :data:`NEWTON_KERNEL_ITERATIONS` Newton iterations with CasADi's symbolic Hessian of
    the sum of squares (a state whose shifted Hessian is not positive definite is left
    with status :data:`sso._solvers.lm_rules.NEWTON_INDEFINITE`); with ``"shifted"`` one
    Newton iteration that shifts such a Hessian past its most negative eigenvalue.

    Parameters
    ----------
    x, p : casadi.SX
        Design variables and fixed parameters (column vectors).
    residual : casadi.SX
        The two residuals (a 2-vector).

    The start and one iteration are SX functions (each one flat instruction list),
    chained in MX (a few call nodes, built in milliseconds at any size), then expanded
    into a single instruction list.

    Returns
    -------
    BufferedFunction
        ``(state, problem) -> state``: ``state`` is the flat list of :func:`pack`, one
        vector; ``problem`` is ``p``, the lower and upper bounds, the tolerance and
        the iteration limit, one vector. A state with ``nfev = 0`` is a fresh start:
        ``x`` is clipped onto the bounds and evaluated there.
    """
    import casadi

    start, iteration = iteration_functions(x, p, residual, mode)
    state = casadi.MX.sym("state", start.numel_in(0))
    problem = casadi.MX.sym("problem", start.numel_in(1))
    chained = start(state, problem)
    chain = {"gauss_newton": KERNEL_ITERATIONS, "newton": NEWTON_KERNEL_ITERATIONS,
             "shifted": 1}[mode]
    for _ in range(chain):
        chained = iteration(chained, problem)
    return BufferedFunction(casadi.Function("lm_kernel", [state, problem], [chained]).expand())


def iteration_operations(nlp: Any) -> int:
    """Arithmetic operations of one Gauss-Newton iteration of the rules for the NLP's shape
    (one residual-and-Jacobian evaluation and the step, every branch computed): the
    instructions of its compiled form less those that only read inputs or constants and
    write outputs."""
    import casadi

    _, iteration = iteration_functions(nlp.symbols["x"], nlp.symbols["p"], nlp.residuals)
    bookkeeping = {casadi.OP_INPUT, casadi.OP_OUTPUT, casadi.OP_CONST}
    return sum(iteration.instruction_id(index) not in bookkeeping
               for index in range(iteration.n_instructions()))


def iteration_functions(x: Any, p: Any, residual: Any, mode: str = "gauss_newton"
                        ) -> tuple[Any, Any]:
    """The start and one iteration of ``mode`` (one of :data:`MODES`) as SX functions
    ``(state, problem) -> state``, each one flat instruction list.

    Raises
    ------
    ValueError
        If ``mode`` is not one of :data:`MODES`.
    """
    import casadi

    if mode not in MODES:
        raise ValueError(f"mode = {mode!r} is not one of {MODES}")
    ops = casadi_operations(shifting=mode == "shifted")
    size = x.numel()
    evaluate_function = casadi.Function(
        "lm_residual", [x, p], [residual, casadi.densify(casadi.jacobian(residual, x))])
    state_in = casadi.SX.sym("state", 3 * size + 2 + len(SCALARS))
    problem_in = casadi.SX.sym("problem", p.numel() + 2 * size + 2)
    parameters, lower, upper, settings = casadi.vertsplit(
        problem_in, [0, p.numel(), p.numel() + size, p.numel() + 2 * size, problem_in.numel()])
    lower_list, upper_list = casadi.vertsplit(lower), casadi.vertsplit(upper)

    def evaluate(point: list[Any]) -> tuple[Any, Any, list[Any], list[Any]]:
        r, derivatives = evaluate_function(casadi.vertcat(*point), parameters)
        return (r[0], r[1], [derivatives[0, i] for i in range(size)],
                [derivatives[1, i] for i in range(size)])

    given = unpack(casadi.vertsplit(state_in), size)
    if mode != "gauss_newton":
        hessian_function = casadi.Function(
            "lm_hessian", [x, p], [casadi.densify(casadi.hessian(casadi.dot(residual, residual),
                                                                 x)[0])])

        def hessian_at(point: list[Any], gradient: list[Any], free: list[Any], needed: Any
                       ) -> tuple[list[list[Any]], Any]:
            matrix = hessian_function(casadi.vertcat(*point), parameters)
            return [[matrix[row, column] for column in range(size)] for row in range(size)], 1

        after = newton_iteration(ops, evaluate, hessian_at, given, lower_list, upper_list,
                                 settings[0], settings[1])
    else:
        after = gauss_newton_iteration(ops, evaluate, given, lower_list, upper_list,
                                       settings[0], settings[1])
    iteration = casadi.Function("lm_iteration", [state_in, problem_in],
                                [casadi.vertcat(*pack(after))], {"cse": True})
    fresh = fresh_state(ops, evaluate, given["x"], lower_list, upper_list)
    is_fresh = given["nfev"] == 0
    start = casadi.Function(
        "lm_start", [state_in, problem_in],
        [casadi.vertcat(*(casadi.if_else(is_fresh, new, old) for new, old in
                          zip(pack(fresh), pack(given), strict=True)))], {"cse": True})
    return start, iteration


def casadi_operations(shifting: bool = False) -> Operations:
    """The rules' operations on CasADi symbols (branches as ``if_else`` selections); with
    ``shifting``, the lowest eigenvalue by bisection (:func:`lowest_eigenvalue_function`)."""
    import casadi

    ops = Operations(select=casadi.if_else, both=casadi.logic_and, either=casadi.logic_or,
                     negate=casadi.logic_not, minimum=casadi.fmin, maximum=casadi.fmax,
                     absolute=casadi.fabs, sqrt=casadi.sqrt)
    if not shifting:
        return ops

    def lowest_eigenvalue(matrix: list[list[Any]]) -> Any:
        entries = casadi.vertcat(*(entry for row in matrix for entry in row))
        return lowest_eigenvalue_function(len(matrix))(entries)

    return replace(ops, lowest_eigenvalue=lowest_eigenvalue)


@cache
def lowest_eigenvalue_function(size: int) -> Any:
    """``entries -> lowest eigenvalue`` of a ``size`` x ``size`` symmetric matrix that is not
    positive definite (its entries row by row), by the rules' bisection
    (:func:`sso._solvers.lm_rules.eigenvalue_bracket`, then
    :data:`sso._solvers.lm_rules.EIGENVALUE_HALVINGS` times
    :func:`sso._solvers.lm_rules.halve_eigenvalue_bracket`).

    The halvings are one SX function folded into a loop, and the function is never
    inlined: a kernel that calls it holds one call instruction, not the halvings'
    Cholesky factors unrolled (which made its build, and a compiler's, many times longer).
    """
    import casadi

    ops = casadi_operations()
    entries = casadi.SX.sym("matrix", size * size)
    matrix = [[entries[row * size + column] for column in range(size)] for row in range(size)]
    bracket = casadi.SX.sym("bracket", 2)
    halved = halve_eigenvalue_bracket(ops, matrix, bracket[0], bracket[1])
    halve = casadi.Function("lm_halve_bracket", [bracket, entries], [casadi.vertcat(*halved)])
    start = casadi.Function("lm_eigenvalue_bracket", [entries],
                            [casadi.vertcat(*eigenvalue_bracket(ops, matrix))])
    given = casadi.MX.sym("matrix", size * size)
    found = halve.fold(EIGENVALUE_HALVINGS)(start(given),
                                             casadi.repmat(given, 1, EIGENVALUE_HALVINGS))
    return casadi.Function(f"lm_lowest_eigenvalue_{size}", [given], [-found[1]],
                           {"never_inline": True})


def pack(state: Mapping[str, Any]) -> list[Any]:
    """A state as one flat list: ``x``, ``r1, r2``, ``dr1/dx_i, dr2/dx_i`` for each ``i``,
    then :data:`sso._solvers.lm_rules.SCALARS`."""
    jacobian = [entry for pair in zip(state["J1"], state["J2"], strict=True) for entry in pair]
    return [*state["x"], state["r1"], state["r2"], *jacobian,
            *(state[name] for name in SCALARS)]


def unpack(values: list[Any], size: int) -> dict[str, Any]:
    """The state of :func:`pack`'s flat list, for ``size`` variables."""
    jacobian = values[size + 2:3 * size + 2]
    state: dict[str, Any] = dict(zip(SCALARS, values[3 * size + 2:], strict=True))
    state.update(x=values[:size], r1=values[size], r2=values[size + 1], J1=jacobian[0::2],
                 J2=jacobian[1::2])
    return state


def run_newton_kernel(kernels: NewtonKernels, state: dict[str, Any],
                      parameters: list[float], lower: list[float], upper: list[float],
                      tolerance: float, max_iterations: int) -> dict[str, Any]:
    """Blocks of the Newton kernel from ``state`` (status
    :data:`sso._solvers.lm_rules.NEWTON` or
    :data:`sso._solvers.lm_rules.NEWTON_INDEFINITE`), a Hessian that the damping leaves
    indefinite shifted by the compiled step, until the solve ends; a state the shifted
    step still hands back (round-off beyond its rescue shifts) is returned with status
    ``NEWTON_INDEFINITE``."""
    size = len(lower)
    problem = [*parameters, *lower, *upper, tolerance, float(max_iterations)]
    values = pack(state)
    status_index = 3 * size + 2 + _STATUS
    while values[status_index] in (NEWTON, NEWTON_INDEFINITE):
        if values[status_index] == NEWTON:
            values = kernels.blocks.flat(values, problem)
            continue
        values[status_index] = float(NEWTON)
        values = kernels.shifted.flat(values, problem)
        if values[status_index] == NEWTON_INDEFINITE:
            break
    return unpack(values, size)


def run_kernel(kernel: BufferedFunction, start: list[float], parameters: list[float],
               lower: list[float], upper: list[float], tolerance: float,
               max_iterations: int) -> dict[str, Any]:
    """Blocks of the kernel from ``start`` (clipped onto the bounds) until the solve ends or
    is handed to the Python loop; returns the rules' state there (plain floats)."""
    return unpack(run_kernel_flat(kernel, start, parameters, lower, upper, tolerance,
                                  max_iterations), len(start))


def run_kernel_flat(kernel: BufferedFunction, start: list[float], parameters: list[float],
                    lower: list[float], upper: list[float], tolerance: float,
                    max_iterations: int) -> list[float]:
    """:func:`run_kernel`'s state as the flat list of :func:`pack` (read with
    :func:`flat_outcome` or :func:`unpack`)."""
    size = len(start)
    problem = [*parameters, *lower, *upper, tolerance, float(max_iterations)]
    values = kernel.flat(start + [0.0] * (2 * size + 2 + len(SCALARS)), problem)
    status_index = 3 * size + 2 + _STATUS
    while values[status_index] == RUNNING:  # each block takes KERNEL_ITERATIONS more steps
        values = kernel.flat(values, problem)
    return values


def flat_outcome(values: list[float], size: int) -> tuple[list[float], float, int, int, int]:
    """``x``, ``fun``, ``nit``, ``nfev`` and ``status`` of a flat state of ``size`` variables."""
    scalars = 3 * size + 2
    return (values[:size], values[scalars + _FUN], int(values[scalars + _NIT]),
            int(values[scalars + _NFEV]), int(values[scalars + _STATUS]))


_FUN, _NIT, _NFEV, _STATUS = (SCALARS.index(name) for name in ("fun", "nit", "nfev", "status"))
