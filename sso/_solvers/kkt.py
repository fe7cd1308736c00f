"""First-order optimality, measured the same way for every solver."""

from __future__ import annotations

import math

import numpy as np

from sso._solvers.run import RunLimits

# A constraint or bound within this distance of its limit counts as active.
ACTIVE_TOLERANCE = 1e-7


def projected_gradient_norm(
    x: np.ndarray, gradient: np.ndarray, lower: np.ndarray, upper: np.ndarray
) -> float:
    """Infinity norm of ``x - clip(x - gradient, lower, upper)`` (NaN if the gradient has one).

    Zero exactly at a first-order (KKT) point of a bound-constrained problem:
    gradient components that push against an active bound do not count.
    """
    return projected_gradient_norm_floats(x.tolist(), np.ravel(gradient).tolist(),
                                          lower.tolist(), upper.tolist())


def projected_gradient_norm_floats(x: list[float], gradient: list[float], lower: list[float],
                                   upper: list[float]) -> float:
    """:func:`projected_gradient_norm` of lists of floats: the vectors are a few dozen
    entries, fewer than a numpy call's overhead is worth."""
    norm = 0.0
    for value, slope, low, high in zip(x, gradient, lower, upper, strict=True):
        projected = value - slope
        if projected != projected:
            return math.nan
        distance = abs(value - (low if projected < low else high if projected > high
                                else projected))
        if distance > norm:
            norm = distance
    return norm


def kkt_residual(
    x: np.ndarray,
    gradient: np.ndarray,
    limits: RunLimits,
    constraint_values: np.ndarray | None = None,
    constraint_jacobian: np.ndarray | None = None,
) -> float:
    """Stationarity error of ``x`` under bounds and constraints.

    Without constraints this is :func:`projected_gradient_norm`. With them, the
    gradient is matched by non-negative multipliers of the active bounds and
    constraints (a non-negative least-squares fit, independent of what any
    solver reports as multipliers), and the infinity norm of what is left is
    returned.
    """
    if not limits.constrained:
        return projected_gradient_norm(x, gradient, limits.lower, limits.upper)
    from scipy.optimize import nnls

    size = len(x)
    identity = np.eye(size)
    normals = []  # gradients of the active constraints written as c(x) >= 0
    normals += [identity[i] for i in np.flatnonzero(x - limits.lower <= ACTIVE_TOLERANCE)]
    normals += [-identity[i] for i in np.flatnonzero(limits.upper - x <= ACTIVE_TOLERANCE)]
    values = np.asarray(constraint_values, dtype=float).ravel()
    jacobian = np.asarray(constraint_jacobian, dtype=float).reshape(len(values), size)
    normals += [jacobian[i] for i in np.flatnonzero(values - limits.constraint_lower
                                                     <= ACTIVE_TOLERANCE)]
    normals += [-jacobian[i] for i in np.flatnonzero(limits.constraint_upper - values
                                                      <= ACTIVE_TOLERANCE)]
    if not normals:
        return float(np.max(np.abs(gradient))) if size else 0.0
    matrix = np.array(normals).T
    multipliers, _ = nnls(matrix, gradient)
    return float(np.max(np.abs(gradient - matrix @ multipliers)))


def constraint_violation(
    x: np.ndarray, limits: RunLimits, constraint_values: np.ndarray | None = None
) -> float:
    """Largest amount by which ``x`` or ``g(x)`` leaves its bounds (0 when feasible)."""
    excess = 0.0
    for value, low, high in zip(x.tolist(), limits.lower.tolist(), limits.upper.tolist(),
                                strict=True):
        excess = max(excess, low - value, value - high)
    if limits.constrained:
        values = np.asarray(constraint_values, dtype=float).ravel()
        excess = max(excess, float(np.max(limits.constraint_lower - values)),
                     float(np.max(values - limits.constraint_upper)))
    return excess
