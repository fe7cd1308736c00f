"""First-order optimality under bounds, from the objective's gradient."""

from __future__ import annotations

import numpy as np


def projected_gradient_norm(
    x: np.ndarray, gradient: np.ndarray, lower: np.ndarray, upper: np.ndarray
) -> float:
    """Infinity norm of ``x - clip(x - gradient, lower, upper)``.

    Zero exactly at a first-order (KKT) point of a bound-constrained problem:
    gradient components that push against an active bound do not count.
    """
    if len(x) == 0:
        return 0.0
    step = x - np.clip(x - gradient, lower, upper)
    return float(np.max(np.abs(step)))
