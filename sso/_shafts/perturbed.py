"""Many perturbed designs of one shaft series at once: the kernel of a tolerance study.

Samples are evaluated as arrays (thousands of designs per numpy call) exactly as
:meth:`sso.ShaftSeries.evaluate` evaluates one design; :mod:`sso._studies.tolerance_study`
draws them, spreads the chunks over processes and gathers the figures.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from sso._kinematics.hooke import chain_kinematics
from sso._kinematics.hooke_matrix import peak_ratio_slope, ratio_extremes
from sso._kinematics.hooke_matrix import residual_error as closed_form_residual_error
from sso._limits import BETA_LIMIT_DEG
from sso._resources import block_samples
from sso._shafts.evaluation import MIN_FIGURE_SAMPLES, RPM_TO_RAD_S
from sso._shafts.objective import residual_error
from sso._shafts.series import ShaftSeries
from sso._validation import as_float_tuple, check_chain_conditioning, check_in_range

METRICS = ("residual_error", "fluctuation", "max_output_accel_rad_s2")
DISTRIBUTIONS = ("normal", "uniform")
MAX_SAMPLES = 100_000_000
MAX_TOLERANCE_DEG = 45.0
DEFAULT_TOLERANCES: dict[str, Any] = {
    "beta_tolerance_deg": 0.5,
    "phase_tolerance_deg": 1.0,
    "distribution": "normal",
    "samples": 10_000,
    "seed": 0,
}
"""Tolerances of a study (:func:`sso.tolerance_study`, and the p95 choice of
:func:`sso.optimise`) that the call does not give."""
# A normal draw further than this many standard deviations out is treated as a
# broken input (probability ~2e-9 per draw), not as a manufacturing deviation.
NORMAL_REACH_SIGMAS = 6.0


@dataclass(frozen=True)
class ToleranceChunk:
    """Samples to evaluate in one task (angles in rad, arrays of shape (m, joints))."""

    beta_rad: np.ndarray
    phase_rad: np.ndarray
    model: str
    quadrature_samples: int
    input_speed_rpm: float


def draw_samples(series: ShaftSeries, beta_tolerance_deg: Sequence[float],
                 phase_tolerance_deg: Sequence[float], distribution: str, samples: int,
                 seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Perturbed operating angles and phases (deg), as documented in
    :func:`sso._studies.tolerance_study.tolerance_study`.

    Raises
    ------
    ValueError
        If a sampled operating angle reaches 90 deg (the joint locks), or the angles
        the samples may reach are too close to 90 deg for float64 to resolve RE
        (:func:`sso._validation.check_chain_conditioning`).
    """
    generator = np.random.default_rng(seed)
    joints = series.n_joints
    if distribution == "normal":
        beta_offsets = generator.normal(0.0, beta_tolerance_deg, (samples, joints))
        phase_offsets = generator.normal(0.0, phase_tolerance_deg, (samples, joints - 1))
    else:
        beta_offsets = generator.uniform(-np.asarray(beta_tolerance_deg),
                                         beta_tolerance_deg, (samples, joints))
        phase_offsets = generator.uniform(-np.asarray(phase_tolerance_deg),
                                          phase_tolerance_deg, (samples, joints - 1))
    beta_deg = np.asarray(series.beta_deg) + beta_offsets
    reach = NORMAL_REACH_SIGMAS if distribution == "normal" else 1.0
    largest = np.asarray(series.beta_deg) + reach * np.asarray(beta_tolerance_deg)
    if np.any(np.abs(beta_deg) >= BETA_LIMIT_DEG) or np.any(largest >= BETA_LIMIT_DEG):
        joint = int(np.argmax(largest))
        raise ValueError(
            f"beta_tolerance_deg[{joint}] = {beta_tolerance_deg[joint]:g} deg lets joint "
            f"{joint} (beta {series.beta_deg[joint]:g} deg) reach 90 deg, where it locks; "
            f"the allowed range is beta + {reach:g} * tolerance < 90 deg")
    check_chain_conditioning(f"beta_tolerance_deg (the angles beta + {reach:g} * tolerance "
                             "that samples may reach)", largest.tolist())
    return beta_deg, np.asarray(series.phase_deg) + phase_offsets


def evaluate_chunk(chunk: ToleranceChunk) -> np.ndarray:
    """RE, fluctuation and peak output acceleration of each sample, shape (3, m).

    The exact model's three figures are closed forms of the chain matrix, one numpy
    pass over the samples with no angle grid; the paper model's are read off a grid
    and refined, as :meth:`sso.ShaftSeries.evaluate` does.
    """
    values = np.empty((len(METRICS), len(chunk.beta_rad)))
    if chunk.model == "exact":
        beta = list(chunk.beta_rad.T)
        phase = list(chunk.phase_rad.T)
        least, greatest = ratio_extremes(np, beta, phase)
        values[0] = closed_form_residual_error(np, beta, phase)
        values[1] = greatest - least
        values[2] = (chunk.input_speed_rpm * RPM_TO_RAD_S) ** 2 * peak_ratio_slope(np, beta,
                                                                                    phase)
        return values
    figure_samples = max(MIN_FIGURE_SAMPLES, 4 * chunk.quadrature_samples)
    step = block_samples(figure_samples)
    for start in range(0, len(chunk.beta_rad), step):
        block = slice(start, start + step)
        beta = [column[:, None] for column in chunk.beta_rad[block].T]
        phase = [column[:, None] for column in chunk.phase_rad[block].T]
        theta_rad = np.pi * np.arange(figure_samples) / figure_samples
        kinematics = chain_kinematics(np, np.cos(theta_rad), np.sin(theta_rad), beta, phase,
                                      chunk.model)
        ratio = kinematics.speed_ratio
        values[0, block] = residual_error(beta, phase, chunk.model, chunk.quadrature_samples)
        values[1, block] = periodic_peaks(ratio) + periodic_peaks(-ratio)
        ratio_slope = np.abs(ratio * kinematics.log_ratio_slope)
        values[2, block] = (chunk.input_speed_rpm * RPM_TO_RAD_S) ** 2 * periodic_peaks(ratio_slope)
    return values


def periodic_peaks(values: np.ndarray) -> np.ndarray:
    """Maximum of each row of a periodic sampled function, refined by a parabola.

    The row-wise form of the refinement :meth:`sso.ShaftSeries.evaluate` uses for the
    paper model, so both give the same figures.
    """
    rows = np.arange(values.shape[0])
    index = np.argmax(values, axis=1)
    left = values[rows, index - 1]
    centre = values[rows, index]
    right = values[rows, (index + 1) % values.shape[1]]
    curvature = left - 2.0 * centre + right
    concave = curvature < 0.0
    offset = np.divide(0.5 * (left - right), curvature, out=np.zeros_like(centre),
                       where=concave)
    peaks: np.ndarray = np.where(concave, centre - 0.25 * (left - right) * offset, centre)
    return peaks


def per_item_tolerances(field_name: str, value: Any, count: int) -> tuple[float, ...]:
    """One tolerance (deg, ``[0, MAX_TOLERANCE_DEG]``) for each of ``count`` angles.

    Raises
    ------
    ValueError
        Naming the field, when ``value`` is neither one number nor ``count`` of them, or
        an entry is out of range.
    """
    values = as_float_tuple(field_name, value)
    if len(values) == 1:
        values = values * count
    elif len(values) != count:
        raise ValueError(f"{field_name} has {len(values)} entries; give 1 or {count}")
    return tuple(check_in_range(f"{field_name}[{index}]", item, 0.0, MAX_TOLERANCE_DEG, "deg")
                 for index, item in enumerate(values))
