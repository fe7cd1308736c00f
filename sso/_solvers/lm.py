"""The least-squares solver ``"lm"``: a bounded Levenberg-Marquardt on two residuals.

Minimises ``f(x) = r_1(x)^2 + r_2(x)^2 = |rho(x)|^2`` under box bounds. With two
residuals and ``k`` variables the damped Gauss-Newton step

    dx = -(J^T J + mu I)^-1 J^T r = -J^T (J J^T + mu I)^-1 r

(the push-through identity) needs one 2x2 solve whatever ``k`` is. The method is a
projected active-set Levenberg-Marquardt (Nielsen's damping rule, scaled by
``|r| / |r_0|``, Newton steps when it converges slowly to a nonzero residual);
:mod:`sso._solvers.lm_rules` states it, once.

A problem that gives its residuals as a CasADi expression (``nlp.residuals``: every
shaft series of the exact model) runs the rules as the shape's CasADi functions
(:mod:`sso._solvers.lm_kernel`), from its first call, whatever ran before:
:func:`sso.optimise_batch` runs the same functions, so a design ends there bit for bit
where it ends alone. A problem without the expression (a column's phasing or joint
centres, through :func:`minimise`) runs the same rules on plain Python floats.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from sso._solvers import round_off_stops
from sso._solvers.lm_kernel import (
    gradient_of,
    kernels_of,
    outcome,
    pack,
    problem_vector,
    solve_one,
    unpack,
)
from sso._solvers.lm_rules import (
    NEWTON,
    NEWTON_INDEFINITE,
    PYTHON,
    RUNNING,
    fresh_state,
    gauss_newton_iteration,
    newton_iteration,
)
from sso._solvers.run import RunLimits, RunOutcome

Residual = Callable[[list[float]], tuple[complex, list[complex]]]
Hessian = Callable[[list[float]], list[list[float]]]

TESTS_ITS_START = True
"""Its first step stops at a start already at a minimum (round-off zero, or a projected
gradient under the tolerance), for the cost of one evaluation: no check before it."""

INDEFINITE = -5
"""Status of a solve whose Newton step round-off kept indefinite past every shift."""

MESSAGES = {
    INDEFINITE: "the Newton step's Hessian stayed indefinite after every shift (round-off)",
    -2: "residual or Jacobian is not finite",
    -1: "no decrease possible (damping overflow) before the tolerance was met",
    0: "iteration limit reached",
    1: "projected gradient below the tolerance",
    2: "actual and predicted relative reductions at round-off",
    3: "step at round-off",
    4: "sum of squares at round-off zero",
    round_off_stops.REFUTED: round_off_stops.REFUTED_MESSAGE,
}
SUCCESS_STATUSES = (1, 2, 3, 4)
"""Statuses of a solve that succeeded."""
# Forward differences: truncation ~ step, round-off ~ eps / step; 1e-7 balances them
# well enough for Newton's superlinear convergence.
_HESSIAN_STEP = 1e-7


@dataclass(frozen=True)
class End:
    """Where a solve of the shape's functions ended (plain floats, NLP units).

    Attributes
    ----------
    x : list of float
    fun : float
        ``r1^2 + r2^2`` at ``x``, as the functions computed it.
    gradient : list of float
        ``2 J^T r`` at ``x``.
    nit, nfev, status : int
        Trial steps, residual evaluations (round-off probes included) and a key of
        :data:`MESSAGES`.
    """

    x: list[float]
    fun: float
    gradient: list[float]
    nit: int
    nfev: int
    status: int


def solve(nlp: Any, start: np.ndarray, parameters: np.ndarray, limits: RunLimits,
          solver_tol: float, max_iterations: int) -> RunOutcome:
    """:meth:`sso._solvers.run.Backend.solve` by the bounded Levenberg-Marquardt: it stops when
    the projected gradient of ``f`` (infinity norm) is at most ``solver_tol``, or after
    ``max_iterations`` trial steps. A problem without a ``residuals`` expression, or with
    constraint functions, fails the run."""
    started = time.perf_counter()
    if kernels_of(nlp) is None or limits.constrained:
        return RunOutcome(np.array(start, dtype=float), float("nan"), 0, 0, 0, -3, False,
                          "lm needs a bound-constrained problem with two residuals",
                          time.perf_counter() - started)
    end = solve_floats(nlp, start.tolist(), parameters.tolist(), limits.lower.tolist(),
                       limits.upper.tolist(), solver_tol, max_iterations)
    return RunOutcome(np.array(end.x), end.fun, end.nit, end.nfev, end.nfev, end.status,
                      end.status > 0, MESSAGES[end.status], time.perf_counter() - started)


def solve_floats(nlp: Any, start: list[float], fixed: list[float], lower: list[float],
                 upper: list[float], solver_tol: float, max_iterations: int) -> End:
    """:func:`solve` on lists of floats, by the shape's functions (``nlp.residuals``)."""
    kernels = kernels_of(nlp)
    assert kernels is not None, "solve_floats needs a problem with a residual expression"
    values = solve_one(kernels, start, problem_vector(fixed, lower, upper, solver_tol,
                                                      max_iterations))
    return end_of(nlp, fixed, values, lower, upper, solver_tol, max_iterations)


def end_of(nlp: Any, fixed: list[float], values: Any, lower: list[float],
           upper: list[float], solver_tol: float, max_iterations: int) -> End:
    """The end of a solve from the flat state the functions ended with: Newton steps on
    plain floats where the shape has no Newton block (:func:`newton_on_floats`), a stop at
    round-off tested (:func:`checked`), a Newton step left indefinite reported as a
    failure. :func:`sso.optimise_batch` and the screening read each design's state with
    it too."""
    size = len(lower)
    values = newton_on_floats(nlp, fixed, values, lower, upper, solver_tol, max_iterations)
    x, fun, nit, nfev, status = outcome(values, size)
    if status == NEWTON_INDEFINITE:
        status = INDEFINITE
    x, fun, nit, nfev, status = checked(nlp, fixed, x, fun, nit, nfev, status, lower, upper)
    return End(x, fun, gradient_of(values, size), nit, nfev, status)


def newton_on_floats(nlp: Any, fixed: list[float], values: Any, lower: list[float],
                     upper: list[float], solver_tol: float, max_iterations: int) -> Any:
    """A flat state of status :data:`sso._solvers.lm_rules.NEWTON` (a shape beyond
    :data:`sso._solvers.lm_kernel.NEWTON_BLOCK_VARIABLES`) taken to its end by the rules'
    Newton iterations on plain floats, with the problem's closed-form Hessian; any other
    state as it is."""
    size = len(lower)
    if outcome(values, size)[4] != NEWTON:
        return values
    residual = nlp.residuals_and_jacobian
    hessian = nlp.objective_hessian
    state = unpack([float(value) for value in values], size)
    ended = _newton_steps(lambda point: residual(point, fixed), state, lower, upper,
                          solver_tol, max_iterations,
                          None if hessian is None else lambda point: hessian(point, fixed))
    return pack(ended)


def gauss_newton_end(nlp: Any, start: list[float], fixed: list[float], lower: list[float],
                     upper: list[float], solver_tol: float, max_iterations: int
                     ) -> tuple[list[float], float, int, int]:
    """The start and Gauss-Newton steps of the rules from ``start`` (the shape's functions):
    ``x``, ``fun``, ``nit`` and ``nfev`` where they end, or where they turn to Newton
    steps."""
    kernels = kernels_of(nlp)
    assert kernels is not None, "gauss_newton_end needs a problem with a residual expression"
    values = solve_one(kernels, start, problem_vector(fixed, lower, upper, solver_tol,
                                                      max_iterations), newton=False)
    x, fun, nit, nfev, _ = outcome(values, len(lower))
    return x, fun, nit, nfev


def checked(nlp: Any, fixed: list[float], x: list[float], fun: float, nit: int, nfev: int,
            status: int, lower: list[float], upper: list[float]
            ) -> tuple[list[float], float, int, int, int]:
    """The outcome of a solve, a stop at round-off tested first: a minimum, or only a
    vanished step (:mod:`sso._solvers.round_off_stops`)?"""
    if status in round_off_stops.ROUND_OFF_STOPS:
        residual = nlp.residuals_and_jacobian
        holds, probes = round_off_stops.holds(lambda point: abs(residual(point, fixed)[0]) ** 2,
                                              list(x), fun, lower, upper)
        nfev += probes
        status = status if holds else round_off_stops.REFUTED
    return x, fun, nit, nfev, status


def minimise(residual: Residual, start: list[float], lower: list[float], upper: list[float],
             tolerance: float, max_iterations: int, hessian: Hessian | None = None
             ) -> tuple[list[float], float, int, int, int]:
    """Minimise ``|rho|^2`` under bounds from ``start`` by the rules on plain Python floats,
    for a problem whose residuals are a Python function ``residual(x) -> (rho, jacobian)``
    (complex numbers).

    ``hessian(x)``, when given, is the exact Hessian of ``|rho|^2`` for the Newton
    steps (one call, counted as one evaluation); without it they difference the
    gradient (one residual call per free variable).

    Returns
    -------
    x, fun, nit, nfev, status
        Final point, sum of squares, trial steps, residual evaluations and a key of
        :data:`MESSAGES`.
    """
    current = fresh_state(PYTHON, _evaluate_of(residual), start, lower, upper)
    while current["status"] == RUNNING:
        current = gauss_newton_iteration(PYTHON, _evaluate_of(residual), current, lower, upper,
                                         tolerance, max_iterations)
    current = _newton_steps(residual, current, lower, upper, tolerance, max_iterations, hessian)
    status = int(current["status"])
    return (current["x"], current["fun"], int(current["nit"]), int(current["nfev"]),
            INDEFINITE if status == NEWTON_INDEFINITE else status)


def _evaluate_of(residual: Residual) -> Any:
    """``point -> (r1, r2, J1, J2)`` of a complex residual function."""
    def evaluate(point: list[Any]) -> tuple[Any, Any, list[Any], list[Any]]:
        rho, jacobian = residual(point)
        # rho = r1 - i r2 (the sign of a residual does not matter to least squares).
        return (rho.real, -rho.imag, [entry.real for entry in jacobian],
                [-entry.imag for entry in jacobian])

    return evaluate


def _newton_steps(residual: Residual, state: dict[str, Any], lower: list[float],
                  upper: list[float], tolerance: float, max_iterations: int,
                  hessian: Hessian | None) -> dict[str, Any]:
    """The rules' Newton iterations on plain floats from ``state`` until it leaves Newton mode."""
    evaluate, hessian_at = _evaluate_of(residual), _hessian_of(residual, hessian)
    while state["status"] == NEWTON:
        state = newton_iteration(PYTHON, evaluate, hessian_at, state, lower, upper, tolerance,
                                 max_iterations)
    return state


def _hessian_of(residual: Residual, hessian: Hessian | None) -> Any:
    """The Newton steps' Hessian: the closed form, or forward differences of the gradient
    over the free variables; computed once per point (a rejected step keeps the point)."""
    last: list[Any] = [None, None]

    def at(point: list[float], gradient: list[float], free: list[bool], needed: bool
           ) -> tuple[list[list[float]], int]:
        size = len(point)
        evaluations = 1 if hessian is not None else sum(free)
        if not needed:
            return [[0.0] * size for _ in range(size)], evaluations
        if last[0] != point:
            last[0] = list(point)
            last[1] = (hessian(point) if hessian is not None
                       else _difference_hessian(residual, point, gradient, free))
        return last[1], evaluations

    return at


def _difference_hessian(residual: Residual, x: list[float], gradient: list[float],
                        free: list[bool]) -> list[list[float]]:
    """The Hessian of ``f`` over the free variables (zero elsewhere) by forward differences
    of the gradient (one residual-and-Jacobian call per free variable)."""
    size = len(x)
    hessian = [[0.0] * size for _ in range(size)]
    for i in (index for index, is_free in enumerate(free) if is_free):
        ahead = list(x)
        ahead[i] += _HESSIAN_STEP
        ahead_rho, ahead_jacobian = residual(ahead)
        r1, r2 = 2.0 * ahead_rho.real, 2.0 * ahead_rho.imag
        for j in (index for index, is_free in enumerate(free) if is_free):
            entry = ahead_jacobian[j]
            hessian[j][i] = (r1 * entry.real + r2 * entry.imag - gradient[j]) / _HESSIAN_STEP
    return hessian
