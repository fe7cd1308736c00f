"""Manufacturing tolerances of a column: a fixed, seeded sample of what production builds.

Hardpoints come with position errors (mm) and yokes with phase errors (deg, spline
backlash and assembly). :class:`Tolerances` draws one sample of them, once, from a
seeded generator (common random numbers): every design is judged on the same
columns, so two designs' percentiles differ only by the designs.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from sso._column.geometry import ColumnGeometry
from sso._column.scenarios import cvar, scenario_re
from sso._display import Part, Readable, TextTable, format_number
from sso._limits import DEFAULT_TOLERANCE_SAMPLES
from sso._record import Record, register_record
from sso._validation import check_choice, finite_in_range, validate_count

if TYPE_CHECKING:
    from sso._shafts.options import DesignProblem

DISTRIBUTIONS = ("normal", "uniform")
MAX_HARDPOINT_MM = 100.0
MAX_YOKE_PHASE_DEG = 45.0
# A percentile objective carries one variable and one constraint per sample, and
# SLSQP's dense subproblem grows with their cube (about 1 s per run at 200).
MIN_SAMPLES = 2
MAX_SAMPLES = 1_000


@register_record
@dataclass(frozen=True)
class Tolerances:
    """Manufacturing tolerances of a column and the sample that represents them.

    Parameters
    ----------
    hardpoint_mm : float
        Error of every coordinate of every hardpoint (``P0 .. P(n+1)``), mm:
        the standard deviation (``"normal"``) or the half-width (``"uniform"``),
        as in :func:`sso.tolerance_study`. In ``[0, 100]``.
    yoke_phase_deg : float
        Error of each yoke phasing ``delta_k`` (spline backlash and assembly),
        deg, same meaning. In ``[0, 45]``.
    cross_angle_deg : float
        Deviation of the cross arms from 90 deg. Only 0 is accepted: the exact
        chain model assumes perpendicular arms.
    samples : int
        Sample size, in ``[2, 1000]`` (a percentile objective has one NLP variable
        and one constraint per sample).
    seed : int
        Seed of ``numpy.random.default_rng``, >= 0.
    distribution : {"normal", "uniform"}

    Raises
    ------
    ValueError
        Naming the field, the value and the allowed range.
    """

    hardpoint_mm: float = 0.0
    yoke_phase_deg: float = 0.0
    cross_angle_deg: float = 0.0
    samples: int = DEFAULT_TOLERANCE_SAMPLES
    seed: int = 0
    distribution: str = "normal"

    def __post_init__(self) -> None:
        object.__setattr__(self, "hardpoint_mm", finite_in_range(
            "hardpoint_mm", self.hardpoint_mm, 0.0, MAX_HARDPOINT_MM, "mm"))
        object.__setattr__(self, "yoke_phase_deg", finite_in_range(
            "yoke_phase_deg", self.yoke_phase_deg, 0.0, MAX_YOKE_PHASE_DEG, "deg"))
        cross = finite_in_range("cross_angle_deg", self.cross_angle_deg, 0.0, MAX_YOKE_PHASE_DEG,
                                "deg")
        if cross != 0.0:
            raise ValueError(
                f"cross_angle_deg = {cross:g} is not supported: the exact chain model assumes "
                "cross arms at 90 deg, so only cross_angle_deg = 0 is allowed")
        object.__setattr__(self, "cross_angle_deg", cross)
        validate_count("samples", self.samples, MIN_SAMPLES, MAX_SAMPLES)
        validate_count("seed", self.seed, 0, 2**63 - 1)
        check_choice("distribution", self.distribution, DISTRIBUTIONS)

    def sample(self, geometry: ColumnGeometry) -> ToleranceSample:
        """The sample of built columns for one nominal geometry.

        ``rng = numpy.random.default_rng(seed)`` draws the hardpoint errors,
        shape ``(samples, n + 2, 3)`` mm, then the yoke phase errors, shape
        ``(samples, n - 1)`` deg (``rng.normal(0, t, ...)`` or
        ``rng.uniform(-t, t, ...)``); a zero tolerance draws nothing.

        Raises
        ------
        ValueError
            If a drawn column is not a column (``hardpoint_mm`` too large for it).
        """
        points = np.asarray(geometry.points_mm)
        joints = geometry.joint_count
        offsets, phase_errors = drawn_errors(geometry, self, self.samples)
        beta = np.empty((self.samples, joints))
        gamma = np.empty((self.samples, joints - 1))
        for index in range(self.samples):
            try:
                built = ColumnGeometry(points + offsets[index])
            except ValueError as error:
                raise ValueError(f"hardpoint_mm = {self.hardpoint_mm:g} mm is too large for this "
                                 f"column: sample {index} is not a column ({error})") from None
            beta[index] = built.beta_deg
            gamma[index] = built.plane_angle_deg
        return ToleranceSample(beta_rad=np.radians(beta),
                               gamma_rad=np.radians(gamma - phase_errors),
                               hardpoint_offsets_mm=offsets, yoke_phase_errors_deg=phase_errors)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary of every field."""
        return {"hardpoint_mm": self.hardpoint_mm, "yoke_phase_deg": self.yoke_phase_deg,
                "cross_angle_deg": self.cross_angle_deg, "samples": self.samples,
                "seed": self.seed, "distribution": self.distribution}


def drawn_errors(geometry: ColumnGeometry, tolerances: Tolerances,
                 count: int) -> tuple[np.ndarray, np.ndarray]:
    """``count`` built columns' errors from the tolerances' seed: hardpoint errors
    ``(count, n + 2, 3)`` (mm), then yoke phase errors ``(count, n - 1)`` (deg), as
    :meth:`Tolerances.sample` draws them (the first draws of a larger count are those of
    a smaller one's hardpoints)."""
    rng = np.random.default_rng(tolerances.seed)
    offsets = draw_errors(rng, tolerances.hardpoint_mm, tolerances.distribution,
                          (count, *np.shape(geometry.points_mm)))
    phase_errors = draw_errors(rng, tolerances.yoke_phase_deg, tolerances.distribution,
                               (count, geometry.joint_count - 1))
    return offsets, phase_errors


def draw_errors(rng: np.random.Generator, tolerance: float, distribution: str,
                shape: tuple[int, ...]) -> np.ndarray:
    """Errors of one kind, drawn from ``rng`` (nothing drawn for a zero tolerance).

    ``rng.normal(0, tolerance, shape)`` (``"normal"``: the tolerance is the standard
    deviation) or ``rng.uniform(-tolerance, tolerance, shape)`` (``"uniform"``: the
    half-width).
    """
    if tolerance == 0.0:
        return np.zeros(shape)
    if distribution == "normal":
        return rng.normal(0.0, tolerance, shape)
    return rng.uniform(-tolerance, tolerance, shape)


@dataclass(frozen=True)
class ToleranceSample:
    """Built columns drawn by :meth:`Tolerances.sample`.

    Attributes
    ----------
    beta_rad : numpy.ndarray, shape (samples, n)
        Operating angles of each built column, rad.
    gamma_rad : numpy.ndarray, shape (samples, n - 1)
        Its bend-plane angles minus its yoke phase errors, rad: a built column
        with design phasing ``delta`` runs at ``phi = 90 + delta - gamma_rad``.
    hardpoint_offsets_mm : numpy.ndarray, shape (samples, n + 2, 3)
    yoke_phase_errors_deg : numpy.ndarray, shape (samples, n - 1)
    """

    beta_rad: np.ndarray
    gamma_rad: np.ndarray
    hardpoint_offsets_mm: np.ndarray
    yoke_phase_errors_deg: np.ndarray

    def residual_error(self, yoke_phase_deg: Any) -> np.ndarray:
        """RE of every built column at a design yoke phasing (deg), shape ``(samples,)``."""
        return scenario_re(self.beta_rad, self.gamma_rad, yoke_phase_deg)


@register_record
@dataclass(frozen=True)
class BuiltColumnSpread:
    """A column's tolerances as the criterion of the choice within its exact optima.

    What :func:`sso.optimise` (a shaft series, ``exact_set_tolerances=``) chooses a
    column's phasing by where RE = 0 is reached on a set of phasings: the p95 RE over
    the seeded sample of built columns of :meth:`Tolerances.sample` (the one the
    tolerance study and the robust phasing judge designs on), and as the smooth measure
    minimised on the set, the mean RE over that sample.

    Parameters
    ----------
    geometry : ColumnGeometry
        The nominal column; the design variables are its model phases (option 1).
    tolerances : Tolerances
    """

    geometry: ColumnGeometry
    tolerances: Tolerances

    @property
    def seed(self) -> int:
        """The seed of the sample."""
        return self.tolerances.seed

    @functools.cached_property
    def _sample(self) -> ToleranceSample:
        return self.tolerances.sample(self.geometry)

    def _residual_errors(self, problem: DesignProblem, x_rad: np.ndarray) -> np.ndarray:
        _, phase_rad = problem.split(list(x_rad), problem.parameters_rad.tolist())
        yoke = self.geometry.yoke_phase_deg_from_phase(np.degrees(np.asarray(phase_rad)))
        return self._sample.residual_error(yoke)

    @property
    def description(self) -> str:
        """The tolerances in words, as a report states them."""
        tolerances = self.tolerances
        return (f"{tolerances.distribution}, every hardpoint coordinate "
                f"{tolerances.hardpoint_mm:g} mm, each yoke phasing {tolerances.yoke_phase_deg:g}"
                f" deg, {tolerances.samples} built columns, seed {tolerances.seed}")

    def p95_residual_error(self, problem: DesignProblem, x_rad: np.ndarray) -> float:
        """p95 RE (``numpy.percentile``, linear) over the built columns at the model
        phases ``x_rad`` (rad, the free variables of ``problem``)."""
        return float(np.percentile(self._residual_errors(problem, x_rad), 95.0))

    def expected_residual_error(self, problem: DesignProblem, x_rad: np.ndarray) -> float:
        """Mean RE over the built columns at the model phases ``x_rad`` (rad)."""
        return float(np.mean(self._residual_errors(problem, x_rad)))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary of the nominal column and the tolerances."""
        return {"geometry": self.geometry.to_dict(), "tolerances": self.tolerances.to_dict()}


SAMPLE_FIGURES = ("nominal_re", "mean", "p50", "p95", "max", "cvar95")


@dataclass(frozen=True, eq=False, repr=False)
class SampleStudy(Record, Readable):
    """RE of one design over a sample: the figures a tolerance study reports.

    Attributes
    ----------
    nominal_re : float
        RE of the nominal column (no errors).
    mean, p50, p95, max : float
        Mean, median, 95th percentile (linear interpolation, ``numpy.percentile``)
        and largest RE over the sample.
    cvar95 : float
        Mean of the worst 5 % of the sample (conditional value at risk at 95 %).
    """

    nominal_re: float
    mean: float
    p50: float
    p95: float
    max: float
    cvar95: float

    def _repr_text(self) -> str:
        return ", ".join(f"{name}={format_number(getattr(self, name))}" for name in SAMPLE_FIGURES)

    def _summary_parts(self) -> list[Part]:
        labels = ("RE of the nominal column", "mean RE", "median RE", "95th percentile of RE",
                  "largest RE", "mean of the worst 5 % (CVaR 95)")
        return ["RE over a sample of built columns", TextTable(("figure", "RE"), tuple(
            (label, format_number(getattr(self, name)))
            for label, name in zip(labels, SAMPLE_FIGURES, strict=True)))]

    @classmethod
    def of(cls, nominal_re: float, values: np.ndarray) -> SampleStudy:
        """The study of sampled RE ``values``."""
        weights = np.full(len(values), 1.0 / len(values))
        return cls(nominal_re=float(nominal_re), mean=float(np.mean(values)),
                   p50=float(np.percentile(values, 50.0)), p95=float(np.percentile(values, 95.0)),
                   max=float(np.max(values)), cvar95=cvar(values, weights, 0.95))
