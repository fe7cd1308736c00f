"""Monte Carlo tolerance study of a steering column: hardpoints (mm) and yoke phasing (deg).

Every sample is one built column: each coordinate of each hardpoint ``P0 .. P(n+1)``
moved by a draw (mm), and each yoke phasing ``delta_k`` by another (deg), drawn as
:meth:`sso.Tolerances.sample` draws them (``numpy.random.default_rng(seed)``: the
hardpoint errors, shape ``(samples, n + 2, 3)``, then the phase errors, shape
``(samples, n - 1)``; normal with the tolerance as standard deviation, or uniform
with it as half-width). A built column runs at ``phi = 90 + delta + error - gamma``
with its own operating and bend-plane angles (:mod:`sso._column.built_columns`), so the
study reports what production would see: RE, and the steering figures from lock to
lock (:func:`sso.steering_range`'s speed and torque fluctuation and largest
transmission error; the input angle measured, as there, from each built column's
first bend-plane normal).

The draw and the angles are computed once in the calling process (a sample that is no
column is bad input: the tolerance is too large for this column); the chain matrices
and the figures in chunks, on local processes or a Dask cluster
(:func:`sso._studies.execution.run_tasks`), so the numbers do not depend on the chunking.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

import sso._studies.column_tolerance_report  # noqa: F401  (registers "column_tolerance")
from sso._column.built_columns import built_angles
from sso._column.chain_matrix import chain_matrix, matrix_residual_error
from sso._column.design import column_design
from sso._column.geometry import ColumnGeometry
from sso._column.steering_range import range_extremes, steering_range
from sso._column.tolerances import Tolerances, draw_errors
from sso._display import Part, Readable, TextTable, format_number, format_numbers
from sso._files import check_report_folder
from sso._limits import (
    DEFAULT_CHUNK_SAMPLES,
    DEFAULT_COLUMN_STUDY_SAMPLES,
    DEFAULT_HARDPOINT_TOLERANCE_MM,
    DEFAULT_LOCK_DEG,
    DEFAULT_STRAIGHT_AHEAD_DEG,
    DEFAULT_YOKE_PHASE_TOLERANCE_DEG,
    OUTPUT_FORMATS,
)
from sso._record import Record
from sso._reports.kinds import write_report
from sso._solvers.progress import ProgressBar, interactive
from sso._solvers.resources import check_memory
from sso._studies.estimate import tolerance_estimate
from sso._studies.execution import run_tasks, validate_workers
from sso._studies.report import TOLERANCE_FOLDER
from sso._studies.results import SampledFigures
from sso._validation import as_float_tuple, check_in_range, finite_float, validate_count

MAX_COLUMN_SAMPLES = 2_000_000
"""Most samples of a column study (its hardpoint draws take 8 (3 n + 6) bytes each)."""
COLUMN_METRICS = ("residual_error", "speed_fluctuation_percent", "torque_fluctuation_percent",
                  "largest_transmission_error_deg")
METRIC_LABELS = {
    "residual_error": "residual error RE (dimensionless)",
    "speed_fluctuation_percent": "speed-ratio fluctuation, lock to lock (%)",
    "torque_fluctuation_percent": "output-torque fluctuation, lock to lock (%)",
    "largest_transmission_error_deg": "largest |transmission error|, lock to lock (deg)",
}
DEFAULT_COLUMN_PERCENTILES = (5.0, 50.0, 95.0, 99.0)


@dataclass(frozen=True)
class ColumnChunk:
    """Samples to evaluate: their angles (rad) and the steering range (deg)."""

    beta_rad: np.ndarray
    phase_rad: np.ndarray
    straight_ahead_deg: float
    lock_deg: float


def evaluate_column_chunk(chunk: ColumnChunk) -> np.ndarray:
    """The figures of :data:`COLUMN_METRICS` of every sample, shape ``(4, samples)``."""
    matrices = chain_matrix(chunk.beta_rad, chunk.phase_rad)
    figures = np.empty((len(COLUMN_METRICS), len(matrices)))
    figures[0] = matrix_residual_error(matrices)
    for index, matrix in enumerate(matrices):
        ratio_low, ratio_high, error_low, error_high = range_extremes(
            matrix, chunk.straight_ahead_deg, chunk.lock_deg)
        figures[1, index] = 100.0 * (ratio_high - ratio_low)
        figures[2, index] = 100.0 * (1.0 / ratio_low - 1.0 / ratio_high)
        figures[3, index] = max(-error_low, error_high)
    return figures


@dataclass(frozen=True, repr=False, eq=False)
class ColumnToleranceResult(SampledFigures, Record, Readable):
    """A Monte Carlo tolerance study of one column design.

    Attributes
    ----------
    geometry : sso.ColumnGeometry
        The nominal column.
    yoke_phase_deg : tuple of float
        Its yoke phasing, deg.
    hardpoint_mm, yoke_phase_tolerance_deg : float
        Tolerance of every hardpoint coordinate (mm) and of each yoke phasing (deg):
        the standard deviation (normal) or half-width (uniform).
    distribution : {"normal", "uniform"}
    seed : int
    straight_ahead_deg, lock_deg : float
        The steering range of the figures (:func:`sso.steering_range`), deg.
    percentiles : tuple of float
        Which percentiles :meth:`percentile_table` reports, percent.
    nominal : dict of str to float
        The figures of :data:`COLUMN_METRICS` of the nominal design.
    beta_deg, plane_angle_deg, yoke_phase_error_deg : numpy.ndarray
        Each built column's operating angles ``(samples, n)``, bend-plane angles
        ``(samples, n - 1)`` and yoke phase errors ``(samples, n - 1)``, deg.
    residual_error, speed_fluctuation_percent, torque_fluctuation_percent,
    largest_transmission_error_deg : numpy.ndarray
        Each sample's figures (dimensionless, %, %, deg).
    elapsed_s : float
        Wall time, s.
    files : tuple of pathlib.Path
        Files written.
    study_of : str
        Which design was studied, in words.
    """

    geometry: ColumnGeometry
    yoke_phase_deg: tuple[float, ...]
    hardpoint_mm: float
    yoke_phase_tolerance_deg: float
    distribution: str
    seed: int
    straight_ahead_deg: float
    lock_deg: float
    percentiles: tuple[float, ...]
    nominal: dict[str, float]
    beta_deg: np.ndarray
    plane_angle_deg: np.ndarray
    yoke_phase_error_deg: np.ndarray
    residual_error: np.ndarray
    speed_fluctuation_percent: np.ndarray
    torque_fluctuation_percent: np.ndarray
    largest_transmission_error_deg: np.ndarray
    elapsed_s: float
    files: tuple[Path, ...] = field(default=())
    study_of: str = "the given design"

    report_kind: ClassVar[str] = "column_tolerance"
    _metrics: ClassVar[tuple[str, ...]] = COLUMN_METRICS

    def _repr_text(self) -> str:
        cells = ", ".join(f"p{q:g} {format_number(value, 3)}"
                          for q, value in self.percentile_table()["residual_error"].items())
        return (f"{self.samples} {self.distribution} built columns of {self.study_of}: RE "
                f"nominal {format_number(self.nominal['residual_error'], 3)}; {cells}")

    def _summary_parts(self) -> list[Part]:
        spread = "standard deviation" if self.distribution == "normal" else "half-width"
        rows = tuple((METRIC_LABELS[metric], format_number(self.nominal[metric]),
                      *(format_number(value) for value in values.values()))
                     for metric, values in self.percentile_table().items())
        return [
            f"column tolerance study: {self.samples} built columns ({self.distribution}, seed "
            f"{self.seed}) in {self.elapsed_s:.2f} s",
            f"  design studied: {self.study_of}: yoke phasing "
            f"[{format_numbers(self.yoke_phase_deg)}] deg, operating angles "
            f"[{format_numbers(self.geometry.beta_deg)}] deg",
            f"  errors ({spread}): every hardpoint coordinate {format_number(self.hardpoint_mm)}"
            f" mm, each yoke phasing {format_number(self.yoke_phase_tolerance_deg)} deg",
            f"  steering range: +-{format_number(self.lock_deg)} deg from straight ahead "
            f"(input angle {format_number(self.straight_ahead_deg)} deg)",
            TextTable(("figure", "nominal", *(f"p{q:g}" for q in self.percentiles)), rows),
        ]


def column_tolerance_study(
    design: Any,
    tolerances: Tolerances,
    *,
    samples: int | None = None,
    lock_deg: float = DEFAULT_LOCK_DEG,
    straight_ahead_deg: float = DEFAULT_STRAIGHT_AHEAD_DEG,
    percentiles: Sequence[float] | None = None,
    study_of: str = "the given design",
    out_dir: str | Path | None = None,
    client: Any = None,
    workers: int | None = None,
    chunk_size: int = DEFAULT_CHUNK_SAMPLES,
    progress: bool | None = None,
    plots: bool = True,
    memory_limit_mb: float | None = None,
) -> ColumnToleranceResult:
    """Monte Carlo study of a column design under hardpoint and yoke-phasing tolerances.

    Parameters
    ----------
    design : (ColumnGeometry, sequence of float) or result
        The column and its yoke phasing (deg), or a result with ``geometry`` and
        ``yoke_phase_deg``.
    tolerances : sso.Tolerances
        Hardpoint (mm) and yoke-phasing (deg) tolerances, distribution and seed; its
        ``samples`` unless ``samples`` is given.
    samples : int, optional
        Built columns drawn, ``1..2e6``.
    lock_deg, straight_ahead_deg : float
        The steering range of the figures (as :func:`sso.steering_range`), deg.
    percentiles : sequence of float, optional
        Percentiles to report, each in ``[0, 100]`` (default 5, 50, 95, 99).
    study_of : str
        Which design this is, in words, for the report.
    out_dir, client, workers, chunk_size, progress, plots, memory_limit_mb
        As :func:`sso.tolerance_study`.

    Raises
    ------
    ValueError
        Naming the field and its allowed range; or if a drawn column is not a column
        (the hardpoint tolerance is too large for it).
    """
    started = time.perf_counter()
    geometry, yoke = column_design(design)
    if not isinstance(tolerances, Tolerances):
        raise TypeError(f"tolerances must be an sso.Tolerances, not {type(tolerances).__name__}")
    count = validate_count("samples", tolerances.samples if samples is None else samples, 1,
                           MAX_COLUMN_SAMPLES)
    chunk_size = validate_count("chunk_size", chunk_size, 1, MAX_COLUMN_SAMPLES)
    quantiles = tuple(check_in_range(f"percentiles[{index}]", value, 0.0, 100.0)
                      for index, value in enumerate(as_float_tuple(
                          "percentiles", DEFAULT_COLUMN_PERCENTILES if percentiles is None
                          else percentiles)))
    if not quantiles:
        raise ValueError("percentiles is empty: give one or more values in [0, 100]")
    nominal_range = steering_range((geometry, yoke), lock_deg=lock_deg,
                                   straight_ahead_deg=straight_ahead_deg)
    if out_dir is not None:
        out_dir = check_report_folder(out_dir, TOLERANCE_FOLDER)
    worker_count = validate_workers(workers)
    check_memory(tolerance_estimate(count, 2 * geometry.joint_count + 3, 1,
                                    worker_count if client is None else 1), memory_limit_mb)

    rng = np.random.default_rng(tolerances.seed)
    points = np.asarray(geometry.points_mm)
    offsets = draw_errors(rng, tolerances.hardpoint_mm, tolerances.distribution,
                          (count, *points.shape))
    phase_errors = draw_errors(rng, tolerances.yoke_phase_deg, tolerances.distribution,
                               (count, geometry.joint_count - 1))
    try:
        beta_deg, gamma_deg = built_angles(points + offsets)
    except ValueError as refused:
        raise ValueError(f"hardpoint_mm = {tolerances.hardpoint_mm:g} mm is too large for this "
                         f"column: {refused}") from None
    phase_rad = np.radians(90.0 + np.asarray(yoke) + phase_errors - gamma_deg)
    beta_rad = np.radians(beta_deg)
    centre = finite_float("straight_ahead_deg", straight_ahead_deg)
    chunks = [ColumnChunk(beta_rad[start:start + chunk_size], phase_rad[start:start + chunk_size],
                          centre, nominal_range.lock_deg)
              for start in range(0, count, chunk_size)]
    figures = np.empty((len(COLUMN_METRICS), count))
    bar = ProgressBar(count, "samples", interactive() if progress is None else progress)
    try:
        for index, values, error in run_tasks(evaluate_column_chunk, chunks, client,
                                              worker_count):
            if error is not None:
                raise RuntimeError(f"column tolerance study: chunk {index} failed: "
                                   f"{error}") from error
            figures[:, index * chunk_size:index * chunk_size + values.shape[1]] = values
            bar.advance(values.shape[1])
    finally:
        bar.close()
    nominal = {"residual_error": float(matrix_residual_error(chain_matrix(
        np.radians(geometry.beta_deg), np.radians(geometry.phase_deg_from_yoke(yoke))))),
        "speed_fluctuation_percent": nominal_range.speed_fluctuation_percent,
        "torque_fluctuation_percent": nominal_range.torque_fluctuation_percent,
        "largest_transmission_error_deg": nominal_range.largest_transmission_error_deg}
    result = ColumnToleranceResult(
        geometry=geometry, yoke_phase_deg=yoke, hardpoint_mm=tolerances.hardpoint_mm,
        yoke_phase_tolerance_deg=tolerances.yoke_phase_deg,
        distribution=tolerances.distribution, seed=tolerances.seed,
        straight_ahead_deg=centre, lock_deg=nominal_range.lock_deg, percentiles=quantiles,
        nominal=nominal, beta_deg=beta_deg, plane_angle_deg=gamma_deg,
        yoke_phase_error_deg=phase_errors, residual_error=figures[0],
        speed_fluctuation_percent=figures[1], torque_fluctuation_percent=figures[2],
        largest_transmission_error_deg=figures[3], elapsed_s=time.perf_counter() - started,
        study_of=study_of)
    if out_dir is None:
        return result
    formats = tuple(name for name in OUTPUT_FORMATS if plots or name != "png")
    return replace(result, files=tuple(write_report(result, out_dir, formats)))


def is_column_design(design: Any) -> bool:
    """Whether ``design`` is a column design (not a case): ``(geometry, phasing)`` or a
    result holding a column's ``geometry``."""
    return ((isinstance(design, tuple) and len(design) == 2
             and isinstance(design[0], ColumnGeometry))
            or isinstance(getattr(design, "geometry", None), ColumnGeometry))


def study_settings(tolerances: Tolerances | None, case: Any, samples: int | None,
                   seed: int | None, distribution: str | None) -> tuple[Tolerances, int]:
    """The tolerances and sample count of a column study, from what is given.

    The tolerances are ``tolerances``, else the case's ``[tolerances]``, else
    :data:`sso._limits.DEFAULT_HARDPOINT_TOLERANCE_MM` and
    :data:`sso._limits.DEFAULT_YOKE_PHASE_TOLERANCE_DEG` (normal, seed 0); ``seed`` and
    ``distribution`` replace theirs. The count is ``samples``, else that of the
    tolerances given (or of the case's table), else
    :data:`sso._limits.DEFAULT_COLUMN_STUDY_SAMPLES`.

    Raises
    ------
    ValueError
        Naming the field, for a bad seed or distribution.
    """
    chosen = tolerances if tolerances is not None else (
        None if case is None else case.tolerances())
    count = samples if samples is not None else (
        chosen.samples if chosen is not None else DEFAULT_COLUMN_STUDY_SAMPLES)
    if chosen is None:
        chosen = Tolerances(hardpoint_mm=DEFAULT_HARDPOINT_TOLERANCE_MM,
                            yoke_phase_deg=DEFAULT_YOKE_PHASE_TOLERANCE_DEG)
    changes = {name: value for name, value in (("seed", seed), ("distribution", distribution))
               if value is not None}
    return (replace(chosen, **changes) if changes else chosen), count
