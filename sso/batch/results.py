"""What a sweep and a tolerance study return: :class:`SweepResult`, :class:`ToleranceResult`.

Kept apart from the code that computes them, so the report writers
(:mod:`sso.batch.report`) and the studies (:mod:`sso.batch.sweep`,
:mod:`sso.batch.tolerance_study`) both import them without a circle.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from sso.batch.axes import Axis
from sso.batch.table import CSV_NAME
from sso.shafts.evaluation import Evaluation
from sso.shafts.perturbed import METRICS
from sso.shafts.series import ShaftSeries


@dataclass(frozen=True)
class SweepResult:
    """What a sweep computed, one row per point.

    Attributes
    ----------
    axes : tuple of Axis
        The varied keys and their values.
    mode : {"product", "listed"}
    action : {"optimise", "evaluate"}
    rows : tuple of dict
        One row per point, sorted by point index, with the columns of
        ``sweep.csv`` (numbers, booleans and lists parsed back).
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
    """

    axes: tuple[Axis, ...]
    mode: str
    action: str
    rows: tuple[dict[str, Any], ...]
    computed: int
    resumed: int
    elapsed_s: float
    out_dir: Path | None = None
    files: tuple[Path, ...] = field(default=())

    @property
    def failed(self) -> tuple[dict[str, Any], ...]:
        """Rows of the points that did not give a result."""
        return tuple(row for row in self.rows if row["status"] != "ok")

    @property
    def best(self) -> dict[str, Any] | None:
        """Row with the lowest residual error, or None if every point failed."""
        finished = [row for row in self.rows if row["status"] == "ok"]
        return min(finished, key=lambda row: row["residual_error"]) if finished else None

    @property
    def success(self) -> bool:
        """Every point finished; when optimising, each converged and cross-checked."""
        return not self.failed and all(row.get("success") is not False for row in self.rows)

    def summary(self) -> str:
        """A few lines for the end of a run."""
        rate = self.computed / self.elapsed_s if self.elapsed_s > 0 else 0.0
        lines = [f"sweep: {len(self.rows)} points ({self.computed} computed in "
                 f"{self.elapsed_s:.1f} s, {rate:.1f} points/s; {self.resumed} from an "
                 f"earlier run), {len(self.failed)} failed"]
        if self.action == "optimise":
            unconverged = sum(row.get("success") is False for row in self.rows)
            lines.append(f"  not converged or solvers disagree: {unconverged}")
        best = self.best
        if best is not None:
            where = ", ".join(f"{axis.path} = {best[axis.path]}" for axis in self.axes)
            lines.append(f"  lowest RE {best['residual_error']:.6g} at point {best['point']} "
                         f"({where})")
        for row in self.failed[:5]:
            lines.append(f"  point {row['point']} failed: {row['error']}")
        if len(self.failed) > 5:
            lines.append(f"  ... and {len(self.failed) - 5} more failures (see sweep.csv)")
        if self.out_dir is not None:
            lines.append(f"  results: {self.out_dir / CSV_NAME}")
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary of every field."""
        return {
            "axes": [{"path": axis.path, "values": list(axis.values)} for axis in self.axes],
            "mode": self.mode,
            "action": self.action,
            "rows": [dict(row) for row in self.rows],
            "computed": self.computed,
            "resumed": self.resumed,
            "elapsed_s": self.elapsed_s,
            "out_dir": None if self.out_dir is None else str(self.out_dir),
            "files": [str(path) for path in self.files],
            "success": self.success,
        }


@dataclass(frozen=True)
class ToleranceResult:
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

    @property
    def samples(self) -> int:
        """Number of samples."""
        return len(self.residual_error)

    def percentile_table(self) -> dict[str, dict[float, float]]:
        """``{metric: {percentile: value}}`` (numpy's linear interpolation)."""
        return {metric: dict(zip(self.percentiles,
                                 np.percentile(getattr(self, metric), self.percentiles).tolist(),
                                 strict=True))
                for metric in METRICS}

    def summary(self) -> str:
        """A few lines for the end of a run."""
        lines = [f"tolerance: {self.samples} samples ({self.distribution}, seed {self.seed}) "
                 f"in {self.elapsed_s:.2f} s"]
        for metric, values in self.percentile_table().items():
            cells = ", ".join(f"p{q:g} {value:.4g}" for q, value in values.items())
            lines.append(f"  {metric}: nominal {getattr(self.nominal, metric):.4g}; {cells}")
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
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
            "percentiles": {metric: {f"{q:g}": value for q, value in values.items()}
                            for metric, values in self.percentile_table().items()},
            "mean": {metric: float(np.mean(getattr(self, metric))) for metric in METRICS},
            "max": {metric: float(np.max(getattr(self, metric))) for metric in METRICS},
            "elapsed_s": self.elapsed_s,
            "files": [str(path) for path in self.files],
        }
