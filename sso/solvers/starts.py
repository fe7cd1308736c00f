"""Start points: the user's start plus space-filling points inside the bounds."""

from __future__ import annotations

import numpy as np

DEFAULT_SEED = 20251122


def start_points(
    user_start: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    count: int,
    seed: int = DEFAULT_SEED,
) -> np.ndarray:
    """``count`` starts: the user's start first, then scrambled Halton points.

    Parameters
    ----------
    user_start, lower, upper : numpy.ndarray
        Start and bounds of the design vector (any consistent unit).
    count : int
        Number of starts, >= 1. With 1, no space-filling points are made (and
        ``scipy.stats`` is not imported).
    seed : int
        Seed of the scrambling, so runs repeat exactly.

    Returns
    -------
    numpy.ndarray
        Shape ``(count, len(user_start))``.
    """
    user_start = np.asarray(user_start, dtype=float)
    if count == 1:
        return user_start[np.newaxis, :]
    from scipy.stats import qmc

    sampler = qmc.Halton(d=user_start.size, scramble=True, seed=seed)
    unit_points = sampler.random(count - 1)
    spread = lower + unit_points * (upper - lower)
    return np.vstack([user_start, spread])
