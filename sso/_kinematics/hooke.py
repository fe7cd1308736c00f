"""Hooke (Cardan) joints in series: the speed ratio and angle of the output shaft.

The chain is written once against a tiny array namespace ``xp`` that provides
``sin``, ``cos`` and ``sqrt`` (the ``numpy`` module or the ``casadi`` module), so the
numbers in reports and the graph the optimisers differentiate come from the same
code. Conventions follow ``docs/model.md``:

* joint ``k`` has operating angle ``beta_k``; ``phi_k`` is the phase of joint
  ``k + 1`` relative to joint ``k``; phases accumulate, ``Phi_1 = 0`` and
  ``Phi_(k+1) = Phi_k + phi_k``;
* ``exact`` model: joint ``k`` is driven by the true angle of its own input shaft;
* ``paper`` model (the paper's eq. 13/16): every joint sees the input angle.

The exact chain carries the unit vector ``(cos psi, sin psi)`` of each shaft angle
instead of the angle itself, so it is branch-free and smooth for CasADi.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

MODELS = ("exact", "paper")


@dataclass(frozen=True)
class ChainKinematics:
    """Speed ratio of a joint chain and what the evaluation figures need.

    Attributes
    ----------
    speed_ratio : array
        ``w_out / w_in`` at each input angle (dimensionless).
    log_ratio_slope : array
        ``d ln(speed_ratio) / d theta`` (1/rad); times ``speed_ratio`` it is the
        derivative of the ratio with respect to the input angle.
    angle_lag_rad : array
        Output angle minus input angle (rad). Exact model: the true
        transmission error. Paper model: the sum of each joint's own angle
        deviation (eq. 5) evaluated at the joint angle the paper assumes.
    """

    speed_ratio: Any
    log_ratio_slope: Any
    angle_lag_rad: Any


def _joint_terms(xp: Any, cos_a: Any, sin_a: Any, cos_b: Any) -> tuple[Any, Any]:
    """Ratio of one joint and its squared output-vector norm.

    ``cos a^2 + cos b^2 sin a^2`` equals ``1 - sin b^2 sin a^2`` (paper eq. 8) but
    does not cancel when ``b`` nears 90 deg. The ratio is divided by the squared
    length of ``(cos a, sin a)`` as well, which makes it exact for the angle that
    vector points at even when round-off leaves its length a few ulp from 1: for
    ``b = 0`` numerator and denominator are then the same number and the ratio is
    exactly 1 (straight shafts have RE = 0, not round-off).
    """
    norm_squared = cos_a * cos_a + cos_b * cos_b * sin_a * sin_a
    return cos_b * (cos_a * cos_a + sin_a * sin_a) / norm_squared, norm_squared


def speed_ratio(
    xp: Any,
    cos_theta: Any,
    sin_theta: Any,
    beta_rad: Sequence[Any],
    phase_rad: Sequence[Any],
    model: str = "exact",
) -> Any:
    """Speed ratio ``w_out / w_in`` of the chain at the given input angles.

    Parameters
    ----------
    xp : module
        ``numpy`` or ``casadi``: supplies ``sin``, ``cos`` and ``sqrt``.
    cos_theta, sin_theta : array
        Cosine and sine of the input shaft angles (numeric arrays or CasADi DM).
    beta_rad : sequence
        Operating angle of each joint (rad), ``n >= 1`` entries; numbers, numpy
        arrays that broadcast against ``cos_theta``, or CasADi symbols.
    phase_rad : sequence
        Relative phases ``phi_1 .. phi_(n-1)`` (rad).
    model : {"exact", "paper"}
        Which chain model to use.

    Returns
    -------
    array
        The speed ratio (dimensionless), broadcast over the inputs.
    """
    return chain_kinematics(xp, cos_theta, sin_theta, beta_rad, phase_rad, model,
                            figures=False).speed_ratio


def chain_kinematics(
    xp: Any,
    cos_theta: Any,
    sin_theta: Any,
    beta_rad: Sequence[Any],
    phase_rad: Sequence[Any],
    model: str = "exact",
    figures: bool = True,
) -> ChainKinematics:
    """Speed ratio, its slope and the output angle lag of a joint chain.

    Parameters are those of :func:`speed_ratio`; with ``figures=False`` only the
    speed ratio is computed (the other fields are ``None``), which is what the
    objective needs.

    Raises
    ------
    ValueError
        If ``model`` is unknown or the phase count is not ``len(beta_rad) - 1``.
    """
    if model not in MODELS:
        raise ValueError(f"model = {model!r} is not one of {MODELS}")
    if len(phase_rad) != len(beta_rad) - 1:
        raise ValueError(
            f"phase_rad has {len(phase_rad)} entries; {len(beta_rad)} joints need "
            f"{len(beta_rad) - 1}"
        )
    cos_psi, sin_psi = cos_theta, sin_theta
    cumulative_phase = 0
    ratio = 1
    log_slope = 0 if figures else None
    lag = 0 if figures else None
    # Rate of each joint's driving angle per unit input angle: the product of the
    # upstream ratios in the exact chain, 1 in the paper model.
    driving_rate = 1
    for k, beta in enumerate(beta_rad):
        if k > 0:
            cumulative_phase = cumulative_phase + phase_rad[k - 1]
        cos_phase = xp.cos(cumulative_phase)
        sin_phase = xp.sin(cumulative_phase)
        cos_a = cos_psi * cos_phase - sin_psi * sin_phase
        sin_a = sin_psi * cos_phase + cos_psi * sin_phase
        cos_b = xp.cos(beta)
        joint_ratio, norm_squared = _joint_terms(xp, cos_a, sin_a, cos_b)
        ratio = ratio * joint_ratio
        if figures:
            sin_b_squared = 1 - cos_b * cos_b
            log_slope = log_slope + (
                2 * sin_b_squared * sin_a * cos_a / norm_squared * driving_rate
            )
            # Angle from the joint's input to its output: atan2 of the cross and dot
            # products of the two unit vectors; the dot product stays positive.
            lag = lag + _atan(xp, cos_a * sin_a * (cos_b - 1),
                              cos_a * cos_a + cos_b * sin_a * sin_a)
        if model == "exact":
            norm = xp.sqrt(norm_squared)
            cos_g = cos_a / norm
            sin_g = cos_b * sin_a / norm
            cos_psi = cos_g * cos_phase + sin_g * sin_phase
            sin_psi = sin_g * cos_phase - cos_g * sin_phase
            if figures:
                driving_rate = driving_rate * joint_ratio
    return ChainKinematics(speed_ratio=ratio, log_ratio_slope=log_slope, angle_lag_rad=lag)


def _atan(xp: Any, numerator: Any, positive_denominator: Any) -> Any:
    """``atan2(y, x)`` for ``x > 0``, from whichever name the namespace uses."""
    atan2 = getattr(xp, "arctan2", None) or xp.atan2
    return atan2(numerator, positive_denominator)
