"""The samples of a shaft series' tolerance study: drawn, evaluated, estimated.

:func:`sso._studies.tolerance_study.tolerance_study` makes a study's samples here, and
a saved study (:class:`sso.ToleranceResult` read back from ``result.json``, which
holds no samples) draws and evaluates the same samples again here
(:func:`redrawn_samples`): the numbers depend on the design, tolerances, distribution
and seed only, never on the chunking, executor or worker count.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from sso._limits import DEFAULT_CHUNK_SAMPLES
from sso._progress import ProgressBar
from sso._resources import ResourceEstimate, check_memory
from sso._shafts.evaluation import MIN_FIGURE_SAMPLES
from sso._shafts.perturbed import (
    DISTRIBUTIONS,
    MAX_SAMPLES,
    METRICS,
    ToleranceChunk,
    draw_samples,
    evaluate_chunk,
    per_item_tolerances,
)
from sso._shafts.quadrature import rule_for_bounds
from sso._shafts.series import ShaftSeries
from sso._studies.estimate import tolerance_estimate
from sso._studies.execution import run_tasks
from sso._validation import check_choice, validate_count


def study_estimate(series: ShaftSeries, samples: int, quadrature: tuple[float, float],
                   workers: int = 1,
                   chunk_size: int = DEFAULT_CHUNK_SAMPLES) -> ResourceEstimate:
    """The memory (whole process) and evaluations of a study of ``series``.

    The exact model's figures are closed forms (one value per sample, no angle grid).
    The paper model's quadrature count is fixed after the draw; until then, estimate
    with the nominal design's count (the figures grid is never coarser than its
    minimum).
    """
    if series.model == "exact":
        figure_samples = 1
    else:
        figure_samples = max(MIN_FIGURE_SAMPLES, 4 * rule_for_bounds(
            np.abs(series.beta_rad).tolist(), series.model, *quadrature).samples)
    return tolerance_estimate(samples, series.n_joints, figure_samples, workers, chunk_size)


def drawn_samples(series: ShaftSeries, beta_tolerance_deg: Sequence[float],
                  phase_tolerance_deg: Sequence[float], distribution: str, samples: int,
                  seed: int) -> tuple[np.ndarray, np.ndarray, int]:
    """The sampled operating angles and phases (deg; an angle below 0 reflected to its
    magnitude) and how many samples had one reflected (:func:`draw_samples`)."""
    beta_deg, phase_deg = draw_samples(series, beta_tolerance_deg, phase_tolerance_deg,
                                       distribution, samples, seed)
    reflected = int(np.count_nonzero((beta_deg < 0.0).any(axis=1)))
    return np.abs(beta_deg), phase_deg, reflected


def evaluate_samples(beta_deg: np.ndarray, phase_deg: np.ndarray, model: str,
                     quadrature_samples: int, speed_rpm: float,
                     chunk_size: int = DEFAULT_CHUNK_SAMPLES, client: Any = None,
                     workers: int = 1, progress: bool = False) -> np.ndarray:
    """The figures (:data:`METRICS`, rows) of every sample, shape ``(3, samples)``: the
    same numbers for any chunk size, executor or worker count."""
    samples = len(beta_deg)
    beta_rad = np.radians(beta_deg)
    phase_rad = np.radians(phase_deg)
    chunks = [ToleranceChunk(beta_rad[start:start + chunk_size],
                             phase_rad[start:start + chunk_size], model, quadrature_samples,
                             speed_rpm)
              for start in range(0, samples, chunk_size)]
    metrics = np.empty((len(METRICS), samples))
    bar = ProgressBar(samples, "samples", progress)
    try:
        for index, values, error in run_tasks(evaluate_chunk, chunks, client, workers):
            if error is not None:
                raise RuntimeError(f"tolerance study: chunk {index} failed: {error}") from error
            metrics[:, index * chunk_size:index * chunk_size + values.shape[1]] = values
            bar.advance(values.shape[1])
    finally:
        bar.close()
    return metrics


def redrawn_samples(series: ShaftSeries, beta_tolerance_deg: Sequence[float],
                    phase_tolerance_deg: Sequence[float], distribution: str, samples: int,
                    seed: int, quadrature_samples: int,
                    speed_rpm: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """The samples of a saved study drawn and evaluated again in this process: angles
    (deg), figures and the samples reflected, as :func:`tolerance_study` made them.

    Raises
    ------
    ValueError
        If the settings are out of range, or the samples would need more memory than
        the limit (``SSO_MEMORY_LIMIT_MB``).
    """
    samples = validate_count("samples", samples, 1, MAX_SAMPLES)
    check_choice("distribution", distribution, DISTRIBUTIONS)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise ValueError(f"seed = {seed!r} must be a whole number >= 0")
    figure_samples = 1 if series.model == "exact" else max(MIN_FIGURE_SAMPLES,
                                                            4 * quadrature_samples)
    check_memory(tolerance_estimate(samples, series.n_joints, figure_samples, 1), None)
    beta_deg, phase_deg, reflected = drawn_samples(
        series, per_item_tolerances("beta_tolerance_deg", beta_tolerance_deg, series.n_joints),
        per_item_tolerances("phase_tolerance_deg", phase_tolerance_deg, series.n_joints - 1),
        distribution, samples, seed)
    metrics = evaluate_samples(beta_deg, phase_deg, series.model, quadrature_samples,
                               speed_rpm)
    return beta_deg, phase_deg, metrics, reflected
