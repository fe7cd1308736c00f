"""Start points: the user's start plus space-filling points inside the bounds.

The space-filling points are a Halton sequence (radical inverses in the first
primes, one per variable) with a Cranley-Patterson rotation (a random shift modulo
1 per variable, from ``numpy.random.default_rng(seed)``): a few lines of numpy, so a
multi-start run imports nothing more (``scipy.stats`` alone takes about 0.3 s to
import). The rotation keeps the sequence's low discrepancy and makes the points
depend on ``seed`` while repeating exactly for one seed.
"""

from __future__ import annotations

import functools

import numpy as np

from sso._limits import DEFAULT_SEED


def start_points(
    user_start: np.ndarray,
    lower: np.ndarray,
    upper: np.ndarray,
    count: int,
    seed: int = DEFAULT_SEED,
) -> np.ndarray:
    """``count`` starts: the user's start first, then rotated Halton points.

    Parameters
    ----------
    user_start, lower, upper : numpy.ndarray
        Start and bounds of the design vector (any consistent unit).
    count : int
        Number of starts, >= 1. With 1, no space-filling points are made.
    seed : int
        Seed of the rotation, so runs repeat exactly.

    Returns
    -------
    numpy.ndarray
        Shape ``(count, len(user_start))``.
    """
    user_start = np.asarray(user_start, dtype=float)
    if count == 1:
        return user_start[np.newaxis, :]
    unit_points = _kept_halton(count - 1, user_start.size, seed)
    spread = lower + unit_points * (upper - lower)
    return np.concatenate((user_start[np.newaxis, :], spread))


@functools.lru_cache(maxsize=16)
def _kept_halton(count: int, dimension: int, seed: int) -> np.ndarray:
    """:func:`rotated_halton`, read-only and kept for the next call of the same shape and
    seed (a multi-start solve of a few joints costs a few times what making them does)."""
    points = rotated_halton(count, dimension, seed)
    points.flags.writeable = False
    return points


def rotated_halton(count: int, dimension: int, seed: int) -> np.ndarray:
    """``count`` points of the Halton sequence in ``[0, 1)^dimension``, randomly rotated.

    Point ``i`` (from 1) has coordinate ``d`` equal to the radical inverse of ``i`` in
    the ``d``-th prime, plus a uniform shift of that coordinate, modulo 1.
    """
    shift = np.random.default_rng(seed).random(dimension)
    # Every coordinate at once, one digit per pass: a coordinate whose index has run
    # out of digits adds zeros, so each sum is the one its own loop would make.
    bases = np.array(_primes(dimension))
    index = np.repeat(np.arange(1, count + 1)[:, np.newaxis], dimension, axis=1)
    points = np.zeros((count, dimension))
    scale = 1.0 / bases
    while np.any(index):
        index, digit = np.divmod(index, bases)
        points += digit * scale
        scale = scale / bases
    return np.mod(points + shift, 1.0)


def _primes(count: int) -> list[int]:
    """The first ``count`` primes."""
    primes: list[int] = []
    candidate = 2
    while len(primes) < count:
        if all(candidate % prime for prime in primes if prime * prime <= candidate):
            primes.append(candidate)
        candidate += 1
    return primes
