"""Closed form of the exact Hooke-joint chain: one 2x2 matrix, no quadrature.

In the exact model (``sso._kinematics.hooke``) joint ``k`` maps the direction
``(cos a, sin a)`` of its driving yoke to ``(cos a, cos beta_k sin a)`` up to length,
and a phase is a rotation. With ``R(phi)`` the rotation by ``+phi`` (the driving
angle of joint ``k`` is ``psi_k + Phi_k``) and ``D_k = diag(1, cos beta_k)``, the
output direction is ``R(-Phi_n) M (cos theta, sin theta)`` with

    M = D_n R(phi_(n-1)) D_(n-1) ... R(phi_1) D_1.

The final rotation changes neither lengths nor angle rates, so everything follows
from ``M`` (``v = (cos theta, sin theta)``, ``det M = prod cos beta_k > 0``):

* speed ratio ``w_out / w_in = det M / |M v|^2`` (the rate of the angle of ``M v``);
  its mean over a turn is exactly 1;
* residual error ``RE = |M|_F^2 / (2 det M) - 1
  = ((m11 - m22)^2 + (m12 + m21)^2) / (2 det M) = |r|^2`` with the two residuals
  ``r = (m11 - m22, m12 + m21) / sqrt(2 det M)`` (zero exactly when ``M`` is a
  scaled rotation);
* ratio extremes ``det M / s_max^2`` and ``det M / s_min^2`` (singular values of
  ``M``), which reduce to ``1 + RE -/+ sqrt(RE (RE + 2))``: reciprocal, and computed
  here without cancellation.

The chain is written once against a namespace ``xp`` (``numpy`` or ``casadi``), as in
``sso._kinematics.hooke``; a 2x2 matrix is a tuple ``(m11, m12, m21, m22)`` of
entries that broadcast, so numpy arrays with leading axes evaluate many designs at
once and CasADi symbols give an expression graph. The Jacobian of the residuals
costs ``O(n)`` matrix products (prefix and suffix products of the chain).
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Sequence
from typing import Any

import numpy as np

Matrix = tuple[Any, Any, Any, Any]


def _product(left: Matrix, right: Matrix) -> Matrix:
    """``left @ right`` of two 2x2 matrices stored as entry tuples."""
    a11, a12, a21, a22 = left
    b11, b12, b21, b22 = right
    return (a11 * b11 + a12 * b21, a11 * b12 + a12 * b22,
            a21 * b11 + a22 * b21, a21 * b12 + a22 * b22)


def _bend_left(cosine: Any, matrix: Matrix) -> Matrix:
    """``diag(1, cosine) @ matrix``."""
    return matrix[0], matrix[1], cosine * matrix[2], cosine * matrix[3]


def _bend_right(matrix: Matrix, cosine: Any) -> Matrix:
    """``matrix @ diag(1, cosine)``."""
    return matrix[0], matrix[1] * cosine, matrix[2], matrix[3] * cosine


def _check_counts(beta_rad: Sequence[Any], phase_rad: Sequence[Any]) -> None:
    """Raise ValueError unless there is a joint and one phase fewer than joints."""
    if len(beta_rad) < 1:
        raise ValueError("beta_rad is empty: a chain needs at least 1 joint")
    if len(phase_rad) != len(beta_rad) - 1:
        raise ValueError(
            f"phase_rad has {len(phase_rad)} entries; {len(beta_rad)} joints need "
            f"{len(beta_rad) - 1}"
        )


def _factors(xp: Any, beta_rad: Sequence[Any], phase_rad: Sequence[Any]) -> list[Matrix]:
    """The chain's factors from the input side: ``D_1, R(phi_1), D_2, ..., D_n``."""
    _check_counts(beta_rad, phase_rad)
    factors: list[Matrix] = []
    for k, beta in enumerate(beta_rad):
        if k > 0:
            cos_phase, sin_phase = xp.cos(phase_rad[k - 1]), xp.sin(phase_rad[k - 1])
            factors.append((cos_phase, -sin_phase, sin_phase, cos_phase))
        cos_beta = xp.cos(beta)
        factors.append((1, 0, 0, cos_beta))
    return factors


def chain_matrix(xp: Any, beta_rad: Sequence[Any], phase_rad: Sequence[Any]) -> Matrix:
    """The chain matrix ``M = D_n R(phi_(n-1)) ... R(phi_1) D_1`` as ``(m11, m12, m21, m22)``.

    Parameters
    ----------
    xp : module
        ``numpy``, ``casadi`` or ``math``: supplies ``sin`` and ``cos``.
    beta_rad : sequence
        Operating angle of each joint (rad), ``n >= 1`` entries: numbers, numpy
        arrays that broadcast against each other, or CasADi symbols.
    phase_rad : sequence
        Relative phases ``phi_1 .. phi_(n-1)`` (rad).

    Returns
    -------
    tuple
        The four entries of ``M`` (dimensionless), broadcast over the inputs.

    Raises
    ------
    ValueError
        If there is no joint or the phase count is not ``len(beta_rad) - 1``.
    """
    _check_counts(beta_rad, phase_rad)
    return chain_entries([xp.cos(beta) for beta in beta_rad],
                         [xp.cos(phase) for phase in phase_rad],
                         [xp.sin(phase) for phase in phase_rad])


def chain_entries(cos_beta: Sequence[Any], cos_phase: Sequence[Any],
                  sin_phase: Sequence[Any]) -> Matrix:
    """Entries ``(m11, m12, m21, m22)`` of ``M`` from the cosines and sines alone.

    Nothing but ``+ - *``, so any arithmetic works (floats, numpy, CasADi). RE does
    not change when ``M`` is scaled, so a rotation may be given scaled
    (``lambda (cos phi, sin phi)``, any ``lambda != 0``).

    Parameters
    ----------
    cos_beta : sequence
        ``cos beta_k`` of each joint (``n`` entries).
    cos_phase, sin_phase : sequence
        ``cos phi_k`` and ``sin phi_k`` of each phase (``n - 1`` entries each).
    """
    m11: Any = 1.0
    m12: Any = 0.0
    m21: Any = 0.0
    m22: Any = cos_beta[0]
    for cosine, c, s in zip(cos_beta[1:], cos_phase, sin_phase, strict=True):
        top_left, top_right = c * m11 - s * m21, c * m12 - s * m22
        m21, m22 = cosine * (s * m11 + c * m21), cosine * (s * m12 + c * m22)
        m11, m12 = top_left, top_right
    return m11, m12, m21, m22


def chain_determinant(xp: Any, beta_rad: Sequence[Any]) -> Any:
    """``det M = prod cos beta_k`` (rotations have determinant 1)."""
    determinant: Any = 1
    for beta in beta_rad:
        determinant = determinant * xp.cos(beta)
    return determinant


def matrix_residual_error(matrix: Matrix) -> Any:
    """``RE = ((m11 - m22)^2 + (m12 + m21)^2) / (2 det M)`` of a chain matrix given by entries.

    For matrices built elsewhere (products of chains, enumerated phasings); the
    determinant is taken from the entries.
    """
    m11, m12, m21, m22 = matrix
    return ((m11 - m22) ** 2 + (m12 + m21) ** 2) / (2.0 * (m11 * m22 - m12 * m21))


def residuals(xp: Any, beta_rad: Sequence[Any], phase_rad: Sequence[Any]) -> tuple[Any, Any]:
    """The two least-squares residuals ``r`` with ``RE = r_1^2 + r_2^2`` (dimensionless).

    ``r = (m11 - m22, m12 + m21) / sqrt(2 det M)``. Parameters as in
    :func:`chain_matrix`.
    """
    m11, m12, m21, m22 = chain_matrix(xp, beta_rad, phase_rad)
    scale = 1 / xp.sqrt(2 * chain_determinant(xp, beta_rad))
    return (m11 - m22) * scale, (m12 + m21) * scale


def residual_error(xp: Any, beta_rad: Sequence[Any], phase_rad: Sequence[Any]) -> Any:
    """Residual error ``RE`` of the exact model, mean square of ``w_out/w_in - 1``.

    Exact (no quadrature) for every operating angle below 90 deg. Parameters as
    in :func:`chain_matrix`.
    """
    first, second = residuals(xp, beta_rad, phase_rad)
    return first * first + second * second


def speed_ratio(xp: Any, cos_theta: Any, sin_theta: Any, beta_rad: Sequence[Any],
                phase_rad: Sequence[Any]) -> Any:
    """Speed ratio ``w_out / w_in = det M / |M v|^2`` at ``v = (cos theta, sin theta)``.

    Parameters
    ----------
    xp : module
        ``numpy`` or ``casadi``.
    cos_theta, sin_theta : array
        Cosine and sine of the input angles; they broadcast against the entries
        of ``M`` (for numpy designs of shape ``(m,)`` pass angles of shape ``(m, k)``
        and designs of shape ``(m, 1)``).
    beta_rad, phase_rad : sequence
        As in :func:`chain_matrix`.
    """
    m11, m12, m21, m22 = chain_matrix(xp, beta_rad, phase_rad)
    first = m11 * cos_theta + m12 * sin_theta
    second = m21 * cos_theta + m22 * sin_theta
    return chain_determinant(xp, beta_rad) / (first * first + second * second)


def ratio_extremes(xp: Any, beta_rad: Sequence[Any], phase_rad: Sequence[Any]) -> tuple[Any, Any]:
    """Least and greatest speed ratio over a turn, ``det M / s_max^2`` and ``det M / s_min^2``.

    With ``RE = (|M|_F^2 - 2 det M) / (2 det M)`` these are
    ``1 + RE -/+ sqrt(RE (RE + 2))``, reciprocal to each other; the least is
    computed as the reciprocal of the greatest so neither cancels.
    """
    error = residual_error(xp, beta_rad, phase_rad)
    greatest = 1 + error + xp.sqrt(error * (error + 2))
    return 1 / greatest, greatest


def peak_ratio_slope(xp: Any, beta_rad: Sequence[Any], phase_rad: Sequence[Any]) -> Any:
    """Largest ``|d(w_out / w_in) / d theta|`` over a turn (1/rad), from the chain matrix.

    With ``G = M^T M``, ``|M v|^2 = A + R cos(2 theta - delta)`` where ``A = trace(G) / 2``
    and ``R = sqrt(((g11 - g22) / 2)^2 + g12^2)``, so the ratio is
    ``det M / (A + R cos u)`` and its slope ``2 R det M sin u / (A + R cos u)^2``. That
    is largest where ``R c^2 - A c - 2 R = 0`` for ``c = cos u``, whose root in
    ``[-1, 1]`` is ``c = (A - S) / (2 R)``, ``S = sqrt(A^2 + 8 R^2)``. Near 90 deg
    ``A - R`` (the least ``|M v|^2``) and ``1 + c`` are tiny differences of large
    numbers, so both are written without subtraction through ``A^2 - R^2 = det^2``:
    ``A - R = det^2 / (A + R)``, ``S - 3 R = det^2 / (S + 3 R)`` and
    ``1 + c = ((A - R) + (S - 3 R)) / (A + S)``, with ``det M = prod cos beta_k``
    (the entries' ``m11 m22 - m12 m21`` cancels near 90 deg). Times the input speed
    squared (rad/s) it is the peak output acceleration. Parameters as in
    :func:`chain_matrix` (``math`` for one design, ``numpy`` for many at once).
    """
    m11, m12, m21, m22 = chain_matrix(xp, beta_rad, phase_rad)
    g11, g22 = m11 * m11 + m21 * m21, m12 * m12 + m22 * m22
    g12 = m11 * m12 + m21 * m22
    half_difference = 0.5 * (g11 - g22)
    mean = 0.5 * (g11 + g22)
    amplitude = xp.sqrt(half_difference * half_difference + g12 * g12)
    determinant = chain_determinant(xp, beta_rad)
    squared = determinant * determinant
    root = xp.sqrt(mean * mean + 8.0 * amplitude * amplitude)
    least = squared / (mean + amplitude)
    one_plus_cosine = (least + squared / (root + 3.0 * amplitude)) / (mean + root)
    sine = xp.sqrt(one_plus_cosine * (2.0 - one_plus_cosine))
    # Divided twice rather than by the square: near the floor on det M the
    # denominator (about det^2) squared would underflow.
    denominator = least + amplitude * one_plus_cosine
    return 2.0 * amplitude * (determinant * sine / denominator) / denominator


def lag_swing(beta_rad: Sequence[float], phase_rad: Sequence[float]) -> tuple[float, float]:
    """How the output angle's lag ``psi_out - theta`` moves about its mean over a turn (rad).

    As a map of ``z = e^(i theta)``, ``M v = e^(i theta) (a + b e^(-2 i theta))`` with
    ``|b| < |a|`` (``det M = |a|^2 - |b|^2 > 0``), so the lag is a constant plus
    ``arg(1 + (b / a) e^(-2 i theta))``, which sweeps ``[-asin |b/a|, asin |b/a|]``.
    Near 90 deg ``|b/a|`` is close to 1, where ``asin`` magnifies round-off; the swing
    is computed as ``atan2(|b|, sqrt(det M))`` with ``det M = prod cos beta_k``.

    Returns
    -------
    at_zero : float
        The moving part at ``theta = 0``, ``arg(1 + b / a)``: the lag at ``theta = 0``
        minus this is the constant.
    swing : float
        ``asin |b / a|``, the largest departure from the constant.
    """
    m11, m12, m21, m22 = chain_matrix(math, beta_rad, phase_rad)
    a, b = 0.5 * complex(m11 + m22, m21 - m12), 0.5 * complex(m11 - m22, m21 + m12)
    swing = math.atan2(abs(b), math.sqrt(chain_determinant(math, beta_rad)))
    return cmath.phase(1.0 + b / a), swing


def residual_jacobian(xp: Any, beta_rad: Sequence[Any],
                      phase_rad: Sequence[Any]) -> tuple[tuple[Any, Any], list[Any], list[Any]]:
    """Residuals and their derivatives with respect to every angle, in ``O(n)`` products.

    ``dM/d beta_k`` and ``dM/d phi_k`` replace one factor by its derivative, so each
    is ``(product of the factors after it) dF (product of the factors before it)``;
    the prefix and suffix products are built once. ``d ln det M / d beta_k =
    -tan beta_k`` and ``det M`` does not depend on the phases.

    Parameters
    ----------
    xp, beta_rad, phase_rad
        As in :func:`chain_matrix`.

    Returns
    -------
    residuals : (r1, r2)
        As :func:`residuals`.
    d_beta : list of (dr1, dr2)
        Derivatives (per rad) with respect to ``beta_1 .. beta_n``.
    d_phase : list of (dr1, dr2)
        Derivatives (per rad) with respect to ``phi_1 .. phi_(n-1)``.
    """
    factors = _factors(xp, beta_rad, phase_rad)
    count = len(factors)
    # Factor 2k is the bend D_(k+1) = diag(1, cos beta): a product with it scales one row
    # (on the left) or one column (on the right), two multiplications instead of twelve.
    # before[i] = F_(i-1) ... F_0; after[i] = F_(count-1) ... F_(i+1).
    before: list[Any] = [None] * count
    after: list[Any] = [None] * count
    for i in range(1, count):
        before[i] = (factors[0] if i == 1 else _bend_left(factors[i - 1][3], before[i - 1])
                     if (i - 1) % 2 == 0 else _product(factors[i - 1], before[i - 1]))
    for i in range(count - 2, -1, -1):
        after[i] = (factors[-1] if i == count - 2 else _bend_right(after[i + 1],
                                                                   factors[i + 1][3])
                    if (i + 1) % 2 == 0 else _product(after[i + 1], factors[i + 1]))
    matrix = factors[-1] if count == 1 else _bend_left(factors[-1][3], before[-1])
    determinant = chain_determinant(xp, beta_rad)
    scale = 1 / xp.sqrt(2 * determinant)
    residual = ((matrix[0] - matrix[3]) * scale, (matrix[1] + matrix[2]) * scale)

    def derivative(i: int, d_factor: Matrix, d_log_scale: Any) -> tuple[Any, Any]:
        d_matrix = d_factor
        if before[i] is not None:
            d_matrix = _product(d_matrix, before[i])
        if after[i] is not None:
            d_matrix = _product(after[i], d_matrix)
        return ((d_matrix[0] - d_matrix[3]) * scale + residual[0] * d_log_scale,
                (d_matrix[1] + d_matrix[2]) * scale + residual[1] * d_log_scale)

    def bend_derivative(i: int, sin_beta: Any, d_log_scale: Any) -> tuple[Any, Any]:
        # dD = diag(0, -sin beta): dD B = (0, 0, u, v) with (u, v) = -sin beta (b21, b22),
        # and A (0, 0, u, v) = (a12 u, a12 v, a22 u, a22 v).
        if before[i] is None:
            u, v = 0 * sin_beta, -sin_beta
        else:
            u, v = -sin_beta * before[i][2], -sin_beta * before[i][3]
        d_matrix = ((0 * u, 0 * v, u, v) if after[i] is None else
                    (after[i][1] * u, after[i][1] * v, after[i][3] * u, after[i][3] * v))
        return ((d_matrix[0] - d_matrix[3]) * scale + residual[0] * d_log_scale,
                (d_matrix[1] + d_matrix[2]) * scale + residual[1] * d_log_scale)

    d_beta, d_phase = [], []
    for k, beta in enumerate(beta_rad):
        sin_beta, cos_beta = xp.sin(beta), xp.cos(beta)
        # d ln(scale) / d beta = -(1/2) d ln det / d beta = tan(beta) / 2
        d_beta.append(bend_derivative(2 * k, sin_beta, sin_beta / (2 * cos_beta)))
    for k, phase in enumerate(phase_rad):
        cos_phase, sin_phase = xp.cos(phase), xp.sin(phase)
        d_phase.append(derivative(2 * k + 1, (-sin_phase, -cos_phase, cos_phase, -sin_phase),
                                  0))
    return residual, d_beta, d_phase


def residuals_and_jacobian_numpy(beta_rad: Any, phase_rad: Any) -> tuple[np.ndarray, np.ndarray]:
    """Residuals and Jacobian of many designs at once, as numpy arrays.

    Parameters
    ----------
    beta_rad : array of shape (..., n)
        Operating angles (rad).
    phase_rad : array of shape (..., n - 1)
        Relative phases (rad).

    Returns
    -------
    residual : numpy.ndarray of shape (..., 2)
    jacobian : numpy.ndarray of shape (..., 2, 2n - 1)
        Columns: ``beta_1 .. beta_n`` then ``phi_1 .. phi_(n-1)`` (per rad).
    """
    beta = np.asarray(beta_rad, dtype=float)
    phase = np.asarray(phase_rad, dtype=float)
    residual, d_beta, d_phase = residual_jacobian(
        np, [beta[..., k] for k in range(beta.shape[-1])],
        [phase[..., k] for k in range(phase.shape[-1])])
    shape = np.broadcast_shapes(beta.shape[:-1], phase.shape[:-1])
    columns = [np.broadcast_to(np.stack(column, axis=-1), (*shape, 2))
               for column in (*d_beta, *d_phase)]
    return (np.broadcast_to(np.stack(residual, axis=-1), (*shape, 2)),
            np.stack(columns, axis=-1))


def residual_and_jacobian_complex(
    beta_rad: Sequence[float], phase_rad: Sequence[float], *, beta_free: bool = True,
    phase_free: bool = True,
) -> tuple[complex, list[complex]]:
    """Residuals and Jacobian of one design in plain Python complex numbers (no numpy, no CasADi).

    A real 2x2 matrix acts on ``z = x + i y`` as ``z -> a z + b conj(z)``, with
    ``a = (m11 + m22 + i (m21 - m12)) / 2`` and ``b = (m11 - m22 + i (m21 + m12)) / 2``,
    so the residuals of :func:`residuals` are ``r1 + i r2 = b sqrt(2 / det M)``.
    ``D_k`` is the map ``(p_k, q_k) = ((1 + cos beta_k) / 2, (1 - cos beta_k) / 2)``
    and ``R(phi)`` is ``(e^(i phi), 0)``. Carrying ``c = conj(b)`` instead of ``b``
    keeps every conjugation out of the loops: ``D_k`` maps ``(a, c)`` to
    ``(p a + q c, p c + q a)`` and ``R(phi)`` to ``(e^(i phi) a, e^(-i phi) c)``.
    With ``(a, c)`` the map before a factor and ``(E, F)`` the conjugate of the map
    ``(A, B)`` after it,

    * ``d conj(b) / d phi = -i (E c - F a)`` (``(a, c)`` taken after the rotation);
    * ``d conj(b) / d beta = -(sin beta / 2) (E - F) (c - a)``, and
      ``d ln sqrt(2 / det M) / d beta = tan(beta) / 2``.

    This is the prefix/suffix scheme of :func:`residual_jacobian`, written on Python
    complex numbers: a design of a few joints costs a few microseconds, several
    times less than one numpy call, which is what a single-design least-squares
    solve spends its time on. The tests check it against complex-step derivatives
    of :func:`residuals`.

    Parameters
    ----------
    beta_rad : sequence of float
        Operating angles (rad), ``n >= 1``.
    phase_rad : sequence of float
        Relative phases (rad), ``n - 1``.
    beta_free, phase_free : bool
        Which derivatives to return.

    Returns
    -------
    rho : complex
        ``r1 - i r2`` (dimensionless), the conjugate of the residual pair:
        ``RE = |rho|^2``.
    jacobian : list of complex
        ``d rho / d beta_1 .. d beta_n`` (if ``beta_free``), then ``d rho / d phi_1
        .. d phi_(n-1)`` (if ``phase_free``), per rad.
    """
    count = len(beta_rad)
    last = count - 1
    cos, sin = math.cos, math.sin
    cos_beta = [cos(beta) for beta in beta_rad]
    turns = [complex(cos(phase), sin(phase)) for phase in phase_rad]
    before_a: list[complex] = []
    before_c: list[complex] = []
    a, c = 1.0 + 0.0j, 0.0j
    determinant = 1.0
    for k, cosine in enumerate(cos_beta):
        before_a.append(a)
        before_c.append(c)
        determinant *= cosine
        p, q = 0.5 + 0.5 * cosine, 0.5 - 0.5 * cosine
        a, c = p * a + q * c, p * c + q * a
        if k < last:
            turn = turns[k]
            a *= turn
            c *= turn.conjugate()
    scale = math.sqrt(2.0 / determinant)
    rho = c * scale
    phase_offset = count if beta_free else 0
    jacobian = [0.0j] * (phase_offset + (last if phase_free else 0))
    e, f = 1.0 + 0.0j, 0.0j
    minus_i_scale = -1j * scale
    for k in range(last, -1, -1):
        cosine = cos_beta[k]
        if beta_free:
            half_sine = 0.5 * sin(beta_rad[k])
            jacobian[k] = ((-half_sine * scale) * (e - f) * (before_c[k] - before_a[k])
                           + rho * (half_sine / cosine))
        p, q = 0.5 + 0.5 * cosine, 0.5 - 0.5 * cosine
        e, f = e * p + f * q, e * q + f * p
        if k:
            if phase_free:
                jacobian[phase_offset + k - 1] = minus_i_scale * (e * before_c[k]
                                                                  - f * before_a[k])
            turn = turns[k - 1]
            e *= turn.conjugate()
            f *= turn
    return rho, jacobian


def residual_hessian_complex(
    beta_rad: Sequence[float], phase_rad: Sequence[float], *, beta_free: bool = True,
    phase_free: bool = True,
) -> tuple[complex, list[complex], list[list[float]]]:
    """Residual and Jacobian of one design's ``rho``, and the Hessian of ``RE = |rho|^2``.

    ``rho = s c`` as in :func:`residual_and_jacobian_complex`: ``c`` is the second
    component of the chain's factors applied to ``(a, c) = (1, 0)`` (``D_k`` maps
    ``(a, c)`` to ``(p a + q c, q a + p c)``, ``R(phi)`` to ``(e^(i phi) a,
    e^(-i phi) c)``) and ``s = sqrt(2 / prod cos beta_k)``. Each factor is linear in
    ``(a, c)`` and depends on one angle, so with ``u_t`` the pair before factor
    ``t`` and ``l_t`` the linear map from the pair after it to ``c``,

    * ``dc/dt = l_t(F_t' u_t)`` and ``d2c/dt2 = l_t(F_t'' u_t)``;
    * ``d2c/dt dt' = l_t'(F_t' F_(t'-1) ... F_(t+1) F_t' u_t)`` for ``t < t'``,

    with ``D' = (sin beta / 2) (c - a, a - c)``, ``D'' = (cos beta / 2) (c - a, a - c)``,
    ``R' = (i e^(i phi) a, -i e^(-i phi) c)`` and ``R'' = -R``; and with ``L = ln s``
    (``dL/d beta = tan beta / 2``, ``d2L/d beta2 = 1 / (2 cos^2 beta)``),
    ``d2 rho = s ((L_i L_j + L_ij) c + L_i c_j + L_j c_i + c_ij)``. The cost grows with
    the square of the free variables, against one residual-and-Jacobian call per
    variable for a difference Hessian. The tests check it against CasADi's symbolic
    Hessian of :func:`residuals`.

    Parameters
    ----------
    beta_rad : sequence of float
        Operating angles (rad), ``n >= 1``.
    phase_rad : sequence of float
        Relative phases (rad), ``n - 1``.
    beta_free, phase_free : bool
        Which variables to differentiate by (operating angles first, then phases).

    Returns
    -------
    rho : complex
        ``r1 - i r2`` (``RE = |rho|^2``).
    jacobian : list of complex
        ``d rho / dx_i`` per rad.
    hessian : list of list of float
        ``d2 RE / dx_i dx_j`` per rad^2 (symmetric, both triangles filled):
        ``2 Re(conj(rho_j) rho_i + conj(rho) rho_ij)``.
    """
    count = len(beta_rad)
    phase_offset = count if beta_free else 0
    size = phase_offset + (count - 1 if phase_free else 0)
    # The factors in the order they act: (variable index or -1, is a bend, then
    # p, q, sin(beta) / 2, cos(beta) / 2 of a bend or e^(i phi), e^(-i phi) of a turn).
    cos_beta = [math.cos(beta) for beta in beta_rad]
    sin_beta = [math.sin(beta) for beta in beta_rad]
    factors: list[tuple[int, bool, Any, Any, float, float]] = []
    for k, cosine in enumerate(cos_beta):
        factors.append((k if beta_free else -1, True, 0.5 + 0.5 * cosine, 0.5 - 0.5 * cosine,
                        0.5 * sin_beta[k], 0.5 * cosine))
        if k < count - 1:
            turn = complex(math.cos(phase_rad[k]), math.sin(phase_rad[k]))
            factors.append((phase_offset + k if phase_free else -1, False, turn,
                            turn.conjugate(), 0.0, 0.0))

    before: list[tuple[complex, complex]] = []
    a, c = 1.0 + 0.0j, 0.0j
    for _, is_bend, first, second, _, _ in factors:
        before.append((a, c))
        a, c = (first * a + second * c, second * a + first * c) if is_bend else (first * a,
                                                                                  second * c)
    final_c = c
    # after[t] = (e, f): the map (a, c) -> e a + f c from the pair after factor t to
    # the final c; the map before factor t is that map composed with the factor.
    after: list[tuple[complex, complex]] = [(0.0j, 1.0 + 0.0j)] * len(factors)
    e, f = 0.0j, 1.0 + 0.0j
    for t in range(len(factors) - 1, -1, -1):
        after[t] = (e, f)
        _, is_bend, first, second, _, _ = factors[t]
        e, f = (e * first + f * second, e * second + f * first) if is_bend else (e * first,
                                                                                 f * second)

    c_first = [0.0j] * size
    c_second = [[0.0j] * size for _ in range(size)]
    for t, (variable, is_bend, first, second, half_sine, half_cosine) in enumerate(factors):
        if variable < 0:
            continue
        e, f = after[t]
        a, c = before[t]
        if is_bend:
            # D' = (sin beta / 2) (c - a, a - c), D'' = (cos beta / 2) (c - a, a - c).
            c_second[variable][variable] = half_cosine * (c - a) * (e - f)
            a, c = half_sine * (c - a), half_sine * (a - c)
        else:
            # R' = (i e^(i phi) a, -i e^(-i phi) c), R'' = -R.
            c_second[variable][variable] = -(e * first * a + f * second * c)
            a, c = 1j * first * a, -1j * second * c
        c_first[variable] = e * a + f * c
        for later in range(t + 1, len(factors)):
            other, other_bend, other_first, other_second, other_sine, _ = factors[later]
            if other >= 0:
                e, f = after[later]
                c_second[variable][other] = c_second[other][variable] = (
                    other_sine * (c - a) * (e - f) if other_bend
                    else 1j * (e * other_first * a - f * other_second * c))
            a, c = ((other_first * a + other_second * c, other_second * a + other_first * c)
                    if other_bend else (other_first * a, other_second * c))

    scale = math.sqrt(2.0 / math.prod(cos_beta))
    log_first = [0.0] * size
    log_second = [0.0] * size
    if beta_free:
        for k, cosine in enumerate(cos_beta):
            log_first[k] = 0.5 * sin_beta[k] / cosine
            log_second[k] = 0.5 / (cosine * cosine)
    rho = scale * final_c
    jacobian = [scale * (log_first[i] * final_c + c_first[i]) for i in range(size)]
    # d2 f / dx_i dx_j = 2 Re(conj(d rho / dx_j) d rho / dx_i + conj(rho) d2 rho / dx_i dx_j).
    weight = 2.0 * scale * rho.conjugate()
    hessian = [[0.0] * size for _ in range(size)]
    for i in range(size):
        slope_i, log_i, c_i = jacobian[i], log_first[i], c_first[i]
        for j in range(i + 1):
            curvature = ((log_i * log_first[j] + (log_second[i] if i == j else 0.0)) * final_c
                         + log_i * c_first[j] + log_first[j] * c_i + c_second[i][j])
            hessian[i][j] = hessian[j][i] = (
                2.0 * (slope_i.real * jacobian[j].real + slope_i.imag * jacobian[j].imag)
                + (weight * curvature).real)
    return rho, jacobian, hessian
