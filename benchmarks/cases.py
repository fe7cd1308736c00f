"""Benchmark cases, the accurate residual error, and the baseline a MATLAB porter would write.

The paper's three cases follow ``docs/model.md`` (section "The paper's
three cases"): input 25 rpm, three joints, the starts and bounds the paper's results
imply, and fmincon's objective-evaluation counts 120 / 135 / 297. The two-, four- and
six-joint cases come in pairs: bounds that let the joints cancel (the exact model
then has whole curves of designs with RE = 0) and bounds that do not (one joint
bent far more than the others can undo).
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np

from sso._shafts.options import DesignProblem, build_problem
from sso._shafts.quadrature import QuadratureWarning, adaptive_residual_error

INPUT_SPEED_RPM = 25.0
# The accurate RE that errors are measured with: the adaptive rule, far tighter
# than the solvers' tolerances. Its absolute floor is the round-off of the mean of
# (ratio - 1)^2: the ratio carries a few ulp of error, so RE carries about
# 2 * |ratio - 1| * ulp = 2 * sqrt(RE) * eps times a small factor.
ACCURATE_RTOL = 1e-13
ROUND_OFF_FACTOR = 16.0
# The baseline samples one full turn at 1 deg steps, both ends included, as the
# paper's plots suggest (0:1:360 in MATLAB).
BASELINE_ANGLES_DEG = np.linspace(0.0, 360.0, 361)


@dataclass(frozen=True)
class BenchmarkCase:
    """One optimisation problem of the benchmark.

    Attributes
    ----------
    name : str
        Short name, unique together with ``model``.
    model : {"exact", "paper"}
    option : int
        1 phases, 2 operating angles (phases 90 deg), 3 both.
    beta_deg, phase_deg : tuple of float
        The start design (deg).
    beta_bounds_deg, phase_bounds_deg : tuple
        Bounds (deg), one pair for all or one pair per joint / phase.
    fmincon_nfev : int or None
        Objective evaluations fmincon needed in the paper (paper cases only).
    """

    name: str
    model: str
    option: int
    beta_deg: tuple[float, ...]
    phase_deg: tuple[float, ...]
    beta_bounds_deg: Any
    phase_bounds_deg: Any = (0.0, 180.0)
    fmincon_nfev: int | None = None

    @property
    def key(self) -> str:
        """``name/model``, the key of the case in ``best_known.json``."""
        return f"{self.name}/{self.model}"

    def problem(self) -> DesignProblem:
        """The design problem (layout, bounds, start moved onto the bounds)."""
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return build_problem(self.beta_deg, self.phase_deg, self.model, self.option,
                                 self.beta_bounds_deg, self.phase_bounds_deg)

    def optimise_arguments(self) -> dict[str, Any]:
        """Keyword arguments of :func:`sso.optimise` for this case (no series)."""
        return {"option": self.option, "beta_bounds_deg": self.beta_bounds_deg,
                "phase_bounds_deg": self.phase_bounds_deg,
                "input_speed_rpm": INPUT_SPEED_RPM}


def _paper_cases(model: str) -> list[BenchmarkCase]:
    return [
        BenchmarkCase("paper-option1", model, 1, (15.0, 20.0, 9.0), (30.0, 40.0),
                      (0.0, 40.0), fmincon_nfev=120),
        BenchmarkCase("paper-option2", model, 2, (10.0, 15.0, 30.0), (90.0, 90.0),
                      (7.0, 25.0), fmincon_nfev=135),
        BenchmarkCase("paper-option3", model, 3, (30.0, 40.0, 50.0), (90.0, 90.0),
                      (10.0, 40.0), fmincon_nfev=297),
    ]


CASES: tuple[BenchmarkCase, ...] = (
    *_paper_cases("exact"),
    *_paper_cases("paper"),
    # Two joints, both free in [5, 30]: equal angles at 90 deg cancel exactly.
    BenchmarkCase("2-joint-cancel", "exact", 3, (25.0, 10.0), (30.0,), (5.0, 30.0)),
    # Joint 1 in [20, 30], joint 2 in [5, 10]: joint 2 cannot undo joint 1.
    BenchmarkCase("2-joint-no-cancel", "exact", 3, (25.0, 8.0), (30.0,),
                  ((20.0, 30.0), (5.0, 10.0))),
    BenchmarkCase("4-joint-cancel", "exact", 3, (30.0, 10.0, 25.0, 15.0), (20.0, 45.0, 60.0),
                  (5.0, 35.0)),
    # Fluctuation grows about as beta^2: 30^2 = 900 > 3 * 10^2.
    BenchmarkCase("4-joint-no-cancel", "exact", 3, (32.0, 8.0, 6.0, 9.0), (20.0, 45.0, 60.0),
                  ((30.0, 35.0), (5.0, 10.0), (5.0, 10.0), (5.0, 10.0))),
    BenchmarkCase("6-joint-cancel", "exact", 3, (30.0, 10.0, 25.0, 15.0, 20.0, 12.0),
                  (20.0, 45.0, 60.0, 120.0, 150.0), (5.0, 35.0)),
    # 35^2 = 1225 > 5 * 8^2 = 320.
    BenchmarkCase("6-joint-no-cancel", "exact", 3, (36.0, 4.0, 6.0, 3.0, 7.0, 5.0),
                  (20.0, 45.0, 60.0, 120.0, 150.0),
                  ((35.0, 40.0), *[(2.0, 8.0)] * 5)),
)


def accurate_residual_error(beta_deg: Any, phase_deg: Any, model: str) -> float:
    """RE of a design by the adaptive rule at ``ACCURATE_RTOL`` (dimensionless).

    Raises
    ------
    RuntimeError
        If the quadrature cannot reach that tolerance (the error would be unknown).
    """
    beta_rad, phase_rad = list(np.radians(beta_deg)), list(np.radians(phase_deg))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", QuadratureWarning)
        rough, _ = adaptive_residual_error(beta_rad, phase_rad, model, ACCURATE_RTOL)
    round_off = ROUND_OFF_FACTOR * np.finfo(float).eps * np.sqrt(abs(rough))
    with warnings.catch_warnings():
        warnings.simplefilter("error", QuadratureWarning)
        value, _ = adaptive_residual_error(beta_rad, phase_rad, model, ACCURATE_RTOL, round_off)
    return float(value)


def baseline_residual_error(beta_rad: np.ndarray, phase_rad: np.ndarray, model: str) -> float:
    """RE the way a MATLAB porter writes it: the mean over 361 angles of 0..360 deg.

    Written independently of :mod:`sso._kinematics.hooke` from the paper's eq. 5 and 8:
    shaft angles are carried as angles through ``atan2`` (paper model: every joint
    sees the input angle).
    """
    theta = np.radians(BASELINE_ANGLES_DEG)
    cumulative_phase = np.concatenate([[0.0], np.cumsum(phase_rad)])
    shaft_angle = theta
    ratio = np.ones_like(theta)
    for beta, phase in zip(beta_rad, cumulative_phase, strict=True):
        joint_angle = (theta if model == "paper" else shaft_angle) + phase
        sin_a = np.sin(joint_angle)
        ratio = ratio * np.cos(beta) / (1.0 - np.sin(beta) ** 2 * sin_a**2)
        shaft_angle = np.arctan2(np.cos(beta) * sin_a, np.cos(joint_angle)) - phase
    return float(np.mean((ratio - 1.0) ** 2))


@dataclass(frozen=True)
class BaselineRun:
    """Outcome of one baseline solve: design (deg), counts and wall time."""

    beta_deg: tuple[float, ...]
    phase_deg: tuple[float, ...]
    nfev: int
    nit: int
    success: bool
    time_s: float


def baseline_solve(case: BenchmarkCase, tolerance: float, max_iterations: int = 500,
                   start_rad: np.ndarray | None = None) -> BaselineRun:
    """scipy SLSQP on :func:`baseline_residual_error` with finite-difference gradients.

    ``ftol`` is ``tolerance`` as scipy defines it (absolute change of the objective).
    """
    from scipy.optimize import minimize

    problem = case.problem()
    parameters = problem.parameters_rad

    def objective(x: np.ndarray) -> float:
        beta, phase = problem.split(x, parameters)
        return baseline_residual_error(np.asarray(beta), np.asarray(phase), case.model)

    x0 = problem.start_rad if start_rad is None else start_rad
    started = time.perf_counter()
    answer = minimize(objective, x0, method="SLSQP",
                      bounds=list(zip(problem.lower_rad, problem.upper_rad, strict=True)),
                      options={"ftol": tolerance, "maxiter": max_iterations})
    elapsed = time.perf_counter() - started
    x = np.clip(answer.x, problem.lower_rad, problem.upper_rad)
    beta_deg, phase_deg = (np.degrees(values) for values in problem.split(x, parameters))
    return BaselineRun(tuple(beta_deg.tolist()), tuple(phase_deg.tolist()), int(answer.nfev),
                       int(answer.nit), bool(answer.success), elapsed)
