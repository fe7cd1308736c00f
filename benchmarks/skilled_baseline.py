"""The solver a skilled engineer writes by hand for the exact model, as the baseline to beat.

Written independently of the ``sso`` package: the closed form of the exact chain
(``RE = ((m11 - m22)^2 + (m12 + m21)^2) / (2 det M)`` with
``M = D_n R(phi_(n-1)) ... R(phi_1) D_1``, ``D_k = diag(1, cos beta_k)``) in
vectorised numpy, its gradient by the complex step (all ``p`` perturbed copies of
the design evaluated together in one vectorised pass, so value and gradient cost
one call), scipy SLSQP under the bounds, one start. No quadrature, no finite
differences, no CasADi.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

COMPLEX_STEP = 1e-30


def residual_error(beta_rad: np.ndarray, phase_rad: np.ndarray) -> np.ndarray:
    """RE of the exact model for designs along the leading axis (real or complex input).

    Parameters
    ----------
    beta_rad : array of shape (k, n)
    phase_rad : array of shape (k, n - 1)
    """
    cos_beta = np.cos(beta_rad)
    m11 = np.ones_like(cos_beta[:, 0])
    m12 = np.zeros_like(m11)
    m21 = np.zeros_like(m11)
    m22 = cos_beta[:, 0]
    for joint in range(1, beta_rad.shape[1]):
        c, s = np.cos(phase_rad[:, joint - 1]), np.sin(phase_rad[:, joint - 1])
        m11, m12, m21, m22 = (c * m11 - s * m21, c * m12 - s * m22,
                              s * m11 + c * m21, s * m12 + c * m22)
        m21, m22 = cos_beta[:, joint] * m21, cos_beta[:, joint] * m22
    determinant = np.prod(cos_beta, axis=1)
    error: np.ndarray = ((m11 - m22) ** 2 + (m12 + m21) ** 2) / (2.0 * determinant)
    return error


@dataclass(frozen=True)
class BaselineSolve:
    """One solve: final design (deg), RE, counts, convergence and wall time (s)."""

    beta_deg: np.ndarray
    phase_deg: np.ndarray
    fun: float
    nit: int
    nfev: int
    success: bool
    time_s: float


def solve(beta_deg: np.ndarray, phase_deg: np.ndarray, option: int,
          beta_bounds_deg: Any, phase_bounds_deg: Any,
          ftol: float = 1e-12, max_iterations: int = 500) -> BaselineSolve:
    """Minimise RE from one start with SLSQP and the complex-step gradient.

    Option 1 frees the phases, 2 the operating angles (phases at 90 deg), 3 both.
    Bounds (deg) are one ``(lower, upper)`` pair for all joints / phases or one pair
    each. The start is clipped onto the bounds.
    """
    from scipy.optimize import minimize  # type: ignore[import-untyped]

    started = time.perf_counter()
    n_joints = len(beta_deg)
    beta = np.radians(np.asarray(beta_deg, dtype=float))
    phase = np.radians(np.full(n_joints - 1, 90.0) if option == 2 else
                       np.asarray(phase_deg, dtype=float))
    free_beta, free_phase = option in (2, 3), option in (1, 3)
    beta_bounds = np.broadcast_to(np.radians(np.asarray(beta_bounds_deg, dtype=float)),
                                  (n_joints, 2))
    phase_bounds = np.broadcast_to(np.radians(np.asarray(phase_bounds_deg, dtype=float)),
                                   (n_joints - 1, 2))
    bounds = [beta_bounds] * free_beta + [phase_bounds] * free_phase
    lower, upper = np.concatenate(bounds).T if bounds else (np.zeros(0), np.zeros(0))
    x0 = np.clip(np.concatenate([beta] * free_beta + [phase] * free_phase), lower, upper)
    size = x0.size
    perturbation = 1j * COMPLEX_STEP * np.eye(size)

    def design(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        rows = x.shape[0]
        beta_x = x[:, :n_joints] if free_beta else np.broadcast_to(beta, (rows, n_joints))
        phase_x = (x[:, size - (n_joints - 1):] if free_phase
                   else np.broadcast_to(phase, (rows, n_joints - 1)))
        return beta_x, phase_x

    def value_and_gradient(x: np.ndarray) -> tuple[float, np.ndarray]:
        values = residual_error(*design(x[None, :] + perturbation))
        return float(values[0].real), values.imag / COMPLEX_STEP

    answer = minimize(value_and_gradient, x0, jac=True, method="SLSQP",
                      bounds=list(zip(lower, upper, strict=True)),
                      options={"ftol": ftol, "maxiter": max_iterations})
    x = np.clip(answer.x, lower, upper)
    elapsed = time.perf_counter() - started
    beta_out, phase_out = design(x[None, :])
    return BaselineSolve(np.degrees(beta_out[0]), np.degrees(phase_out[0]),
                         float(residual_error(beta_out, phase_out)[0]), int(answer.nit),
                         int(answer.nfev), bool(answer.success), elapsed)
