"""Second-order care around a local solver: stop at once at a minimum, leave saddle points.

A gradient-based solver started on a symmetric design (phases at 0, 90 or 180 deg,
equal angles) sees a gradient that is zero along the symmetry-breaking directions,
so it stops on a saddle point and calls it a success. With bounds only (no
constraint functions), the Hessian of the objective over the variables off their
bounds tells a minimum from a saddle:

* if the start is already stationary and the Hessian has no negative curvature,
  the start is returned without running the solver (e.g. straight shafts: RE = 0);
* if a solver stops where the Hessian has negative curvature, the design is moved
  along that direction until the objective drops, and the solver runs again from
  there (at most ``MAX_ESCAPES`` times); the counts of every leg are summed.

An objective that is never negative (a sum of squares such as RE; the problem says
so by ``nlp.nonnegative_objective``) is at a global minimum wherever it is at or
below ``ZERO_OBJECTIVE`` (round-off), so no check is made there.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from sso._record import rebuilt
from sso._solvers.kkt import projected_gradient_norm_floats
from sso._solvers.lm_rules import PYTHON, cholesky
from sso._solvers.nlp import value_and_gradient_floats
from sso._solvers.run import RunLimits, RunOutcome

Parameters = np.ndarray | list[float]
"""The fixed parameters (NLP units): an array, or the same values as a list of floats."""

MAX_ESCAPES = 3
# Negative curvature counts when the smallest eigenvalue is below -RELATIVE_CURVATURE
# times the largest magnitude, and below -ABSOLUTE_CURVATURE (the difference
# Hessian's error stays far under both).
RELATIVE_CURVATURE = 1e-6
ABSOLUTE_CURVATURE = 1e-14
# Distance (NLP units) within which a variable counts as sitting on its bound.
ON_BOUND = 1e-9
# A start counts as stationary when its projected gradient is below both the
# solver tolerance and this (straight shafts give exactly 0).
STATIONARY_START = 1e-12
HESSIAN_STEP = 1e-4
# A nonnegative objective at or below this is zero up to round-off: a global minimum.
ZERO_OBJECTIVE = 1e-20
# Residuals of a least-squares objective (nlp.residuals_and_jacobian: RE = r1^2 + r2^2).
LEAST_SQUARES_RESIDUALS = 2
FIRST_STEP = 0.1
SMALLEST_STEP = 1e-7


def solve_with_second_order_care(
    solve: Callable[[np.ndarray], RunOutcome],
    nlp: Any,
    start: np.ndarray,
    parameters: np.ndarray,
    limits: RunLimits,
    solver_tol: float,
    check_start: bool = True,
) -> RunOutcome:
    """Run ``solve(start)``, skipping it at a minimum and restarting it off saddle points.

    Parameters
    ----------
    solve : callable
        One solver run from a start: ``solve(start) -> RunOutcome``.
    nlp : sso._solvers.nlp.CompiledNLP
        The problem graph (its exact gradient gives the Hessian).
    start, parameters : numpy.ndarray
        Start and fixed parameters (NLP units).
    limits : RunLimits
        Bounds; with constraint functions the solver is simply run.
    solver_tol : float
        The solver tolerance; the start counts as stationary when its projected
        gradient is below it and below ``STATIONARY_START``.
    check_start : bool
        Look at the start before running the solver (False for a solver whose
        first step is that same test, such as ``"lm"``: a start at a minimum
        costs it one evaluation, and a saddle point it stops on is still left).

    Returns
    -------
    RunOutcome
        Its ``time_s`` covers every solver leg and the checks between them.
    """
    if limits.constrained:
        return solve(start)
    started = time.perf_counter()
    outcome = _solve_with_checks(solve, nlp, start, parameters, limits, solver_tol, check_start)
    return outcome.with_time(time.perf_counter() - started)


def _solve_with_checks(solve: Callable[[np.ndarray], RunOutcome], nlp: Any, start: np.ndarray,
                       parameters: np.ndarray, limits: RunLimits, solver_tol: float,
                       check_start: bool) -> RunOutcome:
    """The checks' own calls are counted: objective values they compare as ``nfev``,
    gradients the difference Hessian uses as ``njev``."""
    counts = _Counts()
    start = np.minimum(np.maximum(np.asarray(start, dtype=float), limits.lower), limits.upper)
    global_floor = _global_floor(nlp)
    if check_start:
        at_minimum = _minimum_at_start(nlp, start, parameters, limits, solver_tol, global_floor,
                                       counts)
        if at_minimum is not None:
            return counts.add_to(at_minimum)
    outcome = solve(start)
    for _ in range(MAX_ESCAPES):
        found = saddle_direction(nlp, outcome.success, outcome.fun, outcome.x.tolist(),
                                 parameters, limits, counts)
        if found is None:
            break
        x, direction = found
        escaped = _descend_along(nlp, x, direction, parameters, limits, counts)
        if escaped is None:
            break
        outcome = _combine(outcome, solve(escaped))
    return counts.add_to(outcome)


def saddle_direction(nlp: Any, success: bool, fun: float, x: list[float],
                     parameters: Parameters, limits: RunLimits | Callable[[], RunLimits],
                     counts: _Counts | None = None) -> tuple[np.ndarray, np.ndarray] | None:
    """Where a run that succeeded stopped on a saddle point: the point (on the bounds) and
    the direction of most negative curvature there; None after a failure, at a nonnegative
    objective's global minimum (round-off zero), at a point that is not finite, or where
    no variable that may move has negative curvature.

    ``limits`` may be a function that gives them: it is called only for the curvature,
    which a run that stops at round-off zero never needs. The checks' gradient calls are
    added to ``counts``.
    """
    if not success or fun <= _global_floor(nlp) or not math.isfinite(sum(x)):
        return None
    bounds = limits if isinstance(limits, RunLimits) else limits()
    point = np.clip(np.array(x, dtype=float), bounds.lower, bounds.upper)
    direction = _negative_curvature(nlp, point, parameters, bounds,
                                    _Counts() if counts is None else counts)
    return None if direction is None else (point, direction)


def _global_floor(nlp: Any) -> float:
    """The objective at which a run is a global minimum without a look: round-off zero for
    a nonnegative objective, none (minus infinity) otherwise."""
    return ZERO_OBJECTIVE if getattr(nlp, "nonnegative_objective", False) else -math.inf


def _minimum_at_start(nlp: Any, start: np.ndarray, parameters: np.ndarray, limits: RunLimits,
                      solver_tol: float, global_floor: float,
                      counts: _Counts) -> RunOutcome | None:
    """The start as the answer when it is a global minimum or a minimum to tolerance, else None."""
    value, gradient = _value_and_gradient(nlp, start, parameters, counts)
    if value <= global_floor:
        return RunOutcome(start, value, 0, 0, 0, 0, True,
                          "start is a global minimum (nonnegative objective at round-off "
                          "zero): solver not run", 0.0)
    stationary = min(solver_tol, STATIONARY_START)
    if (projected_gradient_norm_floats(start.tolist(), gradient, limits.lower.tolist(),
                                       limits.upper.tolist()) <= stationary
            and _negative_curvature(nlp, start, parameters, limits, counts) is None):
        return RunOutcome(start, value, 0, 0, 0, 0, True,
                          "start is a minimum to tolerance (stationary, no negative curvature): "
                          "solver not run", 0.0)
    return None


class _Counts:
    """Objective values and gradients the checks evaluate (one CasADi call gives both)."""

    def __init__(self) -> None:
        self.objective = 0
        self.gradient = 0

    def add_to(self, outcome: RunOutcome) -> RunOutcome:
        if not (self.objective or self.gradient):
            return outcome
        return rebuilt(outcome, nfev=outcome.nfev + self.objective,
                       njev=outcome.njev + self.gradient)


def _value_and_gradient(nlp: Any, x: np.ndarray | list[float], parameters: Parameters,
                        counts: _Counts, use: str = "both") -> tuple[float, list[float]]:
    """Objective and gradient, counted as ``use``: ``"both"``, ``"objective"`` or ``"gradient"``."""
    counts.objective += use in ("both", "objective")
    counts.gradient += use in ("both", "gradient")
    return value_and_gradient_floats(nlp, x, parameters)


def _hessian(nlp: Any, point: list[float], parameters: Parameters, counts: _Counts,
             free: list[int]) -> list[list[float]]:
    """Hessian of the objective over the variables ``free``: the problem's own closed form
    (``nlp.objective_hessian``, counted as one gradient call) where it has one, else
    central differences of its exact gradient.

    Differences take ``2 len(free)`` gradient calls and no symbolic work: a symbolic
    Hessian of a twelve-joint graph takes seconds to build, longer than the solve it
    checks. Their truncation error (``HESSIAN_STEP^2`` times third derivatives)
    stays far below the ``RELATIVE_CURVATURE`` that counts as negative curvature.
    Plain floats: the matrices are small, and each numpy call costs more than their
    arithmetic.
    """
    closed_form = getattr(nlp, "objective_hessian", None)
    if closed_form is not None:
        counts.gradient += 1
        full = closed_form(point, parameters)
        return [[full[row][column] for column in free] for row in free]
    columns = []
    for index in free:
        ahead, behind = list(point), list(point)
        ahead[index] += HESSIAN_STEP
        behind[index] -= HESSIAN_STEP
        gradient_ahead = _value_and_gradient(nlp, ahead, parameters, counts, "gradient")[1]
        gradient_behind = _value_and_gradient(nlp, behind, parameters, counts, "gradient")[1]
        columns.append([(gradient_ahead[row] - gradient_behind[row]) / (2.0 * HESSIAN_STEP)
                        for row in free])
    size = len(free)
    return [[0.5 * (columns[column][row] + columns[row][column]) for column in range(size)]
            for row in range(size)]


def _free_hessian(nlp: Any, x: np.ndarray, parameters: Parameters, limits: RunLimits,
                  counts: _Counts) -> tuple[list[int], list[list[float]]]:
    """The variables that may move and the Hessian over them."""
    point = x.tolist()
    _, free = _free_variables(nlp, point, parameters, limits, counts)
    return free, (_hessian(nlp, point, parameters, counts, free) if free else [])


def _free_variables(nlp: Any, point: list[float], parameters: Parameters, limits: RunLimits,
                    counts: _Counts) -> tuple[float, list[int]]:
    """The objective at ``point`` and the variables that may move there.

    A variable is held when its bounds pin it, or when it sits on a bound and the
    gradient pushes it against that bound by more than round-off (at a symmetric
    point the gradient is zero up to a sign that means nothing).
    """
    value, gradient = _value_and_gradient(nlp, point, parameters, counts, "gradient")
    free = [index for index, (entry, low, high, slope)
            in enumerate(zip(point, limits.lower.tolist(), limits.upper.tolist(), gradient,
                             strict=True))
            if not (high - low <= ON_BOUND
                    or (entry - low <= ON_BOUND and slope > STATIONARY_START)
                    or (high - entry <= ON_BOUND and slope < -STATIONARY_START))]
    return value, free


def _negative_curvature(nlp: Any, x: np.ndarray, parameters: Parameters,
                        limits: RunLimits, counts: _Counts) -> np.ndarray | None:
    """Unit direction of most negative curvature over the variables that may move."""
    free, hessian = _free_hessian(nlp, x, parameters, limits, counts)
    if not free:
        return None
    if not all(math.isfinite(entry) for row in hessian for entry in row):
        return None
    # The largest eigenvalue magnitude is at least the largest diagonal magnitude, so
    # the threshold below is at least RELATIVE_CURVATURE times the latter: when H plus
    # that shift has a Cholesky factor, no eigenvalue lies below the threshold, and
    # only when it has none is the eigendecomposition needed.
    largest_diagonal = max(abs(hessian[index][index]) for index in range(len(free)))
    if cholesky(PYTHON, hessian, max(RELATIVE_CURVATURE * largest_diagonal,
                                     ABSOLUTE_CURVATURE))[1]:
        return None
    eigenvalues, eigenvectors = np.linalg.eigh(np.array(hessian))
    largest = max(abs(float(eigenvalues[0])), abs(float(eigenvalues[-1])))
    threshold = max(RELATIVE_CURVATURE * largest, ABSOLUTE_CURVATURE)
    if eigenvalues[0] >= -threshold:
        return None
    direction = np.zeros_like(x)
    direction[free] = eigenvectors[:, 0]
    return direction


def isolated_minimum(nlp: Any, x: np.ndarray, parameters: np.ndarray,
                     limits: RunLimits) -> bool:
    """True when ``x`` is a strict local minimum, so another solver must reach the same design.

    Bound-only problems: every variable that may move (see :func:`_free_hessian`) has
    positive curvature, the Hessian's smallest eigenvalue above ``RELATIVE_CURVATURE``
    times its largest. A least-squares objective (``nlp.residuals_and_jacobian``, two
    residuals) at round-off zero with more than two variables free is not: there its
    Hessian is ``2 J^T J`` of rank two at most, so the point lies on a set of optima,
    and no Hessian is computed. With constraint functions: False (not judged).
    """
    if limits.constrained:
        return False
    point = np.clip(np.asarray(x, dtype=float), limits.lower, limits.upper).tolist()
    counts = _Counts()
    value, free = _free_variables(nlp, point, parameters, limits, counts)
    if not free:
        return True
    if (getattr(nlp, "nonnegative_objective", False)
            and getattr(nlp, "residuals_and_jacobian", None) is not None
            and value <= ZERO_OBJECTIVE and len(free) > LEAST_SQUARES_RESIDUALS):
        return False
    hessian = _hessian(nlp, point, parameters, counts, free)
    if not all(math.isfinite(entry) for row in hessian for entry in row):
        return False
    eigenvalues = np.linalg.eigvalsh(np.array(hessian))
    largest = max(abs(float(eigenvalues[0])), abs(float(eigenvalues[-1])))
    return bool(eigenvalues[0] > max(RELATIVE_CURVATURE * largest, ABSOLUTE_CURVATURE))


def _descend_along(nlp: Any, x: np.ndarray, direction: np.ndarray, parameters: np.ndarray,
                   limits: RunLimits, counts: _Counts) -> np.ndarray | None:
    """A point along ``+-direction`` (clipped to the bounds) with a lower objective."""
    value, _ = _value_and_gradient(nlp, x, parameters, counts, "objective")
    step = FIRST_STEP
    while step >= SMALLEST_STEP:
        for sign in (1.0, -1.0):
            candidate = np.clip(x + sign * step * direction, limits.lower, limits.upper)
            candidate_value, _ = _value_and_gradient(nlp, candidate, parameters, counts,
                                                     "objective")
            if np.isfinite(candidate_value) and candidate_value < value:
                return candidate
        step /= 4.0
    return None


def _combine(first: RunOutcome, second: RunOutcome) -> RunOutcome:
    """The second leg's answer with the counts and time of both legs."""
    return RunOutcome(second.x, second.fun, first.nit + second.nit, first.nfev + second.nfev,
                      first.njev + second.njev, second.status, second.success,
                      f"{second.message} (after leaving a saddle point)",
                      first.time_s + second.time_s)
