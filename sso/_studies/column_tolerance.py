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
The built columns are then judged against the limits given (a case's ``[limits]``):
the yield of each and of all together with its confidence interval, which tolerance
matters, and the largest one halved and re-sampled (:mod:`sso._studies.column_yields`).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

import sso._studies.column_tolerance_report  # noqa: F401  (registers "column_tolerance")
from sso._column.built_columns import built_angles
from sso._column.built_figures import BUILT_FIGURES, built_column_figures, limited_figures
from sso._column.chain_matrix import chain_matrix, matrix_residual_error
from sso._column.design import column_design
from sso._column.geometry import ColumnGeometry
from sso._column.sensitivity import FigureSensitivity
from sso._column.steering_criteria import SteeringLimits
from sso._column.steering_range import steering_range
from sso._column.tolerances import Tolerances, drawn_errors
from sso._column.yields import YieldJudgement, column_limits
from sso._display import Part, Readable, TextTable, format_number, format_numbers
from sso._files import check_report_folder
from sso._limits import (
    DEFAULT_CHUNK_SAMPLES,
    DEFAULT_COLUMN_STUDY_SAMPLES,
    DEFAULT_HARDPOINT_TOLERANCE_MM,
    DEFAULT_LOCK_DEG,
    DEFAULT_STRAIGHT_AHEAD_DEG,
    DEFAULT_YOKE_PHASE_TOLERANCE_DEG,
    MAX_COLUMN_SAMPLES,
    OUTPUT_FORMATS,
)
from sso._progress import ProgressBar, interactive
from sso._record import Record, encode
from sso._reports.kinds import write_report
from sso._resources import check_memory
from sso._studies.column_yields import HalvedTolerance, judge_study
from sso._studies.column_yields_report import yield_parts
from sso._studies.estimate import tolerance_estimate
from sso._studies.execution import run_tasks, validate_workers
from sso._studies.report import TOLERANCE_FOLDER
from sso._studies.results import SampledFigures
from sso._studies.saved_samples import (
    EXTRA_SCHEMA,
    check_summary,
    read_saved_fields,
    saved_field_names,
)
from sso._validation import (
    as_float_tuple,
    check_in_range,
    finite_float,
    finite_in_range,
    validate_count,
)

COLUMN_METRICS = BUILT_FIGURES
COLUMN_SAMPLE_FIELDS = ("beta_deg", "plane_angle_deg", "yoke_phase_error_deg", *COLUMN_METRICS)
"""The per-sample arrays of a column's study, kept in its table, not its record."""
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
    return built_column_figures(chunk.beta_rad, chunk.phase_rad, chunk.straight_ahead_deg,
                                chunk.lock_deg)


@dataclass(frozen=True)
class BuiltSample:
    """Built columns to evaluate: their hardpoints (mm), design phasing and phase errors
    (deg), and the steering range (deg)."""

    points_mm: np.ndarray
    yoke_phase_deg: np.ndarray
    phase_errors_deg: np.ndarray
    straight_ahead_deg: float
    lock_deg: float


def built_figures(sample: BuiltSample, hardpoint_mm: float, chunk_size: int, client: Any,
                  workers: int, advance: Callable[[int], None]
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Operating angles, bend-plane angles (deg) and the figures of
    :data:`COLUMN_METRICS` ``(4, samples)`` of built columns, evaluated in chunks.

    Raises
    ------
    ValueError
        If a built column is not a column (``hardpoint_mm`` too large for it).
    RuntimeError
        If a chunk fails.
    """
    try:
        beta_deg, gamma_deg = built_angles(sample.points_mm)
    except ValueError as refused:
        raise ValueError(f"hardpoint_mm = {hardpoint_mm:g} mm is too large for this "
                         f"column: {refused}") from None
    phase_rad = np.radians(90.0 + sample.yoke_phase_deg + sample.phase_errors_deg - gamma_deg)
    beta_rad = np.radians(beta_deg)
    count = len(beta_rad)
    chunks = [ColumnChunk(beta_rad[start:start + chunk_size], phase_rad[start:start + chunk_size],
                          sample.straight_ahead_deg, sample.lock_deg)
              for start in range(0, count, chunk_size)]
    figures = np.empty((len(COLUMN_METRICS), count))
    for index, values, error in run_tasks(evaluate_column_chunk, chunks, client, workers):
        if error is not None:
            raise RuntimeError(f"column tolerance study: chunk {index} failed: "
                               f"{error}") from error
        figures[:, index * chunk_size:index * chunk_size + values.shape[1]] = values
        advance(values.shape[1])
    return beta_deg, gamma_deg, figures


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
    yields : YieldJudgement or None
        The yield of each limit and of all together, with its interval and the verdict
        against the required yield (:mod:`sso._studies.column_yields`).
    sensitivity : tuple of FigureSensitivity
        Each failed limit's figure: the first-order index of every tolerance, ranked.
    halved : tuple of HalvedTolerance
        The yields re-sampled with each figure's largest contributor halved.
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
    yields: YieldJudgement | None = None
    sensitivity: tuple[FigureSensitivity, ...] = ()
    halved: tuple[HalvedTolerance, ...] = ()

    report_kind: ClassVar[str] = "column_tolerance"
    _metrics: ClassVar[tuple[str, ...]] = COLUMN_METRICS

    def _record_save(self) -> dict[str, Any]:
        """The saved form (``result.json``): every field but the per-sample arrays, the
        number of samples and their summary; the samples are in ``tolerance.csv`` and
        are drawn again from the seed on reading (:meth:`_record_load`)."""
        saved = {name: encode(getattr(self, name))
                 for name in saved_field_names(type(self), COLUMN_SAMPLE_FIELDS)}
        return {**saved, "samples": self.samples, "summary": self._sample_summary()}

    @classmethod
    def _record_fields_saved(cls) -> tuple[list[str], dict[str, Any]]:
        """The saved form's fields of the class and the others (with their schema)."""
        return saved_field_names(cls, COLUMN_SAMPLE_FIELDS), EXTRA_SCHEMA

    @classmethod
    def _record_load(cls, saved: Mapping[str, Any], where: str) -> ColumnToleranceResult:
        """A saved study read back: its built columns drawn and evaluated again from its
        column, tolerances and seed, its nominal figures computed again, and the saved
        summary and nominal figures checked against them.

        Raises
        ------
        ValueError
            Naming the field missing, unknown, out of range, or not that of the
            samples drawn again (beyond ``1e-14 + 1e-6 * |figure|``).
        """
        names, extra = cls._record_fields_saved()
        arguments = read_saved_fields(cls, saved, names, tuple(extra), where)
        count = validate_count("samples", saved["samples"], 1, MAX_COLUMN_SAMPLES)
        tolerances = Tolerances(hardpoint_mm=arguments["hardpoint_mm"],
                                yoke_phase_deg=arguments["yoke_phase_tolerance_deg"],
                                seed=arguments["seed"], distribution=arguments["distribution"])
        geometry, yoke = arguments["geometry"], arguments["yoke_phase_deg"]
        check_memory(tolerance_estimate(count, 2 * geometry.joint_count + 3, 1, 1), None)
        check_summary(arguments["nominal"],
                      nominal_figures(geometry, yoke, arguments["straight_ahead_deg"],
                                      arguments["lock_deg"]), f"{where}.nominal",
                      "the nominal column, computed again")
        offsets, phase_errors = drawn_errors(geometry, tolerances, count)
        beta_deg, gamma_deg, figures = built_figures(
            BuiltSample(np.asarray(geometry.points_mm) + offsets, np.asarray(yoke), phase_errors,
                        arguments["straight_ahead_deg"], arguments["lock_deg"]),
            tolerances.hardpoint_mm, DEFAULT_CHUNK_SAMPLES, None, 1, lambda done: None)
        made = cls(**arguments, beta_deg=beta_deg, plane_angle_deg=gamma_deg,
                   yoke_phase_error_deg=phase_errors, residual_error=figures[0],
                   speed_fluctuation_percent=figures[1], torque_fluctuation_percent=figures[2],
                   largest_transmission_error_deg=figures[3])
        check_summary(saved["summary"], made._sample_summary(), f"{where}.summary")
        if made.yields is not None:
            check_judgement(made, tolerances, offsets, f"{where}.yields")
        return made

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
            *yield_parts(self),
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
    limits: SteeringLimits | None = None,
    required_yield: float | None = None,
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
    limits : sso.SteeringLimits, optional
        The limits the built columns are judged against (default: the largest
        operating angle only, 35 deg): the yield of each and of all together, and
        the sensitivity of each figure some built column fails
        (:mod:`sso._studies.column_yields`).
    required_yield : float, optional
        The yield of all limits together the design must show, in ``(0, 1]``; None
        reports the yields without a verdict.

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
    limits = SteeringLimits() if limits is None else limits
    if not isinstance(limits, SteeringLimits):
        raise TypeError(f"limits must be an sso.SteeringLimits, not {type(limits).__name__}")
    if required_yield is not None:
        required_yield = finite_in_range("required_yield", required_yield, 0.0, 1.0,
                                         lower_open=True)
    nominal_range = steering_range((geometry, yoke), lock_deg=lock_deg,
                                   straight_ahead_deg=straight_ahead_deg)
    if out_dir is not None:
        out_dir = check_report_folder(out_dir, TOLERANCE_FOLDER)
    worker_count = validate_workers(workers)
    check_memory(tolerance_estimate(count, 2 * geometry.joint_count + 3, 1,
                                    worker_count if client is None else 1), memory_limit_mb)

    points = np.asarray(geometry.points_mm)
    offsets, phase_errors = drawn_errors(geometry, tolerances, count)
    centre = finite_float("straight_ahead_deg", straight_ahead_deg)
    bar = ProgressBar(count, "samples", interactive() if progress is None else progress)

    def evaluate(offsets_mm: np.ndarray, phase_errors_deg: np.ndarray,
                 advance: Callable[[int], None]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return built_figures(BuiltSample(points + offsets_mm, np.asarray(yoke),
                                         phase_errors_deg, centre, nominal_range.lock_deg),
                             tolerances.hardpoint_mm, chunk_size, client, worker_count, advance)

    def limited(offsets_mm: np.ndarray, phase_errors_deg: np.ndarray) -> dict[str, np.ndarray]:
        again = ProgressBar(count, "samples, a tolerance halved",
                            interactive() if progress is None else progress)
        try:
            return built_limited_figures(
                BuiltSample(points + offsets_mm, np.asarray(yoke), phase_errors_deg, centre,
                            nominal_range.lock_deg),
                tolerances.hardpoint_mm, chunk_size, client, worker_count, again.advance)
        finally:
            again.close()

    try:
        beta_deg, gamma_deg, figures = evaluate(offsets, phase_errors, bar.advance)
    finally:
        bar.close()
    judged = judge_study(offsets, phase_errors, limited_figures(beta_deg, figures),
                         column_limits(limits), required_yield, tolerances.hardpoint_mm,
                         tolerances.yoke_phase_deg, limited)
    nominal = nominal_figures(geometry, yoke, centre, nominal_range.lock_deg)
    result = ColumnToleranceResult(
        geometry=geometry, yoke_phase_deg=yoke, hardpoint_mm=tolerances.hardpoint_mm,
        yoke_phase_tolerance_deg=tolerances.yoke_phase_deg,
        distribution=tolerances.distribution, seed=tolerances.seed,
        straight_ahead_deg=centre, lock_deg=nominal_range.lock_deg, percentiles=quantiles,
        nominal=nominal, beta_deg=beta_deg, plane_angle_deg=gamma_deg,
        yoke_phase_error_deg=phase_errors, residual_error=figures[0],
        speed_fluctuation_percent=figures[1], torque_fluctuation_percent=figures[2],
        largest_transmission_error_deg=figures[3], elapsed_s=time.perf_counter() - started,
        study_of=study_of, yields=judged.yields, sensitivity=judged.sensitivity,
        halved=judged.halved)
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



def built_limited_figures(sample: BuiltSample, hardpoint_mm: float, chunk_size: int,
                          client: Any, workers: int, advance: Callable[[int], None]
                          ) -> dict[str, np.ndarray]:
    """The limited figures (:func:`sso._column.built_figures.limited_figures`) of the built
    columns of ``sample``: what the yields, the sensitivity and a halved tolerance are
    judged on, in a study and when a saved study is checked again."""
    beta_deg, _, figures = built_figures(sample, hardpoint_mm, chunk_size, client, workers,
                                         advance)
    return limited_figures(beta_deg, figures)

def check_judgement(study: ColumnToleranceResult, tolerances: Tolerances,
                    offsets_mm: np.ndarray, where: str) -> None:
    """Check a saved study's yields, sensitivity and halved tolerances against the same
    judgement made again on its samples drawn again (the same limits and required
    yield).

    Raises
    ------
    ValueError
        Naming the field whose saved value is not the one computed again.
    """
    assert study.yields is not None
    points = np.asarray(study.geometry.points_mm)
    yoke = np.asarray(study.yoke_phase_deg)

    def limited(offsets: np.ndarray, phase_errors: np.ndarray) -> dict[str, np.ndarray]:
        return built_limited_figures(
            BuiltSample(points + offsets, yoke, phase_errors, study.straight_ahead_deg,
                        study.lock_deg),
            tolerances.hardpoint_mm, DEFAULT_CHUNK_SAMPLES, None, 1, lambda done: None)

    limits = tuple((item.figure, item.label, item.unit, item.limit)
                   for item in study.yields.limits if item.limit is not None)
    again = judge_study(offsets_mm, study.yoke_phase_error_deg,
                        limited_figures(study.beta_deg, np.stack(
                            [getattr(study, name) for name in COLUMN_METRICS])),
                        limits, study.yields.required, tolerances.hardpoint_mm,
                        tolerances.yoke_phase_deg, limited)
    for name in ("yields", "sensitivity", "halved"):
        if getattr(again, name) != getattr(study, name):
            raise ValueError(f"{where.rsplit('.', 1)[0]}.{name}: the saved value is not the "
                             "one computed again from the study's samples drawn again")


def nominal_figures(geometry: ColumnGeometry, yoke_phase_deg: Sequence[float],
                    straight_ahead_deg: float, lock_deg: float) -> dict[str, float]:
    """The figures of :data:`COLUMN_METRICS` of the nominal column."""
    steering = steering_range((geometry, yoke_phase_deg), lock_deg=lock_deg,
                              straight_ahead_deg=straight_ahead_deg)
    return {"residual_error": float(matrix_residual_error(chain_matrix(
        np.radians(geometry.beta_deg), np.radians(geometry.phase_deg_from_yoke(yoke_phase_deg))))),
        "speed_fluctuation_percent": steering.speed_fluctuation_percent,
        "torque_fluctuation_percent": steering.torque_fluctuation_percent,
        "largest_transmission_error_deg": steering.largest_transmission_error_deg}
