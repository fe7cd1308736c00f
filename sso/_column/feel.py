"""Steering feel: the speed ratio on-centre (around straight ahead) and at lock.

A driver feels the ratio's fluctuation most around straight ahead. The input angle
``theta`` here is the angle of the input shaft's yoke pin axis from the first bend
plane's normal ``n_1``, about the input shaft ``u_0`` (right-hand rule), deg: the
model's driving angle of joint 1. There the speed ratio of the exact chain is

    ratio(theta) = det M / |M (cos theta, sin theta)|^2

(``M`` the chain matrix of :mod:`sso._column.chain_matrix`; checked against the 3D
cross-and-yoke simulation), of period 180 deg and mean 1 over a period.

* :func:`steering_feel` reports the peak-to-peak ratio over the on-centre window
  ``straight_ahead_deg +- window_deg`` and over windows of the same width around
  both locks (``straight_ahead_deg +- lock_deg``), and the weighted RE.
* :func:`optimise_on_centre` chooses the yoke phasing that minimises
  ``RE + on_centre_weight * V``: ``V`` is the variance of the ratio over the
  on-centre window, weighted by the raised cosine ``c = cos^2(90 d / window_deg)``
  for ``|d| < window_deg`` (``d`` the angle from straight ahead, mod 180; 0
  outside), ``V = sum_j c_j (ratio_j - rbar)^2 / sum_j c_j`` with ``rbar`` the
  weighted mean. Both are sums over ``theta_j`` every ``GRID_STEP_DEG`` over one
  period (RE the plain mean of ``(ratio_j - 1)^2``). ``V`` is small where the ratio
  is flat, not where it is 1: a driver feels the ratio change on-centre, while a
  constant ratio slightly off 1 is just a steering ratio. With
  ``on_centre_weight = 0`` the objective is RE itself.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from sso._column.chain_matrix import chain_matrix
from sso._column.design import column_design
from sso._column.geometry import ColumnGeometry, wrap_half_turn
from sso._column.phasing import PhasingResult, optimise_phasing
from sso._column.scenarios import (
    PhasingOutcome,
    chain_matrix_expression,
    outcome_fields,
    solve_phasing_nlp,
    yoke_starts,
)
from sso._display import Part, Readable, TextTable, format_number
from sso._limits import (
    CROSS_CHECK_SOLVERS,
    DEFAULT_COLUMN_SEED,
    DEFAULT_COLUMN_SOLVER_TOL,
    DEFAULT_COLUMN_STARTS,
    DEFAULT_MAX_ITERATIONS,
    DEFAULT_ON_CENTRE_WEIGHT,
    DEFAULT_WINDOW_DEG,
    MAX_ITERATIONS,
    MAX_STARTS,
)
from sso._record import Record
from sso._solvers.nlp import cached_nlp, compile_nlp
from sso._solvers.run import RunLimits
from sso._validation import (
    finite_float,
    finite_in_range,
    validate_count,
    validate_solver_tol,
    validate_solvers,
)

GRID_STEP_DEG = 0.5
FLUCTUATION_STEP_DEG = 0.05
MAX_ON_CENTRE_WEIGHT = 1e6


@dataclass(frozen=True, eq=False, repr=False)
class SteeringFeel(Record, Readable):
    """The speed ratio on-centre and at lock of one design.

    Attributes
    ----------
    straight_ahead_deg, window_deg, lock_deg : float
        Input angle at straight ahead, half-width of the windows, lock angle
        from straight ahead, deg.
    on_centre_fluctuation : float
        Peak-to-peak speed ratio (output over input) over
        ``straight_ahead_deg +- window_deg``.
    lock_fluctuation : float
        The larger peak-to-peak ratio over the windows around the two locks.
    re : float
        Residual error over a period.
    on_centre_variance : float
        ``V``, the window-weighted variance of the ratio on-centre.
    objective : float
        ``RE + on_centre_weight * V``, the objective of :func:`optimise_on_centre`.
    """

    straight_ahead_deg: float
    window_deg: float
    lock_deg: float
    on_centre_fluctuation: float
    lock_fluctuation: float
    re: float
    on_centre_variance: float
    objective: float

    def _repr_text(self) -> str:
        return (f"on-centre fluctuation {format_number(self.on_centre_fluctuation)}, at lock "
                f"{format_number(self.lock_fluctuation)}, RE {format_number(self.re)}")

    def _summary_parts(self) -> list[Part]:
        return [f"Steering feel: straight ahead at {format_number(self.straight_ahead_deg)} deg, "
                f"windows +-{format_number(self.window_deg)} deg, lock "
                f"{format_number(self.lock_deg)} deg",
                TextTable(("figure", "value"), (
                    ("speed-ratio fluctuation on-centre (peak to peak)",
                     format_number(self.on_centre_fluctuation)),
                    ("speed-ratio fluctuation at lock (peak to peak)",
                     format_number(self.lock_fluctuation)),
                    ("residual error RE", format_number(self.re)),
                    ("on-centre variance V", format_number(self.on_centre_variance)),
                    ("objective RE + weight V", format_number(self.objective))))]


@dataclass(frozen=True, eq=False, repr=False)
class OnCentreResult(PhasingOutcome):
    """Outcome of :func:`optimise_on_centre`.

    Attributes
    ----------
    x, fun, nit, nfev, status, success, message, best, solutions, runs, crosscheck
        As :class:`sso._column.scenarios.PhasingOutcome`: ``x`` the yoke phasing
        (deg), ``fun`` = ``RE + on_centre_weight * V`` at ``x``.
    on_centre_weight : float
    feel, nominal_feel : SteeringFeel
        Of this phasing and of the RE optimum (:func:`sso.optimise`).
    nominal : PhasingResult
    """

    on_centre_weight: float
    feel: SteeringFeel
    nominal_feel: SteeringFeel
    nominal: PhasingResult

    @property
    def objective_name(self) -> str:
        """What ``fun`` measures, in words."""
        return "RE + on_centre_weight * V"

    def phasing_objective(self) -> Callable[[np.ndarray], np.ndarray]:
        """``RE + on_centre_weight * V`` of the nominal column, as a function of yoke
        phasings (``(m, shafts)`` deg -> ``(m,)``)."""
        geometry = self.nominal.geometry
        settings = {"straight_ahead_deg": self.feel.straight_ahead_deg,
                    "lock_deg": self.feel.lock_deg, "window_deg": self.feel.window_deg,
                    "on_centre_weight": self.on_centre_weight}

        def objective(yokes: np.ndarray) -> np.ndarray:
            return np.array([steering_feel((geometry, list(yoke)), **settings).objective
                             for yoke in yokes])

        return objective


def speed_ratio(geometry: ColumnGeometry, yoke_phase_deg: Any, input_angle_deg: Any) -> np.ndarray:
    """Output over input speed at input angles ``theta`` (deg, see the module notes)."""
    matrix = chain_matrix(np.radians(geometry.beta_deg),
                          np.radians(geometry.phase_deg_from_yoke(yoke_phase_deg)))
    theta = np.radians(np.asarray(input_angle_deg, dtype=float))
    directions = np.stack([np.cos(theta), np.sin(theta)], axis=-1) @ matrix.T
    ratio: np.ndarray = np.linalg.det(matrix) / np.sum(directions ** 2, axis=-1)
    return ratio


def steering_feel(design: Any, *, straight_ahead_deg: float, lock_deg: float,
                  window_deg: float = DEFAULT_WINDOW_DEG,
                  on_centre_weight: float = DEFAULT_ON_CENTRE_WEIGHT) -> SteeringFeel:
    """Ratio fluctuation on-centre and at lock of a design.

    Parameters
    ----------
    design : (ColumnGeometry, sequence of float) or result
        A column and its yoke phasing (deg), or a result with ``geometry`` and
        ``yoke_phase_deg``.
    straight_ahead_deg : float
        Input angle ``theta`` at straight ahead, deg.
    window_deg : float
        Half-width of the on-centre and lock windows, deg, in ``(0, 90)``.
    lock_deg : float
        Steering-wheel (input) angle from straight ahead to each lock, deg, >= 0.
        The ratio has period 180 deg, so a lock at a multiple of 180 deg feels
        exactly like straight ahead.
    on_centre_weight : float
        Weight of ``V`` in ``objective``, in ``[0, 1e6]``.

    Raises
    ------
    TypeError, ValueError
        For a bad design or option, naming the field.
    """
    geometry, yoke = column_design(design)
    centre, window, lock, weight = _options(straight_ahead_deg, window_deg, lock_deg,
                                            on_centre_weight)
    offsets = np.arange(-window, window + FLUCTUATION_STEP_DEG / 2, FLUCTUATION_STEP_DEG)

    def peak_to_peak(middle: float) -> float:
        ratio = speed_ratio(geometry, yoke, middle + offsets)
        return float(ratio.max() - ratio.min())

    theta = _grid()
    ratio = speed_ratio(geometry, yoke, theta)
    window_weights = _window(theta, centre, window)
    mean = float(np.dot(window_weights, ratio))
    variance = float(np.dot(window_weights, (ratio - mean) ** 2))
    re = float(np.mean((ratio - 1.0) ** 2))
    return SteeringFeel(
        straight_ahead_deg=centre, window_deg=window, lock_deg=lock,
        on_centre_fluctuation=peak_to_peak(centre),
        lock_fluctuation=max(peak_to_peak(centre - lock), peak_to_peak(centre + lock)),
        re=re, on_centre_variance=variance, objective=re + weight * variance)


def optimise_on_centre(geometry: ColumnGeometry, *, straight_ahead_deg: float, lock_deg: float,
                       window_deg: float = DEFAULT_WINDOW_DEG,
                       on_centre_weight: float = DEFAULT_ON_CENTRE_WEIGHT,
                       solvers: tuple[str, ...] = CROSS_CHECK_SOLVERS,
                       starts: int = DEFAULT_COLUMN_STARTS,
                       solver_tol: float = DEFAULT_COLUMN_SOLVER_TOL,
                       max_iterations: int = DEFAULT_MAX_ITERATIONS,
                       seed: int = DEFAULT_COLUMN_SEED) -> OnCentreResult:
    """Yoke phasing that minimises ``RE + on_centre_weight * V`` (module notes).

    Parameters
    ----------
    geometry : ColumnGeometry
        At least 2 joints.
    straight_ahead_deg, window_deg, lock_deg, on_centre_weight
        As :func:`steering_feel`.
    solvers, starts, solver_tol, max_iterations, seed
        As :func:`optimise_positions` (starts added to the RE optimum, its
        equivalent phasings and the in-phase assembly).

    Returns
    -------
    OnCentreResult
        Solver failures and disagreements are reported in it, not raised.

    Raises
    ------
    TypeError, ValueError
        For a bad geometry or option, naming the field.
    """
    if not isinstance(geometry, ColumnGeometry):
        raise TypeError(f"geometry must be a ColumnGeometry, not {type(geometry).__name__}")
    centre, window, lock, weight = _options(straight_ahead_deg, window_deg, lock_deg,
                                            on_centre_weight)
    solver_names = validate_solvers(solvers)
    starts = validate_count("starts", starts, 0, MAX_STARTS)
    max_iterations = validate_count("max_iterations", max_iterations, 1, MAX_ITERATIONS)
    solver_tol = validate_solver_tol(solver_tol)
    nominal = optimise_phasing(geometry, solvers=solver_names, seed=seed)
    options = {"straight_ahead_deg": centre, "window_deg": window, "lock_deg": lock,
               "on_centre_weight": weight}
    nominal_feel = steering_feel(nominal, **options)
    shafts = geometry.joint_count - 1
    theta = _grid()
    reference = nominal_feel.objective
    scale = 1.0 / reference if reference > 0 else 1.0
    nlp = cached_nlp(("column_on_centre", geometry.joint_count, len(theta)),
                     lambda: _build(geometry.joint_count, np.radians(theta)))
    parameters = np.concatenate([np.cos(np.radians(geometry.beta_deg)),
                                 np.radians(geometry.plane_angle_deg),
                                 _window(theta, centre, window), [weight, scale]])
    points, lower, upper = yoke_starts(
        [nominal.yoke_phase_deg, *nominal.equivalent_yoke_phase_deg, [0.0] * shafts],
        shafts, starts, seed)
    solved = solve_phasing_nlp(nlp, parameters, points, RunLimits(lower, upper), shafts, scale,
                               solver_names, solver_tol, max_iterations)
    feel = steering_feel((geometry, solved.yoke_phase_deg), **options)
    message = (f"{solved.best.message}; on-centre fluctuation {feel.on_centre_fluctuation:.4g} "
               f"(RE optimum {nominal_feel.on_centre_fluctuation:.4g}), at lock "
               f"{feel.lock_fluctuation:.4g} ({nominal_feel.lock_fluctuation:.4g})")
    return OnCentreResult(**outcome_fields(solved, feel.objective, message),
                          on_centre_weight=weight, feel=feel, nominal_feel=nominal_feel,
                          nominal=nominal)


def _grid() -> np.ndarray:
    grid: np.ndarray = np.arange(0.0, 180.0, GRID_STEP_DEG)
    return grid


def _window(theta_deg: np.ndarray, centre: float, window: float) -> np.ndarray:
    """Raised-cosine weights of the on-centre window, summing to 1."""
    distance = np.abs(wrap_half_turn(theta_deg - centre))
    bump = np.where(distance < window, np.cos(np.radians(90.0 * distance / window)) ** 2, 0.0)
    weights: np.ndarray = bump / bump.sum()
    return weights


def _options(straight_ahead_deg: Any, window_deg: Any, lock_deg: Any,
             on_centre_weight: Any) -> tuple[float, float, float, float]:
    return (finite_float("straight_ahead_deg", straight_ahead_deg),
            finite_in_range("window_deg", window_deg, 0.0, 90.0, "deg", lower_open=True,
                            upper_open=True),
            finite_in_range("lock_deg", lock_deg, 0.0, np.inf, "deg", upper_open=True),
            finite_in_range("on_centre_weight", on_centre_weight, 0.0, MAX_ON_CENTRE_WEIGHT))


def _build(joints: int, theta_rad: np.ndarray) -> Any:
    import casadi

    shafts = joints - 1
    count = len(theta_rad)
    p = casadi.SX.sym("p", joints + shafts + count + 2)
    x = casadi.SX.sym("x", shafts)
    cos_beta = [p[k] for k in range(joints)]
    phases = [np.pi / 2 + x[k] - p[joints + k] for k in range(shafts)]
    window = p[joints + shafts:joints + shafts + count]
    weight, scale = p[joints + shafts + count], p[joints + shafts + count + 1]
    m11, m12, m21, m22 = chain_matrix_expression(cos_beta, phases)
    determinant = m11 * m22 - m12 * m21
    cosine, sine = casadi.DM(np.cos(theta_rad)), casadi.DM(np.sin(theta_rad))
    first = m11 * cosine + m12 * sine
    second = m21 * cosine + m22 * sine
    ratio = determinant / (first * first + second * second)
    mean = casadi.dot(window, ratio)
    variance = casadi.dot(window, (ratio - mean) ** 2)
    objective = scale * (casadi.sum1((ratio - 1.0) ** 2) / count + weight * variance)
    return compile_nlp(f"sso_column_on_centre_{joints}_{count}", x, p, objective)
