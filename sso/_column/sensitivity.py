"""First-order variance-based sensitivity indices from one Monte Carlo sample ("given data").

The first-order (Sobol') index of an input ``X_i`` in a figure ``Y`` is the share of
``Var(Y)`` that ``X_i`` explains alone, ``S_i = Var(E[Y | X_i]) / Var(Y)``. It is
estimated here from the study's own sample, with no design of its own (no Saltelli
matrices): the sample is sorted by ``X_i`` and cut into ``B`` bins of equal count;
``E[Y | X_i]`` is the mean of ``Y`` in each bin, and the variance of those means,
weighted by their counts, estimates ``Var(E[Y | X_i])`` (E. Plischke, E. Borgonovo
and C. L. Smith, "Global sensitivity measures from given data", European Journal of
Operational Research 226 (2013) 536-550). The spread of each bin's mean around the
bin's true mean adds about ``(B - 1) / N`` of the pooled within-bin variance to that
weighted variance; it is subtracted, and a result below 0 (an input that explains
nothing, up to sampling noise) is reported as 0. ``B`` is ``round(sqrt(N))``
(at least 2): the bins' sampling error and their width's smoothing then shrink
together as ``N`` grows.

The indices of independent inputs sum to at most 1; their shortfall from 1 is the
share of interactions (tested against the Ishigami function's known indices in
``tests/column/test_sensitivity.py``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sso._record import register_record

MIN_SAMPLES = 16
"""Fewest samples an index is estimated from (4 bins of 4)."""


def bin_count(samples: int) -> int:
    """Bins of the estimator for ``samples`` samples: ``round(sqrt(samples))``, >= 2."""
    return max(2, round(math.sqrt(samples)))


def first_order_indices(inputs: np.ndarray, output: np.ndarray) -> np.ndarray:
    """First-order sensitivity index of ``output`` to each column of ``inputs``.

    Parameters
    ----------
    inputs : numpy.ndarray, shape (samples, inputs)
        Each sample's inputs (independent draws).
    output : numpy.ndarray, shape (samples,)
        Each sample's figure.

    Returns
    -------
    numpy.ndarray, shape (inputs,)
        ``S_i`` in ``[0, 1]`` (module notes); all 0 where ``output`` does not vary.

    Raises
    ------
    ValueError
        If the shapes disagree, there are fewer than :data:`MIN_SAMPLES` samples, or a
        value is not finite.
    """
    inputs = np.asarray(inputs, dtype=float)
    if inputs.ndim != 2:
        raise ValueError(f"inputs of shape {inputs.shape}: need (samples, inputs)")
    return np.array([first_order_index(inputs[:, column], output)
                     for column in range(inputs.shape[1])])


def first_order_index(values: np.ndarray, output: np.ndarray) -> float:
    """First-order sensitivity index of ``output`` to one input's ``values`` (module
    notes), in ``[0, 1]``; 0 where ``output`` does not vary.

    Raises
    ------
    ValueError
        As :func:`first_order_indices`.
    """
    values = np.asarray(values, dtype=float)
    output = np.asarray(output, dtype=float)
    if values.ndim != 1 or output.shape != values.shape:
        raise ValueError(f"inputs of shape {values.shape} and output of shape {output.shape}: "
                         "need (samples, inputs) and (samples,)")
    samples = len(output)
    if samples < MIN_SAMPLES:
        raise ValueError(f"samples = {samples}: the indices need at least {MIN_SAMPLES}")
    if not (np.all(np.isfinite(values)) and np.all(np.isfinite(output))):
        raise ValueError("inputs and output must be finite")
    total = float(np.var(output))
    if total == 0.0:
        return 0.0
    bins = bin_count(samples)
    edges = np.linspace(0, samples, bins + 1).round().astype(int)
    mean = float(np.mean(output))
    # stable sort: tied inputs (a zero tolerance) keep the sample order
    ordered = output[np.argsort(values, kind="stable")]
    between = 0.0
    within = 0.0
    for start, stop in zip(edges[:-1], edges[1:], strict=True):
        part = ordered[start:stop]
        part_mean = float(np.mean(part))
        between += len(part) * (part_mean - mean) ** 2
        within += float(np.sum((part - part_mean) ** 2))
    between /= samples
    within /= samples - bins
    return min(1.0, max(0.0, between - (bins - 1) / samples * within) / total)


@register_record
@dataclass(frozen=True)
class Contribution:
    """The first-order index of one tolerance in one figure.

    Attributes
    ----------
    tolerance : str
        The input in words (``"P1 y"``, ``"yoke phasing delta_1"``).
    index : float
        Its first-order index, a fraction of the figure's variance.
    """

    tolerance: str
    index: float


@register_record
@dataclass(frozen=True)
class FigureSensitivity:
    """Which tolerances a limited figure's spread comes from, largest first.

    Attributes
    ----------
    figure, label, unit : str
        The figure (as :mod:`sso._column.yields` names it), in words, and its unit.
    contributions : tuple of Contribution
        Every tolerance's first-order index, largest first.
    """

    figure: str
    label: str
    unit: str
    contributions: tuple[Contribution, ...]

    @property
    def interactions(self) -> float:
        """``1 - sum of the indices``: the share no single tolerance explains alone."""
        return max(0.0, 1.0 - sum(item.index for item in self.contributions))


def ranked(names: tuple[str, ...], indices: np.ndarray) -> tuple[Contribution, ...]:
    """Contributions largest first (ties in input order)."""
    order = sorted(range(len(names)), key=lambda position: -float(indices[position]))
    return tuple(Contribution(names[position], float(indices[position])) for position in order)
