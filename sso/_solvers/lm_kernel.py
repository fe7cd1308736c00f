"""The ``"lm"`` solver's rules as CasADi functions of one shape, run for one design or many.

The rules (:mod:`sso._solvers.lm_rules`) are evaluated once on CasADi symbols: one
Gauss-Newton iteration and one Newton iteration are each an SX function (a flat
instruction list). A block folds :data:`GAUSS_NEWTON_ITERATIONS` (or
:data:`NEWTON_ITERATIONS`) of them: CasADi's virtual machine runs the block's
instructions in about the time Python takes for one iteration. A state that is not in
the block's mode passes through it unchanged (every branch is an ``if_else`` selection),
so a design that ended inside a block is frozen exactly.

The driver (:func:`solve_one`, :func:`solve_states`) runs Gauss-Newton blocks while a
design's status is :data:`sso._solvers.lm_rules.RUNNING`, then Newton blocks while it is
:data:`sso._solvers.lm_rules.NEWTON`. One design runs the functions themselves; many
designs run the same functions through ``Function.map`` (CasADi calls the same
instruction list once per column), so a design's answer is bit for bit the one it gets
alone, whichever designs are beside it and whatever ran before in the process. Nothing
depends on a count of calls: a block is built when a design first needs it, which
changes no design's arithmetic.

A Newton iteration whose damped Hessian is not positive definite leaves the state with
status :data:`sso._solvers.lm_rules.NEWTON_INDEFINITE`; the driver hands it to the
shifted Newton iteration, which shifts the Hessian past its most negative eigenvalue,
found by bisection (:data:`sso._solvers.lm_rules.EIGENVALUE_HALVINGS` Cholesky
factors, one never-inlined function): those instructions are spent only on such a step
(at 11 variables they are most of a Newton iteration's). A shift that round-off still
leaves indefinite after its rescue shifts ends the design with that status (a failure).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import replace
from functools import cache
from typing import Any

import numpy as np

from sso._interrupts import raised_after_native_call
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

# casadi is imported inside the functions that build: this module is imported with
# sso._solvers.lm, which a mechanism's analysis loads (through the column and the
# shafts' exact optima) without solving; it loads no CasADi
# (tests/cli/test_start_up_imports.py).

GAUSS_NEWTON_ITERATIONS = 6
"""Gauss-Newton iterations folded into one block. Most exact-model solves of 3 to 6
joints take 4 or 5 steps and the final test, which one block of 6 holds (the paper's
option 3: 4 steps); an iteration after the end still costs its instructions."""

NEWTON_ITERATIONS = 4
"""Newton iterations folded into one block."""

SHIFTED_ITERATIONS = 4
"""Shifted Newton iterations folded into one block. A design handed to it is near a
saddle, where the next Hessian is often indefinite too (a Newton block that hands it
back at once costs a block for no step): ``sso.optimise_batch`` of 2,000 random
option-3 designs of 3 joints took 0.22 s of CPU with blocks of 1, 0.19 s with 2 and
0.17 s with 4 (best of 3 each, in one run)."""

NEWTON_BLOCK_VARIABLES = 12
"""A shape's Newton block is built for at most this many variables (6 joints of option 3
have 11). Its Hessian and Cholesky factors are made of scalar symbols in Python, a cost
that grows with the cube of the variables (measured, its build: 0.15 s at 11 variables,
0.41 s at 15, 2.2 s at 29, 13.6 s at 59); a larger shape takes its Newton steps by the
same rules on plain floats (:func:`sso._solvers.lm.newton_on_floats`), one design at a
time, in the single solve and the batch alike."""

MAP_COLUMNS = (1, 8, 64, 512)
"""Column counts of the mapped blocks a batch is run through: each call takes up to the
largest, and a part smaller than a count is padded with copies of its last design."""

FUN, NIT, NFEV, STATUS = (SCALARS.index(name) for name in ("fun", "nit", "nfev", "status"))
"""Places of these numbers among a state's scalars (after ``x``, ``r`` and ``J``)."""


class ShapeKernels:
    """The blocks of one shape, built on first use and kept (on the shape's NLP).

    Parameters
    ----------
    x, p : casadi.SX
        Design variables and fixed parameters (column vectors).
    residual : casadi.SX
        The two residuals (a 2-vector) as an expression of ``x`` and ``p``.
    """

    def __init__(self, x: Any, p: Any, residual: Any) -> None:
        self.size = int(x.numel())
        self.state_size = 3 * self.size + 2 + len(SCALARS)
        self.problem_size = int(p.numel()) + 2 * self.size + 2
        self._symbols = (x, p, residual)
        self._functions: dict[str, Any] = {}
        self._buffered: dict[tuple[str, int], BufferedFunction] = {}

    def function(self, mode: str) -> Any:
        """The block of ``mode`` (one of :data:`MODES`): ``(state, problem) -> state``, with a
        state of :func:`pack` and the problem of :func:`problem_vector`.

        Each block is built when a design of the shape first needs it: the Gauss-Newton
        block at the shape's first call (10 to 25 ms at 5 to 15 variables), the Newton
        block at its first Newton step (about 40 ms at 11 variables), the shifted block
        at its first indefinite Hessian (about 110 ms at 11 variables, half of it the
        eigenvalue bisection's): a shape whose designs reach zero never pays the Newton
        blocks, and one whose Hessians stay positive definite never pays the shifted one.
        The arithmetic is the same whenever they are built."""
        if mode not in self._functions:
            # CasADi's bindings discard what a signal handler raises while a graph is
            # built (a SIGTERM then went unanswered): raised again after the build
            with raised_after_native_call():
                self._functions[mode] = build_block(*self._symbols, mode)
        return self._functions[mode]

    def buffered(self, mode: str, columns: int) -> BufferedFunction:
        """The block of ``mode`` on ``columns`` designs at once (one of :data:`MAP_COLUMNS`)."""
        key = (mode, columns)
        if key not in self._buffered:
            block = self.function(mode)
            self._buffered[key] = BufferedFunction(block if columns == 1
                                                   else block.map(columns, "serial"))
        return self._buffered[key]


def kernels_of(nlp: Any) -> ShapeKernels | None:
    """The NLP's blocks, kept on it; None for a problem without a residual expression.

    Parameters
    ----------
    nlp : sso._solvers.nlp.CompiledNLP
    """
    if nlp.lm_kernel is None and nlp.residuals is not None:
        nlp.lm_kernel = ShapeKernels(nlp.symbols["x"], nlp.symbols["p"], nlp.residuals)
    kernels: ShapeKernels | None = nlp.lm_kernel
    return kernels


MODES = ("gauss_newton", "newton", "shifted")
"""The iterations a block can fold: Gauss-Newton, Newton (handing back a Hessian that its
damping leaves indefinite), and Newton shifted past the most negative eigenvalue."""


def build_block(x: Any, p: Any, residual: Any, mode: str) -> Any:
    """One block of ``mode`` for residuals ``residual(x, p)``, as a CasADi function.

    The Gauss-Newton block starts with the start (a state with ``nfev = 0`` has ``x``
    moved onto the bounds and evaluated there), then folds
    :data:`GAUSS_NEWTON_ITERATIONS` iterations; the Newton block folds
    :data:`NEWTON_ITERATIONS` Newton iterations with CasADi's symbolic Hessian of the
    sum of squares; the shifted block folds :data:`SHIFTED_ITERATIONS` Newton iterations
    shifted past the most negative eigenvalue where the Hessian is indefinite. Each
    iteration is one SX function; the fold calls it in turn.

    Raises
    ------
    ValueError
        If ``mode`` is not one of :data:`MODES`.
    """
    import casadi

    start, iteration = iteration_functions(x, p, residual, mode)
    state = casadi.MX.sym("state", iteration.numel_in(0))
    problem = casadi.MX.sym("problem", iteration.numel_in(1))
    chain = {"gauss_newton": GAUSS_NEWTON_ITERATIONS, "newton": NEWTON_ITERATIONS,
             "shifted": SHIFTED_ITERATIONS}[mode]
    first = state if start is None else start(state, problem)
    # fold calls the iteration ``chain`` times and gives the last state.
    folded = iteration.fold(chain)(first, casadi.repmat(problem, 1, chain))
    return casadi.Function(f"lm_{mode}", [state, problem], [folded])


def iteration_functions(x: Any, p: Any, residual: Any, mode: str) -> tuple[Any, Any]:
    """The start (None but for ``"gauss_newton"``) and one iteration of ``mode`` as SX functions
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
        start = None
    else:
        after = gauss_newton_iteration(ops, evaluate, given, lower_list, upper_list,
                                       settings[0], settings[1])
        fresh = fresh_state(ops, evaluate, given["x"], lower_list, upper_list)
        is_fresh = given["nfev"] == 0
        start = casadi.Function(
            "lm_start", [state_in, problem_in],
            [casadi.vertcat(*(casadi.if_else(is_fresh, new, old) for new, old in
                              zip(pack(fresh), pack(given), strict=True)))], {"cse": True})
    # Common subexpressions merged save 6 % of a Newton iteration's instructions and cost
    # half its build (measured at 11 variables): the Newton iteration keeps them.
    iteration = casadi.Function(f"lm_{mode}_iteration", [state_in, problem_in],
                                [casadi.vertcat(*pack(after))], {"cse": mode == "gauss_newton"})
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
    :func:`sso._solvers.lm_rules.halve_eigenvalue_bracket`), one never-inlined function."""
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
    # The fold expanded into one instruction list: evaluated step by step as MX, each
    # halving cost a function call's overhead, more than its arithmetic.
    folded = casadi.Function("lm_lowest_eigenvalue", [given], [-found[1]]).expand()
    symbols = casadi.SX.sym("matrix", size * size)
    return casadi.Function(f"lm_lowest_eigenvalue_{size}", [symbols], [folded(symbols)],
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


def problem_vector(parameters: list[float], lower: list[float], upper: list[float],
                   tolerance: float, max_iterations: float) -> list[float]:
    """The problem input of a block: the fixed parameters, the bounds, the projected-gradient
    tolerance and the iteration limit."""
    return [*parameters, *lower, *upper, tolerance, float(max_iterations)]


def solve_one(kernels: ShapeKernels, start: list[float], problem: list[float],
              newton: bool = True) -> list[float]:
    """One design from ``start`` to its end (the flat state of :func:`pack`): Gauss-Newton
    blocks while it runs, then Newton blocks while it takes Newton steps (without
    ``newton``, or beyond :data:`NEWTON_BLOCK_VARIABLES`, a design whose steps turn to
    Newton steps ends with status :data:`sso._solvers.lm_rules.NEWTON`)."""
    size = kernels.size
    status = 3 * size + 2 + STATUS
    values = kernels.buffered("gauss_newton", 1).flat(
        start + [0.0] * (kernels.state_size - size), problem)
    while values[status] == RUNNING:
        values = kernels.buffered("gauss_newton", 1).flat(values, problem)
    if not newton or kernels.size > NEWTON_BLOCK_VARIABLES:
        return values
    while values[status] in (NEWTON, NEWTON_INDEFINITE):
        if values[status] == NEWTON:
            values = kernels.buffered("newton", 1).flat(values, problem)
            continue
        values[status] = float(NEWTON)
        values = kernels.buffered("shifted", 1).flat(values, problem)
        if values[status] == NEWTON_INDEFINITE:  # round-off beyond the rescue shifts
            break
    return values


def solve_states(kernels: ShapeKernels, starts: np.ndarray, problems: np.ndarray) -> np.ndarray:
    """Every design from its start (a row of ``starts``) with its problem (a row of
    ``problems``) to its end, as :func:`solve_one` ends it, bit for bit; the states, one row
    per design."""
    count, size = starts.shape
    states = np.zeros((count, kernels.state_size))
    states[:, :size] = starts
    status = 3 * size + 2 + STATUS
    rows = np.arange(count)
    while rows.size:
        states[rows] = _run_mapped(kernels, "gauss_newton", states[rows], problems[rows])
        rows = rows[states[rows, status] == RUNNING]
    if size > NEWTON_BLOCK_VARIABLES:
        return states
    rows = np.flatnonzero(states[:, status] == NEWTON)
    while rows.size:
        states[rows] = _run_mapped(kernels, "newton", states[rows], problems[rows])
        handed = rows[states[rows, status] == NEWTON_INDEFINITE]
        if handed.size:
            states[handed, status] = NEWTON
            states[handed] = _run_mapped(kernels, "shifted", states[handed], problems[handed])
        rows = rows[states[rows, status] == NEWTON]
    return states


def _run_mapped(kernels: ShapeKernels, mode: str, states: np.ndarray, problems: np.ndarray
                ) -> np.ndarray:
    """One block of ``mode`` for each row, through the mapped blocks of :data:`MAP_COLUMNS`."""
    out = np.empty_like(states)
    count = len(states)
    first = 0
    while first < count:
        columns = next((size for size in MAP_COLUMNS if size >= count - first), MAP_COLUMNS[-1])
        part = slice(first, min(first + columns, count))
        taken = part.stop - part.start
        block = kernels.buffered(mode, columns)
        given_states, given_problems = block.inputs
        # CasADi stores a matrix column by column: one design's state is one column.
        given_states.reshape(columns, -1)[:taken] = states[part]
        given_states.reshape(columns, -1)[taken:] = states[part.stop - 1]
        given_problems.reshape(columns, -1)[:taken] = problems[part]
        given_problems.reshape(columns, -1)[taken:] = problems[part.stop - 1]
        block.evaluate()
        out[part] = block.outputs[0].reshape(columns, -1)[:taken]
        first = part.stop
    return out


def outcome(values: Any, size: int) -> tuple[list[float], float, int, int, int]:
    """``x``, ``fun``, ``nit``, ``nfev`` and ``status`` of a flat state of ``size`` variables."""
    scalars = 3 * size + 2
    return (list(values[:size]), float(values[scalars + FUN]), int(values[scalars + NIT]),
            int(values[scalars + NFEV]), int(values[scalars + STATUS]))


def gradient_of(values: Any, size: int) -> list[float]:
    """``2 J^T r`` of a flat state (plain floats, in the order numpy's columns take them)."""
    r1, r2 = float(values[size]), float(values[size + 1])
    return [2.0 * (float(values[size + 2 + 2 * i]) * r1 + float(values[size + 3 + 2 * i]) * r2)
            for i in range(size)]
