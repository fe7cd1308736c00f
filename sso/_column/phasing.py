"""Yoke phasing for fixed hardpoints: the best assembly and the ones it replaces."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from sso._column.cancel import CancelVerdict, can_cancel, minimising_phases_deg
from sso._column.chain_matrix import chain_matrix, residual_error
from sso._column.geometry import ColumnGeometry, wrap_half_turn
from sso._column.tolerances import BuiltColumnSpread, Tolerances
from sso._display import Part, Readable, TextTable, format_number, format_numbers
from sso._limits import (
    CONVENTIONAL_PHASE_DEG,
    CROSS_CHECK_SOLVERS,
    DEFAULT_COLUMN_SEED,
    DEFAULT_INPUT_SPEED_RPM,
    DEFAULT_MAX_ITERATIONS,
    DEFAULT_SHAFT_SOLVER_TOL,
    DEFAULT_STARTS,
)
from sso._record import NON_NEGATIVE, FieldRule, Record
from sso._shafts.optimise import OptimisationResult, optimise
from sso._solvers.crosscheck import allowed_objective_gap

# Phase bounds of the NLP: one and a half periods, so every minimum (period 180 deg)
# lies strictly inside them at least once and no start stalls on a bound.
PHASE_BOUNDS_DEG = (-90.0, 270.0)
# Two phasings are the same assembly when they differ by less than this (deg, mod 180).
SAME_PHASING_DEG = 1e-6
EXACT_SET_CRITERION = ("nearest the textbook correction: the exact optimum whose model phases "
                       "lie furthest inside the bounds (-90, 270) deg, i.e. nearest phi = 90 "
                       "(delta = gamma)")
"""How :func:`sso.optimise` chooses within a set of exact optima of a column's phasing (the
largest margin to the bounds of :data:`PHASE_BOUNDS_DEG`, said in a column's terms)."""
TOLERANCE_SET_CRITERION = ("lowest p95 RE over the built columns of the tolerances (the "
                           "seeded sample of the tolerance study)")
"""How it chooses there with tolerances (the shaft series' p95 criterion, on a column's
hardpoint and yoke-phasing errors)."""


@dataclass(frozen=True, eq=False, repr=False)
class PhasingResult(Record, Readable):
    """The best yoke phasing of a column and the reference assemblies.

    Attributes
    ----------
    geometry : ColumnGeometry
    x : tuple of float
        Best yoke phasing ``delta_k`` per intermediate shaft, deg, in ``[-90, 90)``
        (the fitter's convention; same as ``yoke_phase_deg``).
    fun : float
        RE of the best phasing (dimensionless).
    success : bool
        The optimisation converged, its solvers agree, and ``fun`` is within
        round-off of the closed-form least RE (the solvers' own agreement rule,
        :func:`sso._solvers.crosscheck.allowed_objective_gap`: relative to the RE's
        size).
    message : str
    yoke_phase_deg : tuple of float
        Same as ``x``.
    phase_deg : tuple of float
        The model phases of the best phasing, deg, in ``[0, 180)``.
    equivalent_yoke_phase_deg : tuple of tuple of float
        Every phasing (mod 180 deg) that reaches the least RE, in the fitter's
        convention: from the closed form where the set is finite; else the
        distinct minima the solvers found (the set is then a continuum).
    optimum_set_is_continuum : bool
        True for 4 or more joints that can cancel, or a straight joint.
    minimum_residual_error : float
        Least RE any phasing reaches, closed form (``sso.can_cancel``).
    in_phase_re : float
        RE with every yoke in phase (``delta = 0``).
    plane_corrected_re : float
        RE of the textbook correction: each yoke turned by its bend-plane angle
        (``delta_k = gamma_k``, so ``phi = 90`` everywhere).
    verdict : CancelVerdict
    optimisation : sso.OptimisationResult
        The option-1 run of :func:`sso.optimise` (IPOPT and SLSQP, cross-checked).
    """

    _record_rules: ClassVar[dict[str, FieldRule]] = {"fun": NON_NEGATIVE}

    geometry: ColumnGeometry
    x: tuple[float, ...]
    fun: float
    success: bool
    message: str
    phase_deg: tuple[float, ...]
    equivalent_yoke_phase_deg: tuple[tuple[float, ...], ...]
    optimum_set_is_continuum: bool
    minimum_residual_error: float
    in_phase_re: float
    plane_corrected_re: float
    verdict: CancelVerdict
    optimisation: OptimisationResult

    def _repr_text(self) -> str:
        return (f"yoke_phase_deg [{format_numbers(self.x)}], RE {format_number(self.fun, 4)} "
                f"(in phase {format_number(self.in_phase_re, 4)}, plane-corrected "
                f"{format_number(self.plane_corrected_re, 4)}), success={self.success}")

    def _summary_parts(self) -> list[Part]:
        rows = (("best phasing", format_numbers(self.x), format_number(self.fun)),
                ("yokes in phase", "0" + ", 0" * (len(self.x) - 1) if self.x else "",
                 format_number(self.in_phase_re)),
                ("each yoke turned by its bend-plane angle", "", 
                 format_number(self.plane_corrected_re)))
        parts: list[Part] = [
            f"Phasing: {self.message}", TextTable(("assembly", "yoke phase (deg)", "RE"), rows),
            f"least RE any phasing reaches: {format_number(self.minimum_residual_error)}"]
        extent = self.exact_optimum_extent_deg
        if extent is not None and self.optimisation.exact_optima is not None:
            parts += [f"exact optima: a set of dimension "
                      f"{self.optimisation.exact_optima.dimension}, chosen "
                      f"{self.exact_optimum_criterion}; the set's delta about it (each end "
                      f"the furthest at which an exact optimum was found, a lower estimate)",
                      TextTable(("intermediate shaft", "set from delta (deg)",
                                 "set to delta (deg)"),
                                tuple((str(shaft + 1), format_number(low), format_number(high))
                                      for shaft, (low, high) in enumerate(extent)))]
        return parts

    @property
    def yoke_phase_deg(self) -> tuple[float, ...]:
        """Best yoke phasing per intermediate shaft, deg (same as ``x``)."""
        return self.x

    @property
    def exact_optimum_criterion(self) -> str | None:
        """How the phasing was chosen within a set of exact optima (RE at round-off zero):
        :data:`EXACT_SET_CRITERION`, or :data:`TOLERANCE_SET_CRITERION` with tolerances;
        None when the least RE is above zero (one optimum, mod 180 deg and mirrors)."""
        exact = self.optimisation.exact_optima
        if exact is None:
            return None
        return EXACT_SET_CRITERION if exact.tolerances is None else TOLERANCE_SET_CRITERION

    @property
    def exact_optimum_extent_deg(self) -> tuple[tuple[float, float], ...] | None:
        """Per intermediate shaft, the least and the largest yoke phasing ``delta`` on the
        set of exact optima about the chosen phasing, deg, or None (no such set).

        The model phases' bounds span two periods, so each shaft's extent is sought
        modulo 180 deg (:func:`sso._shafts.exact_optima.set_extent`): walking from the
        chosen phasing in 5 deg steps each way to the first step where no exact optimum
        is found, then bisecting. Each end is the furthest phasing at which an exact
        optimum was found (a lower estimate of the arc), with its witness
        (:attr:`exact_optimum_extent_witnesses_deg`). The first value lies in
        ``[-90, 90)``; the second may exceed 90 (the arc wraps). An arc of 180 deg: an
        exact optimum was found at every step of the period, every phasing of that
        shaft. Found on first use.
        """
        exact = self.optimisation.exact_optima
        if exact is None:
            return None
        extents = []
        for (low, high), gamma in zip(exact.extent, self.geometry.plane_angle_deg,
                                      strict=True):
            start = float(wrap_half_turn(low - CONVENTIONAL_PHASE_DEG + gamma))
            extents.append((start, start + min(high - low, 180.0)))
        return tuple(extents)

    @property
    def exact_optimum_extent_witnesses_deg(
            self) -> tuple[tuple[tuple[float, ...], tuple[float, ...]], ...] | None:
        """Per intermediate shaft, the exact optima found at the two ends of
        :attr:`exact_optimum_extent_deg`: each a yoke phasing of every intermediate shaft,
        deg, in ``[-90, 90)`` (its entry for that shaft is the end, mod 180); None where
        there is no set."""
        exact = self.optimisation.exact_optima
        if exact is None:
            return None
        convert = self.geometry.yoke_phase_deg_from_phase
        return tuple((convert(low.witness), convert(high.witness))
                     for low, high in exact.extent_search.ends)


def optimise_phasing(geometry: ColumnGeometry, *, starts: int = DEFAULT_STARTS,
                     solvers: tuple[str, ...] = CROSS_CHECK_SOLVERS,
                     input_speed_rpm: float = DEFAULT_INPUT_SPEED_RPM,
                     solver_tol: float = DEFAULT_SHAFT_SOLVER_TOL,
                     max_iterations: int = DEFAULT_MAX_ITERATIONS,
                     seed: int = DEFAULT_COLUMN_SEED,
                     tolerances: Tolerances | None = None) -> PhasingResult:
    """Best yoke phasing of a column whose hardpoints are fixed.

    Runs :func:`sso.optimise` option 1 (operating angles fixed by the points, every
    phase free over a full period) from the in-phase assembly and space-filling
    starts, and checks the answer against the closed-form least RE. Where RE = 0 is
    reached on a set of phasings, the one returned is chosen within the set as
    :func:`sso.optimise` chooses for a shaft series: nearest the textbook correction
    (the largest margin to the phase bounds), or with ``tolerances`` the lowest p95 RE
    over their built columns.

    Parameters
    ----------
    geometry : ColumnGeometry
        The column, at least 2 joints.
    starts : int
        Starts per solver (the in-phase assembly plus space-filling points).
    solvers : tuple of {"ipopt", "slsqp"}
        Solvers; with two they are cross-checked.
    input_speed_rpm : float
        Input speed for the reported figures, rpm.
    solver_tol, max_iterations
        The solvers' stopping tolerance and iteration limit of each run (as :func:`sso.optimise`).
    seed : int
        Seed of the space-filling starts and of the search for representatives of
        a continuum of optima.
    tolerances : Tolerances, optional
        Hardpoint and yoke-phasing errors by whose p95 RE the phasing is chosen within
        a set of exact optima (its sample has its own seed).

    Returns
    -------
    PhasingResult

    Raises
    ------
    TypeError
        If ``geometry`` is not a :class:`ColumnGeometry`.
    ValueError
        If the column has one joint (nothing to phase), or an option is bad.
    """
    if not isinstance(geometry, ColumnGeometry):
        raise TypeError(f"geometry must be a ColumnGeometry, not {type(geometry).__name__}")
    if geometry.joint_count < 2:
        raise ValueError("geometry has 1 joint: yoke phasing needs at least 2 joints "
                         "(an intermediate shaft)")
    beta_rad = np.radians(geometry.beta_deg)
    gamma_deg = np.asarray(geometry.plane_angle_deg)
    in_phase = geometry.series()
    # Every solver from every start (no least-squares screening): where a continuum of
    # phasings cancels, this keeps the one the position and robust studies measured.
    run = optimise(in_phase, option=1, phase_bounds_deg=PHASE_BOUNDS_DEG,
                   solvers=solvers, starts=starts, input_speed_rpm=input_speed_rpm,
                   solver_tol=solver_tol, max_iterations=max_iterations, seed=seed,
                   screen_starts=False,
                   exact_set_tolerances=(None if tolerances is None
                                         else BuiltColumnSpread(geometry, tolerances)))
    best_phase = np.mod(np.asarray(run.best_series.phase_deg), 180.0)
    verdict = can_cancel(geometry.beta_deg)
    closed = minimising_phases_deg(geometry.beta_deg)
    if closed is None:
        optima = _distinct(np.vstack([best_phase[None, :],
                                      _local_minima_deg(beta_rad, verdict, seed)]))
    else:
        optima = np.asarray(closed, dtype=float)
    fun = float(run.fun)
    gap = fun - verdict.minimum_residual_error
    reached = gap <= allowed_objective_gap((fun, verdict.minimum_residual_error))
    message = (f"{run.best.message}; RE {fun:.6g}, closed-form least RE "
               f"{verdict.minimum_residual_error:.6g} (gap {gap:.3g})")
    return PhasingResult(
        geometry=geometry,
        x=geometry.yoke_phase_deg_from_phase(best_phase),
        fun=fun,
        success=bool(run.success and reached),
        message=message,
        phase_deg=tuple(float(value) for value in best_phase),
        equivalent_yoke_phase_deg=tuple(geometry.yoke_phase_deg_from_phase(row) for row in optima),
        optimum_set_is_continuum=closed is None,
        minimum_residual_error=verdict.minimum_residual_error,
        in_phase_re=float(residual_error(beta_rad, np.radians(in_phase.phase_deg))),
        plane_corrected_re=float(residual_error(
            beta_rad, np.radians(geometry.phase_deg_from_yoke(wrap_half_turn(gamma_deg))))),
        verdict=verdict,
        optimisation=run,
    )


def _local_minima_deg(beta_rad: np.ndarray, verdict: CancelVerdict, seed: int,
                      count: int = 16) -> np.ndarray:
    """Representatives of a continuum of optimal phasings (deg): least-squares polishes
    of the closed-form chain from random starts, kept where they reach the least RE."""
    from scipy.optimize import least_squares

    def residuals(phase_rad: np.ndarray) -> np.ndarray:
        matrix = chain_matrix(beta_rad, phase_rad)
        scale = np.sqrt(2.0 * np.linalg.det(matrix))
        scaled: np.ndarray = np.array([matrix[0, 0] - matrix[1, 1],
                                       matrix[0, 1] + matrix[1, 0]]) / scale
        return scaled

    rng = np.random.default_rng(seed)
    found = []
    for start in rng.uniform(0.0, np.pi, (count, len(beta_rad) - 1)):
        solution = least_squares(residuals, start, xtol=1e-15, ftol=1e-15, gtol=1e-15)
        if residual_error(beta_rad, solution.x) <= verdict.minimum_residual_error + 1e-12:
            found.append(np.mod(np.degrees(solution.x), 180.0))
    minima: np.ndarray = np.asarray(found).reshape(-1, len(beta_rad) - 1)
    return minima


def _distinct(phases_deg: np.ndarray) -> np.ndarray:
    kept: list[np.ndarray] = []
    for row in phases_deg:
        if all(np.max(np.abs(wrap_half_turn(row - other))) > SAME_PHASING_DEG for other in kept):
            kept.append(row)
    return np.asarray(kept)


