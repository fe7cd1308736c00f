"""What a sweep and a tolerance study return: :class:`SweepResult`, :class:`ToleranceResult`.

Kept apart from the code that computes them, so the report writers
(:mod:`sso._studies.report`) and the studies (:mod:`sso._studies.sweep`,
:mod:`sso._studies.tolerance_study`) both import them without a circle.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from importlib import import_module
from pathlib import Path
from typing import Any, ClassVar, overload

import numpy as np

import sso._studies.report  # noqa: F401  (registers the "sweep" and "tolerance" report kinds)
from sso._display import Part, Readable, TextTable, format_number, format_numbers
from sso._limits import ROUND_OFF_FLOOR
from sso._record import Record, RecordError, encode
from sso._shafts.evaluation import Evaluation
from sso._shafts.perturbed import METRICS
from sso._shafts.series import ShaftSeries
from sso._studies.axes import Axis
from sso._studies.columns import RowTable
from sso._studies.element_columns import gathered
from sso._studies.parquet_output import PARQUET_NAME, read_frame
from sso._studies.saved_samples import (
    EXTRA_SCHEMA,
    SHAFT_SAMPLE_FIELDS,
    check_summary,
    read_saved_fields,
    saved_field_names,
)
from sso._studies.table import CSV_NAME
from sso._studies.tolerance_samples import redrawn_samples
from sso._validation import shown


class SweepRows(Sequence[dict[str, Any]]):
    """A sweep's rows, sorted by point, held as columns: each row is made a dict only
    when it is read (a sweep of a million points holds no million dicts).

    Parameters
    ----------
    table : sso._studies.columns.RowTable
        The rows, sorted by point.
    """

    def __init__(self, table: RowTable) -> None:
        self.table = table

    def __len__(self) -> int:
        return self.table.length

    @overload
    def __getitem__(self, index: int) -> dict[str, Any]: ...

    @overload
    def __getitem__(self, index: slice) -> list[dict[str, Any]]: ...

    def __getitem__(self, index: int | slice) -> dict[str, Any] | list[dict[str, Any]]:
        if isinstance(index, slice):
            return [self.table.row(position) for position in range(len(self))[index]]
        position = range(len(self))[index]  # negative indices; IndexError past the end
        return self.table.row(position)

    def __iter__(self) -> Iterator[dict[str, Any]]:
        return self.table.rows()

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Sequence):
            return NotImplemented
        return len(self) == len(other) and all(
            mine == theirs for mine, theirs in zip(self, other, strict=True))

    __hash__ = None  # type: ignore[assignment]  # mutable-looking sequence: no hash

    def __repr__(self) -> str:
        return f"<{len(self)} sweep rows>"

    def column(self, name: str) -> np.ndarray:
        """Column ``name`` as an array (numbers where every cell is one, else objects)."""
        column = self.table.columns.get(name)
        if column is None or column.ndim != 1:
            return self.table.object_column(name)
        return column


@dataclass(frozen=True, eq=False, repr=False)
class SweepResult(Record, Readable):
    """What a sweep computed, one row per point.

    Attributes
    ----------
    axes : tuple of Axis
        The varied keys and their values.
    mode : {"product", "listed"}
    action : {"optimise", "evaluate"}
    rows : sequence of dict
        One row per point, sorted by point index, with the columns of
        ``sweep.csv`` (numbers and booleans parsed back; a list one column per
        element, ``design_beta_deg[0]``, ...). A sweep gives a
        :class:`SweepRows`, which holds them as columns (:meth:`frame` is a
        ``pandas.DataFrame`` of them).
    computed : int
        Points computed by this run.
    resumed : int
        Points taken over from an earlier run (``resume=True``).
    elapsed_s : float
        Wall time of this run, s.
    out_dir : pathlib.Path or None
        Where ``sweep.csv``, ``sweep.json`` and the report were written.
    files : tuple of pathlib.Path
        Files written.
    manifest : dict
        What the sweep is (``sweep.json``): base case, axes, mode, action, points.
    """

    axes: tuple[Axis, ...]
    mode: str
    action: str
    rows: Sequence[dict[str, Any]]
    computed: int
    resumed: int
    elapsed_s: float
    out_dir: Path | None = None
    files: tuple[Path, ...] = field(default=())
    manifest: dict[str, Any] = field(default_factory=dict)

    report_kind: ClassVar[str] = "sweep"

    def column(self, name: str) -> np.ndarray:
        """Column ``name`` of every row, in point order: numbers where every cell is one
        (a float column's NaN: an empty cell), else Python values (``None``: empty).

        Read from the columns a sweep holds, never row by row.
        """
        if isinstance(self.rows, SweepRows):
            return self.rows.column(name)
        column = np.empty(len(self.rows), dtype=object)
        column[:] = [row.get(name) for row in self.rows]
        return column

    def numbers(self, name: str) -> np.ndarray:
        """Column ``name`` as floats (NaN where a cell is empty or not a number)."""
        column = self.column(name)
        if column.dtype.kind in "fiu":
            return column.astype(float, copy=False)
        return np.array([value if isinstance(value, (int, float))
                         and not isinstance(value, bool) else np.nan
                         for value in column.tolist()], dtype=float)

    def failed_points(self) -> np.ndarray:
        """Positions (in :attr:`rows`) of the points that did not give a result."""
        return np.flatnonzero(self.column("status") != "ok")

    @property
    def failed(self) -> tuple[dict[str, Any], ...]:
        """Rows of the points that did not give a result."""
        return tuple(self.rows[int(index)] for index in self.failed_points())

    def lowest_re_order(self) -> np.ndarray:
        """Positions of every point: the finished ones by residual error, lowest first,
        then the failed ones; an empty RE counts as 0 and ties keep point order. RE at
        or below :data:`sso._limits.ROUND_OFF_FLOOR` ties (the same exact cancellation,
        whatever its round-off)."""
        errors = np.maximum(self.numbers("residual_error"), ROUND_OFF_FLOOR)
        return np.lexsort((np.where(np.isnan(errors), 0.0, errors),
                           self.column("status") != "ok"))

    @property
    def best(self) -> dict[str, Any] | None:
        """Row with the lowest residual error, or None if every point failed."""
        finished = np.flatnonzero(self.column("status") == "ok")
        if not len(finished):
            return None
        # Exact cancellations tie (the first point wins), as in lowest_re_order.
        errors = np.maximum(self.numbers("residual_error")[finished], ROUND_OFF_FLOOR)
        return self.rows[int(finished[np.nanargmin(errors) if np.isfinite(errors).any() else 0])]

    @property
    def success(self) -> bool:
        """Every point finished; when optimising, each converged and cross-checked."""
        return (not np.any(self.column("status") != "ok")
                and not any(value is False for value in self.column("success").tolist()))

    def frame(self) -> Any:
        """The rows as a ``pandas.DataFrame``, one column per column of ``sweep.csv``.

        Read from ``sweep.parquet`` when the sweep wrote it, else from the rows.

        Raises
        ------
        ImportError
            If pandas is not installed (the ``parquet`` extra installs it).
        """
        try:
            pandas = import_module("pandas")
        except ImportError:
            raise ImportError("SweepResult.frame needs pandas; install the 'parquet' extra "
                              "(pip install 'sso[parquet]')") from None
        if self.out_dir is not None and (self.out_dir / PARQUET_NAME).is_dir():
            return read_frame(self.out_dir)  # loaded only now, from the disk
        header = list(self.rows[0]) if len(self.rows) else []
        if isinstance(self.rows, SweepRows):
            table = self.rows.table
            data = {name: (table.columns[name] if name in table.columns
                           and table.columns[name].ndim == 1
                           else table.object_column(name)) for name in table.header}
            return pandas.DataFrame(data, columns=list(table.header))
        return pandas.DataFrame(list(self.rows), columns=header)

    def _repr_text(self) -> str:
        axes = " x ".join(f"{axis.path} ({len(axis.values)})" for axis in self.axes)
        best = self.best
        lowest = ("" if best is None else f", lowest RE {format_number(best['residual_error'], 4)}"
                  f" at point {best['point']}")
        return (f"{self.action} {self.mode} over {axes}: {len(self.rows)} points, "
                f"{len(self.failed_points())} failed{lowest}")

    def _summary_parts(self) -> list[Part]:
        rate = self.computed / self.elapsed_s if self.elapsed_s > 0 else 0.0
        failed = self.failed_points()
        headline = (f"sweep: {len(self.rows)} points ({self.computed} computed in "
                    f"{self.elapsed_s:.1f} s, {rate:.1f} points/s; {self.resumed} from an "
                    f"earlier run), {len(failed)} failed")
        parts: list[Part] = [headline]
        if self.action == "optimise":
            unconverged = sum(value is False for value in self.column("success").tolist())
            parts.append(f"  not converged or solvers disagree: {unconverged}")
        best = self.best
        if best is not None:
            where = ", ".join(f"{axis.path} = {gathered(best, axis.path)}"
                              for axis in self.axes)
            parts.append(f"  lowest RE {format_number(best['residual_error'])} at point "
                         f"{best['point']} ({where})")
        for index in failed[:5].tolist():
            row = self.rows[index]
            parts.append(f"  point {row['point']} failed: {row['error']}")
        if len(failed) > 5:
            parts.append(f"  ... and {len(failed) - 5} more failures (see sweep.csv)")
        if self.out_dir is not None:
            parts.append(f"  results: {self.out_dir / CSV_NAME}")
        return parts


class SampledFigures:
    """The samples and percentiles of a Monte Carlo study's figures (its ``_metrics``:
    array fields, one value per sample)."""

    _metrics: ClassVar[tuple[str, ...]]
    percentiles: tuple[float, ...]
    residual_error: np.ndarray

    @property
    def samples(self) -> int:
        """Number of samples."""
        return len(self.residual_error)

    def percentile_table(self) -> dict[str, dict[float, float]]:
        """``{metric: {percentile: value}}`` (numpy's linear interpolation)."""
        return {metric: dict(zip(self.percentiles,
                                 np.percentile(getattr(self, metric), self.percentiles).tolist(),
                                 strict=True))
                for metric in self._metrics}

    def _sample_summary(self) -> dict[str, Any]:
        """Percentiles, mean and largest value of each figure over the samples (what a
        saved study keeps of them)."""
        return {"percentiles": {metric: {f"{q:g}": value for q, value in values.items()}
                                for metric, values in self.percentile_table().items()},
                "mean": {metric: float(np.mean(getattr(self, metric)))
                         for metric in self._metrics},
                "max": {metric: float(np.max(getattr(self, metric)))
                        for metric in self._metrics}}


@dataclass(frozen=True, eq=False, repr=False)
class ToleranceResult(SampledFigures, Record, Readable):
    """A Monte Carlo tolerance study of one design.

    Attributes
    ----------
    design : sso.ShaftSeries
        The nominal design.
    nominal : sso.Evaluation
        Its evaluation.
    distribution : {"normal", "uniform"}
    beta_tolerance_deg, phase_tolerance_deg : tuple of float
        Per joint / per phase: the standard deviation (normal) or half-width
        (uniform) of the deviation, deg.
    seed : int
    input_speed_rpm : float
    quadrature_samples : int
        Angles of the residual-error rule (one rule serves every sample).
    percentiles : tuple of float
        Which percentiles :meth:`percentile_table` reports, in percent.
    beta_deg, phase_deg : numpy.ndarray
        The sampled designs, shape ``(samples, joints)`` / ``(samples, joints - 1)``.
    residual_error, fluctuation, max_output_accel_rad_s2 : numpy.ndarray
        Each sample's RE (dimensionless), peak-to-peak output over input speed
        (dimensionless) and peak output acceleration (rad/s^2).
    elapsed_s : float
        Wall time, s.
    files : tuple of pathlib.Path
        Files written.
    study_of : str
        Which design was studied, in words (an optimum, a case's start, ...).
    reflected_samples : int
        Samples in which a perturbed operating angle fell below 0 deg and was
        reflected to its magnitude (the same joint bent the other way).
    """

    design: ShaftSeries
    nominal: Evaluation
    distribution: str
    beta_tolerance_deg: tuple[float, ...]
    phase_tolerance_deg: tuple[float, ...]
    seed: int
    input_speed_rpm: float
    quadrature_samples: int
    percentiles: tuple[float, ...]
    beta_deg: np.ndarray
    phase_deg: np.ndarray
    residual_error: np.ndarray
    fluctuation: np.ndarray
    max_output_accel_rad_s2: np.ndarray
    elapsed_s: float
    files: tuple[Path, ...] = field(default=())
    study_of: str = "the given design"
    reflected_samples: int = 0

    report_kind: ClassVar[str] = "tolerance"
    _metrics: ClassVar[tuple[str, ...]] = METRICS

    def _repr_text(self) -> str:
        median = self.percentile_table()["residual_error"]
        cells = ", ".join(f"p{q:g} {format_number(value, 3)}" for q, value in median.items())
        return (f"{self.samples} {self.distribution} samples of {self.study_of}: RE nominal "
                f"{format_number(self.nominal.residual_error, 3)}; {cells}")

    def _summary_parts(self) -> list[Part]:
        header = ("figure", "nominal", *(f"p{q:g}" for q in self.percentiles))
        rows = tuple((metric, format_number(getattr(self.nominal, metric)),
                      *(format_number(value) for value in values.values()))
                     for metric, values in self.percentile_table().items())
        spread = "standard deviation" if self.distribution == "normal" else "half-width"
        headline = (f"tolerance: {self.samples} samples ({self.distribution}, seed {self.seed}) "
                    f"in {self.elapsed_s:.2f} s")
        design = (f"  design studied: {self.study_of}: beta "
                  f"[{format_numbers(self.design.beta_deg)}] deg, phase "
                  f"[{format_numbers(self.design.phase_deg)}] deg")
        deviations = (f"  deviations ({spread}): beta [{format_numbers(self.beta_tolerance_deg)}]"
                      f" deg, phase [{format_numbers(self.phase_tolerance_deg)}] deg")
        reflected = ("  samples with a negative operating angle, reflected to |beta|: "
                     f"{self.reflected_samples}")
        return [headline, design, deviations, reflected, TextTable(header, rows)]

    def _record_save(self) -> dict[str, Any]:
        """The saved form (``result.json``): every field but the per-sample arrays, the
        number of samples and their summary (:meth:`_sample_summary`).

        The samples are in the study's table (``tolerance.csv``); the record stays a
        few kilobytes whatever the number of samples, and is read back by drawing the
        samples again from its seed (:meth:`_record_load`).
        """
        saved = {name: encode(getattr(self, name))
                 for name in saved_field_names(type(self), SHAFT_SAMPLE_FIELDS)}
        return {**saved, "samples": self.samples, "summary": self._sample_summary()}

    @classmethod
    def _record_fields_saved(cls) -> tuple[list[str], dict[str, Any]]:
        """The saved form's fields of the class and the others (with their schema)."""
        return saved_field_names(cls, SHAFT_SAMPLE_FIELDS), EXTRA_SCHEMA

    @classmethod
    def _record_load(cls, saved: Mapping[str, Any], where: str) -> ToleranceResult:
        """A saved study read back: its samples drawn and evaluated again from its design,
        tolerances and seed (the same numbers; the study's chunking never changes
        them), and its saved summary checked against them.

        Raises
        ------
        ValueError
            Naming the field that is missing, unknown, out of range, or whose summary
            figure is not that of the samples drawn again (beyond ``1e-14 + 1e-6 *
            |figure|``).
        """
        names, extra = cls._record_fields_saved()
        arguments = read_saved_fields(cls, saved, names, tuple(extra), where)
        samples = saved["samples"]
        if isinstance(samples, bool) or not isinstance(samples, int) or samples < 1:
            raise RecordError(f"{where}.samples = {shown(samples)}; allowed: a whole number "
                              ">= 1")
        beta_deg, phase_deg, metrics, reflected = redrawn_samples(
            arguments["design"], arguments["beta_tolerance_deg"],
            arguments["phase_tolerance_deg"], arguments["distribution"], samples,
            arguments["seed"], arguments["quadrature_samples"], arguments["input_speed_rpm"])
        made = cls(**arguments, beta_deg=beta_deg, phase_deg=phase_deg,
                   residual_error=metrics[0], fluctuation=metrics[1],
                   max_output_accel_rad_s2=metrics[2])
        check_summary(saved["summary"], made._sample_summary(), f"{where}.summary")
        if reflected != made.reflected_samples:
            raise RecordError(f"{where}.reflected_samples = {made.reflected_samples}; the "
                              f"samples drawn again from the study's seed reflect {reflected}")
        return made

    def _document_dict(self) -> dict[str, Any]:
        """JSON-ready summary: settings, nominal evaluation and percentiles.

        The per-sample arrays are left out (``tolerance.csv`` holds them).
        """
        return {
            "design": self.design.to_dict(),
            "nominal": self.nominal.to_dict(),
            "distribution": self.distribution,
            "beta_tolerance_deg": list(self.beta_tolerance_deg),
            "phase_tolerance_deg": list(self.phase_tolerance_deg),
            "samples": self.samples,
            "seed": self.seed,
            "input_speed_rpm": self.input_speed_rpm,
            "quadrature_samples": self.quadrature_samples,
            **self._sample_summary(),
            "elapsed_s": self.elapsed_s,
            "files": [str(path) for path in self.files],
            "study_of": self.study_of,
            "reflected_samples": self.reflected_samples,
        }
