"""The step rules of the ``"lm"`` solver, written once for every way it runs.

One Gauss-Newton iteration of the bounded Levenberg-Marquardt on two residuals
(:mod:`sso._solvers.lm`): the stopping tests, the projected damped step over the
free variables by the push-through identity (one 2x2 solve whatever the number of
variables), the acceptance test and the damping rules. It is written on lists of
per-variable scalars with every branch a selection, so the same function builds the
shape's CasADi functions (:mod:`sso._solvers.lm_kernel`) and runs one design in plain
Python floats (:func:`sso._solvers.lm.minimise`). What differs between them is only the
arithmetic that :class:`Operations` names.

A state is a dict of scalars and lists: ``x`` (the design vector), ``r1``, ``r2``
(the residuals), ``J1``, ``J2`` (their derivatives, one per variable) and the
loop's numbers named in :data:`SCALARS`. A state whose ``status`` is not
:data:`RUNNING` passes through an iteration unchanged.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from functools import reduce
from types import MappingProxyType
from typing import Any

import numpy as np

RUNNING = 10
"""Status of a solve still under way."""
NEWTON = 11
"""Status of a solve whose Gauss-Newton steps converge only linearly (a minimum above
zero): it continues with Newton steps."""

NEWTON_INDEFINITE = 12
"""Status of a Newton step whose shifted Hessian is not positive definite, on a backend
that cannot shift it further: the iteration was not taken."""

SCALARS = ("fun", "nit", "nfev", "status", "damping", "growth", "slow_steps", "previous_norm",
           "first_size", "hessian_counted")
"""The loop's numbers in a state, besides the design vector, residuals and Jacobian."""

ACCEPT_RATIO = 1e-4
INITIAL_DAMPING = 1e-3
MAX_DAMPING = 1e16
ZERO_RESIDUAL = 1e-30
ROUND_OFF = 4.0 * 2.0**-52
SLOW_LEVEL = 1e-20
SLOW_STEPS = 3
NEWTON_DAMPING = 1e-8

CONSTANTS: Mapping[str, float] = MappingProxyType({
    "accept_ratio": ACCEPT_RATIO, "initial_damping": INITIAL_DAMPING,
    "max_damping": MAX_DAMPING, "zero_residual": ZERO_RESIDUAL, "round_off": ROUND_OFF,
    "slow_level": SLOW_LEVEL, "slow_steps": SLOW_STEPS})
"""The rules' constants by name."""

Evaluate = Callable[[list[Any]], tuple[Any, Any, list[Any], list[Any]]]
"""``point -> (r1, r2, J1, J2)``: the residuals and their derivatives at a point."""


@dataclass(frozen=True)
class Operations:
    """The arithmetic an iteration needs beyond ``+ - * /`` and comparisons.

    Attributes
    ----------
    select : callable
        ``(condition, if_true, if_false)``, elementwise.
    both, either : callable
        Logical and / or of two conditions.
    negate : callable
        Logical not of a condition.
    minimum, maximum : callable
        Of two values, elementwise.
    absolute, sqrt : callable
    lazy : bool
        Conditions are plain booleans (one design): a loop may run until its condition
        holds, where arrays and symbols take a fixed number of rounds.
    lowest_eigenvalue : callable or None
        The most negative eigenvalue of a symmetric matrix (a list of lists), for the
        Newton step's shift past it; None where the backend has no eigenvalue solver.
    anywhere : callable
        Whether a condition may hold for some design (always True for symbols), so a
        branch that no design takes is not computed.
    """

    select: Callable[[Any, Any, Any], Any]
    both: Callable[[Any, Any], Any]
    either: Callable[[Any, Any], Any]
    negate: Callable[[Any], Any]
    minimum: Callable[[Any, Any], Any]
    maximum: Callable[[Any, Any], Any]
    absolute: Callable[[Any], Any]
    sqrt: Callable[[Any], Any]
    lazy: bool = False
    lowest_eigenvalue: Callable[[list[list[Any]]], Any] | None = None
    anywhere: Callable[[Any], bool] = lambda condition: True

    def largest(self, values: Sequence[Any]) -> Any:
        """The largest of a non-empty list, elementwise."""
        return reduce(self.maximum, values)

    def select_each(self, condition: Any, if_true: list[Any], if_false: list[Any]) -> list[Any]:
        """``select`` of two lists (or lists of lists) under one condition; on plain
        booleans one choice, not one per entry."""
        if self.lazy:
            return if_true if condition else if_false
        return [self.select_each(condition, first, second) if isinstance(first, list)
                else self.select(condition, first, second)
                for first, second in zip(if_true, if_false, strict=True)]

    def clip(self, value: Any, low: Any, high: Any) -> Any:
        """``value`` moved onto ``[low, high]``."""
        return self.minimum(self.maximum(value, low), high)


def _python_select(condition: Any, if_true: Any, if_false: Any) -> Any:
    return if_true if condition else if_false


def _python_minimum(first: float, second: float) -> float:
    return first if first < second else second


def _python_maximum(first: float, second: float) -> float:
    return first if first > second else second


def _python_lowest_eigenvalue(matrix: list[list[float]]) -> float:
    return float(np.linalg.eigvalsh(np.array(matrix))[0])


PYTHON = Operations(
    select=_python_select, both=operator.and_, either=operator.or_, negate=operator.not_,
    minimum=_python_minimum, maximum=_python_maximum, absolute=abs, sqrt=math.sqrt,
    lazy=True, lowest_eigenvalue=_python_lowest_eigenvalue, anywhere=bool)
"""The operations on plain Python floats (one design)."""


def fresh_state(ops: Operations, evaluate: Evaluate, start: list[Any], lower: list[Any],
                upper: list[Any]) -> dict[str, Any]:
    """The state at ``start`` moved onto the bounds: evaluated there, nothing taken yet."""
    x = [ops.clip(value, low, high) for value, low, high in zip(start, lower, upper, strict=True)]
    r1, r2, first, second = evaluate(x)
    fun = r1 * r1 + r2 * r2
    return {"x": x, "r1": r1, "r2": r2, "J1": first, "J2": second, "fun": fun, "nit": 0,
            "nfev": 1, "status": RUNNING, "damping": INITIAL_DAMPING, "growth": 2.0,
            "slow_steps": 0, "previous_norm": math.inf,
            "first_size": ops.maximum(ops.sqrt(fun), 1e-300), "hessian_counted": 0}


def gauss_newton_iteration(ops: Operations, evaluate: Evaluate, state: Mapping[str, Any],
                           lower: list[Any], upper: list[Any], tolerance: Any,
                           max_iterations: Any) -> dict[str, Any]:
    """One iteration of the Gauss-Newton mode: the tests at the top, one trial step.

    The tests in order: the iteration limit (status 0), a residual or Jacobian
    that is not finite (-2), the projected gradient at most ``tolerance`` (1),
    the sum of squares at round-off zero (4). Then the damped Gauss-Newton step
    over the free variables (off their bounds, or pulled inwards), projected onto
    the bounds: a move at round-off ends the solve (3); a trial point is
    accepted when it achieves at least :data:`ACCEPT_RATIO` of the decrease the
    linear model predicts; actual and predicted decreases both at round-off end it
    (2); a damping past :data:`MAX_DAMPING` fails it (-1); :data:`SLOW_STEPS`
    accepted steps that did not halve the projected gradient at a sum of squares
    above :data:`SLOW_LEVEL` turn it to Newton steps (:data:`NEWTON`).

    Parameters
    ----------
    ops : Operations
    evaluate : callable
        ``point -> (r1, r2, J1, J2)``.
    state : mapping
        As the module describes; it passes unchanged unless its status is
        :data:`RUNNING`.
    lower, upper : list
        Bounds of each variable.
    tolerance, max_iterations
        The projected-gradient tolerance (infinity norm, per unit of ``x``) and the
        iteration limit.
    """
    status, _, norm, free = top_of_iteration(ops, state, RUNNING, lower, upper, tolerance,
                                             max_iterations)
    select = ops.select
    r1, r2, fun = state["r1"], state["r2"], state["fun"]
    first = [select(is_free, d1, 0.0) for is_free, d1 in zip(free, state["J1"], strict=True)]
    second = [select(is_free, d2, 0.0) for is_free, d2 in zip(free, state["J2"], strict=True)]
    # -J^T (J J^T + mu I)^-1 r over the free variables. mu = damping * trace / 2, scaled
    # by |r| / |r_0| once the residual has fallen: damping in proportion to |r| keeps
    # the convergence to a zero residual quadratic (Fan and Yuan), where a damping
    # that only shrinks by 1/3 a step makes the last steps linear.
    a11 = sum(d1 * d1 for d1 in first)
    a12 = sum(d1 * d2 for d1, d2 in zip(first, second, strict=True))
    a22 = sum(d2 * d2 for d2 in second)
    mu = (state["damping"] * ops.maximum(0.5 * (a11 + a22), 1e-30)
          * ops.minimum(1.0, ops.sqrt(fun) / state["first_size"]))
    a11, a22 = a11 + mu, a22 + mu
    # floored so a start at zero residual with J J^T singular (its damping zero) divides
    # by no zero on plain floats; above the floor the bits are those of the product
    determinant = ops.maximum(a11 * a22 - a12 * a12, 1e-300)
    y1 = (a22 * r1 - a12 * r2) / determinant
    y2 = (a11 * r2 - a12 * r1) / determinant
    step = [-(d1 * y1 + d2 * y2) for d1, d2 in zip(first, second, strict=True)]
    return trial_step(ops, evaluate, state, RUNNING, status, norm, step, None, lower, upper)[0]


def top_of_iteration(ops: Operations, state: Mapping[str, Any], mode: int, lower: list[Any],
                     upper: list[Any], tolerance: Any, max_iterations: Any
                     ) -> tuple[Any, list[Any], Any, list[Any]]:
    """The tests at the top of an iteration, and what the step needs.

    Returns
    -------
    status
        The state's status after the tests (``mode`` where the solve goes on).
    gradient : list
        ``2 J^T r``.
    norm
        The projected gradient's infinity norm, ``|x - clip(x - gradient)|``.
    free : list
        Whether each variable takes part in the step: off its bounds, or pulled
        inwards, and not pinned by equal bounds.
    """
    select, both, negate = ops.select, ops.both, ops.negate
    x, r1, r2, first, second = state["x"], state["r1"], state["r2"], state["J1"], state["J2"]
    fun, status, nit = state["fun"], state["status"], state["nit"]
    running = status == mode
    status = select(both(running, nit >= max_iterations), 0, status)
    running = status == mode
    total = fun + sum(ops.absolute(entry) for entry in first) + sum(
        ops.absolute(entry) for entry in second)
    finite = both(total == total, ops.absolute(total) < math.inf)
    status = select(both(running, negate(finite)), -2, status)
    running = status == mode
    gradient = [2.0 * (d1 * r1 + d2 * r2) for d1, d2 in zip(first, second, strict=True)]
    norm = ops.largest([ops.absolute(value - ops.clip(value - slope, low, high))
                        for value, slope, low, high in zip(x, gradient, lower, upper,
                                                            strict=True)])
    status = select(both(running, norm <= tolerance), 1, status)
    running = status == mode
    status = select(both(running, fun <= ZERO_RESIDUAL), 4, status)
    free = [both(high > low, negate(ops.either(both(value <= low, slope > 0.0),
                                               both(value >= high, slope < 0.0))))
            for value, slope, low, high in zip(x, gradient, lower, upper, strict=True)]
    return status, gradient, norm, free


def trial_step(ops: Operations, evaluate: Evaluate, state: Mapping[str, Any], mode: int,
               status: Any, norm: Any, step: list[Any], predicted: Any, lower: list[Any],
               upper: list[Any]) -> tuple[dict[str, Any], Any]:
    """The projected trial point of ``step``, its test, the state after it and whether it
    moved there.

    Parameters
    ----------
    mode : {RUNNING, NEWTON}
        The solve's mode: a status of ``mode`` goes on in it.
    status, norm
        From :func:`top_of_iteration`.
    step : list
        The step before its projection onto the bounds.
    predicted
        The decrease the step's model predicts, or None for the linear model's
        (Gauss-Newton) for the projected step.
    """
    select, both, negate = ops.select, ops.both, ops.negate
    x, r1, r2, first, second = state["x"], state["r1"], state["r2"], state["J1"], state["J2"]
    fun, nit, nfev = state["fun"], state["nit"], state["nfev"]
    damping, growth = state["damping"], state["growth"]
    running = status == mode
    trial = [ops.clip(value + change, low, high)
             for value, change, low, high in zip(x, step, lower, upper, strict=True)]
    move = [moved - value for moved, value in zip(trial, x, strict=True)]
    # A NaN step component counts for no move and makes the step rejected (a clip
    # that drops NaN would put it onto a bound).
    finite = [change == change for change in step]
    all_finite = reduce(both, finite)
    largest_move = ops.largest([select(is_finite, ops.absolute(change), 0.0)
                                for is_finite, change in zip(finite, move, strict=True)])
    largest_value = ops.largest([ops.absolute(value) for value in x])
    status = select(both(running, largest_move <= ROUND_OFF * (1.0 + largest_value)), 3, status)
    running = status == mode
    if predicted is None:
        # The linear model's decrease for the projected step actually taken.
        model1 = r1 + sum(d1 * change for d1, change in zip(first, move, strict=True))
        model2 = r2 + sum(d2 * change for d2, change in zip(second, move, strict=True))
        predicted = fun - (model1 * model1 + model2 * model2)
    if not ops.anywhere(running):
        trial_r1, trial_r2, trial_first, trial_second = r1, r2, first, second
    else:
        trial_r1, trial_r2, trial_first, trial_second = evaluate(trial)
    trial_fun = trial_r1 * trial_r1 + trial_r2 * trial_r2
    actual = fun - trial_fun
    accept = both(all_finite, both(predicted > 0.0, actual >= ACCEPT_RATIO * predicted))
    negligible = both(all_finite, both(ops.absolute(actual) <= ROUND_OFF * fun,
                                       predicted <= ROUND_OFF * fun))
    # Nielsen's rule. A ratio past 2 shrinks by 1/3 as 2 does; capping it keeps the cube
    # finite, and a divisor of 1 where the step is rejected keeps the quotient defined.
    ratio = ops.minimum(actual / select(predicted > 0.0, predicted, 1.0), 2.0)
    accepted_damping = damping * ops.maximum(1.0 / 3.0, 1.0 - (2.0 * ratio - 1.0) ** 3)
    # Gauss-Newton is only linear at a nonzero residual: take Newton steps once the
    # projected gradient has fallen by less than half in SLOW_STEPS accepted steps.
    slow = both(trial_fun > SLOW_LEVEL, norm > 0.5 * state["previous_norm"])
    slow_steps = state["slow_steps"] + select(slow, 1, 0)
    accepted_status = select(negligible, 2, select(slow_steps >= SLOW_STEPS, NEWTON, mode))
    if mode == RUNNING:
        # Plain Newton first (shifted only to be positive definite), so convergence is
        # quadratic; damping returns on a rejected step.
        accepted_damping = select(accepted_status == NEWTON, 0.0, accepted_damping)
    rejected_damping = damping * growth
    if mode == NEWTON:
        rejected_damping = ops.maximum(rejected_damping, NEWTON_DAMPING)
    rejected_status = select(negligible, 2, select(rejected_damping > MAX_DAMPING, -1, mode))
    moves = both(running, accept)
    stays = both(running, negate(accept))

    def kept(on_accept: Any, unchanged: Any) -> Any:
        return select(moves, on_accept, unchanged)

    return {
        "x": ops.select_each(moves, trial, x),
        "r1": kept(trial_r1, r1), "r2": kept(trial_r2, r2),
        "J1": ops.select_each(moves, trial_first, first),
        "J2": ops.select_each(moves, trial_second, second),
        "fun": kept(trial_fun, fun),
        "nit": nit + select(running, 1, 0),
        "nfev": nfev + select(running, 1, 0),
        "status": select(running, select(accept, accepted_status, rejected_status), status),
        "damping": select(moves, accepted_damping, select(stays, rejected_damping, damping)),
        "growth": select(moves, 2.0, select(stays, 2.0 * growth, growth)),
        "slow_steps": kept(slow_steps, state["slow_steps"]),
        "previous_norm": kept(norm, state["previous_norm"]),
        "first_size": state["first_size"],
        "hessian_counted": kept(0, state["hessian_counted"]),
    }, moves


HessianAt = Callable[[list[Any], list[Any], list[Any], Any], tuple[list[list[Any]], Any]]
"""``(point, gradient, free, needed) -> (hessian, evaluations)``: the Hessian of
``r1^2 + r2^2`` at ``point`` (every variable; only the free ones' block is read) and
the residual evaluations it costs. ``needed`` tells whether the iteration uses it (a
backend that computes it lazily may skip it when it does not)."""

RESCUE_SHIFTS = 4
"""Tenfold shifts tried after the shift past the most negative eigenvalue, where round-off
keeps the shifted Hessian from being positive definite (on plain floats the loop goes
on until it is)."""


def newton_iteration(ops: Operations, evaluate: Evaluate, hessian_at: HessianAt,
                     state: Mapping[str, Any], lower: list[Any], upper: list[Any],
                     tolerance: Any, max_iterations: Any) -> dict[str, Any]:
    """One iteration of the Newton mode: the tests at the top, one damped Newton step.

    The tests are those of :func:`gauss_newton_iteration`. The step solves
    ``(H + shift I) d = -g`` over the free variables with the Hessian ``H`` of the sum
    of squares, ``shift = damping * max |H_ij|``; the damping starts at 0 (plain
    Newton, quadratic convergence), is raised on a rejected step (at least to
    :data:`NEWTON_DAMPING`) and shrinks on an accepted one as in the Gauss-Newton
    mode. The model's decrease is that of the quadratic ``g.d + d.H.d / 2``. A
    Hessian with an entry that is not finite gives no step (the solve ends with
    status 3). Where the shifted Hessian is not positive definite (near a saddle) the
    shift goes just past its most negative eigenvalue, so the step is long along the
    direction of negative curvature (Moré and Sorensen), plus ``max(damping,
    NEWTON_DAMPING) * max |H_ij|``; then tenfold while round-off keeps it indefinite.
    A backend without an eigenvalue solver, or whose tenfold shifts run out
    (:data:`RESCUE_SHIFTS`), leaves the state as it was with status
    :data:`NEWTON_INDEFINITE`.

    The Hessian is counted as ``evaluations`` once per point: ``hessian_counted`` in
    the state says it was counted at ``x`` (a rejected step keeps ``x``).
    """
    select, both, either, negate = ops.select, ops.both, ops.either, ops.negate
    status, gradient, norm, free = top_of_iteration(ops, state, NEWTON, lower, upper,
                                                    tolerance, max_iterations)
    running = status == NEWTON
    size = len(gradient)
    damping = state["damping"]
    hessian, evaluations = hessian_at(state["x"], gradient, free, running)
    pair = [[both(free[row], free[column]) for column in range(size)] for row in range(size)]
    magnitudes = [select(pair[row][column], ops.absolute(hessian[row][column]), 0.0)
                  for row in range(size) for column in range(size)]
    # Magnitudes are never negative: their sum is finite exactly when each one is.
    total = sum(magnitudes)
    finite = both(total == total, total < math.inf)
    # The free block (identity elsewhere, which takes no step), symmetrised; identity
    # where an entry is not finite, so that no factor or eigenvalue meets one.
    block = [[select(both(finite, pair[row][column]),
                     0.5 * (hessian[row][column] + hessian[column][row]),
                     1.0 if row == column else 0.0) for column in range(size)]
             for row in range(size)]
    free_gradient = [select(is_free, slope, 0.0) for is_free, slope in zip(free, gradient,
                                                                            strict=True)]
    scale = ops.maximum(ops.largest(magnitudes), 1e-30)
    factor, factored = cholesky(ops, block, damping * scale)
    lowest_eigenvalue = ops.lowest_eigenvalue
    if lowest_eigenvalue is not None and ops.anywhere(both(running, negate(factored))):
        # The padding's eigenvalues are 1; the shift is needed only where the block's
        # lowest is below -damping * scale <= 0, so the lowest is the free block's.
        shift = (1.01 * ops.maximum(-lowest_eigenvalue(block), 0.0)
                 + ops.maximum(damping, NEWTON_DAMPING) * scale)
        rescued, positive = cholesky(ops, block, shift)
        attempts = 0
        while ops.anywhere(negate(positive)) and (ops.lazy or attempts < RESCUE_SHIFTS):
            attempts += 1
            shift = select(positive, shift, ops.maximum(10.0 * shift, 1e-6 * scale))
            candidate, candidate_positive = cholesky(ops, block, shift)
            rescued = ops.select_each(positive, rescued, candidate)
            positive = either(positive, candidate_positive)
        factor = ops.select_each(factored, factor, rescued)
        factored = either(factored, positive)
    step = solve_factored(ops, factor, free_gradient)
    step = [select(finite, value, 0.0) for value in step]
    linear = sum(slope * value for slope, value in zip(free_gradient, step, strict=True))
    curvature = sum(step[row] * block[row][column] * step[column]
                    for row in range(size) for column in range(size))
    predicted = select(finite, -(linear + 0.5 * curvature), 0.0)
    handed = both(running, both(finite, negate(factored)))
    status = select(handed, NEWTON_INDEFINITE, status)
    counted = state["hessian_counted"]
    after, moved = trial_step(ops, evaluate, state, NEWTON, status, norm, step, predicted,
                              lower, upper)
    charged = both(status == NEWTON, counted == 0)
    after["nfev"] = after["nfev"] + select(charged, evaluations, 0)
    after["hessian_counted"] = select(moved, 0, select(charged, 1, counted))
    return after


EIGENVALUE_HALVINGS = 52
"""Halvings of :func:`eigenvalue_bracket` by :func:`halve_eigenvalue_bracket` that find the
most negative eigenvalue of a symmetric matrix that is not positive definite, for a
backend without an eigenvalue solver (CasADi symbols,
:func:`sso._solvers.lm_kernel.lowest_eigenvalue_function`): ``matrix + t I`` has a
Cholesky factor exactly when ``t`` exceeds minus the lowest eigenvalue, and no eigenvalue
lies below minus the largest absolute row sum (Gershgorin). The bracket starts twice as
wide as that sum, so the eigenvalue is found to about ``4.4e-16`` of it (round-off, as a
library's eigenvalue solver finds it); the least shift found with a factor is kept, so
minus it is at most the lowest eigenvalue and a shift past it gives a factor."""


def eigenvalue_bracket(ops: Operations, matrix: list[list[Any]]) -> tuple[Any, Any]:
    """Shifts ``(0, 2 * largest absolute row sum)``: between them lies minus the lowest
    eigenvalue of a matrix that is not positive definite."""
    bound = ops.largest([sum(ops.absolute(entry) for entry in row) for row in matrix])
    return 0.0 * bound, 2.0 * bound + 1e-300


def halve_eigenvalue_bracket(ops: Operations, matrix: list[list[Any]], low: Any, high: Any
                             ) -> tuple[Any, Any]:
    """The half of the bracket ``(low, high)`` of shifts that holds the least shift giving
    ``matrix`` a Cholesky factor."""
    middle = 0.5 * (low + high)
    positive = cholesky(ops, matrix, middle)[1]
    return ops.select(positive, low, middle), ops.select(positive, middle, high)


def cholesky(ops: Operations, matrix: list[list[Any]], shift: Any
             ) -> tuple[list[list[Any]], Any]:
    """Lower Cholesky factor of ``matrix + shift I`` and whether it exists (positive definite).

    Only the lower triangle of ``matrix`` is read. Where a pivot is not positive the
    factor goes on with a pivot of 1 (its entries are then meaningless).
    """
    size = len(matrix)
    factor: list[list[Any]] = [[0.0] * size for _ in range(size)]
    positive: Any = True
    for r in range(size):
        row, given = factor[r], matrix[r]
        for c in range(r):
            other = factor[c]
            total = given[c]
            for k in range(c):
                total = total - row[k] * other[k]
            row[c] = total / other[c]
        total = given[r] + shift
        for k in range(r):
            total = total - row[k] * row[k]
        pivot_positive = total > 0.0
        positive = ops.both(positive, pivot_positive)
        row[r] = ops.sqrt(ops.select(pivot_positive, total, 1.0))
    return factor, positive


def solve_factored(ops: Operations, factor: list[list[Any]], gradient: list[Any]) -> list[Any]:
    """``d`` with ``L L^T d = -gradient`` (forward, then back substitution)."""
    size = len(factor)
    forward: list[Any] = [0.0] * size
    for r in range(size):
        total = -gradient[r]
        row = factor[r]
        for c in range(r):
            total = total - row[c] * forward[c]
        forward[r] = total / row[r]
    step: list[Any] = [0.0] * size
    for r in range(size - 1, -1, -1):
        total = forward[r]
        for c in range(r + 1, size):
            total = total - factor[c][r] * step[c]
        step[r] = total / factor[r][r]
    return step
