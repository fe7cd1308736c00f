"""A series of shafts joined by Hooke joints: the design the package works on."""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from sso._kinematics.hooke import MODELS, ChainKinematics, chain_kinematics
from sso._kinematics.hooke_matrix import speed_ratio as closed_form_speed_ratio
from sso._limits import BETA_LIMIT_DEG, CONVENTIONAL_PHASE_DEG, DEFAULT_INPUT_SPEED_RPM
from sso._record import register_record
from sso._validation import as_float_tuple, check_chain_conditioning, check_choice, check_in_range

if TYPE_CHECKING:
    from sso._shafts.evaluation import Evaluation



class InertPhaseWarning(UserWarning):
    """The paper's extra phase after the last joint was given; it enters no equation."""


@register_record
@dataclass(frozen=True, init=False)
class ShaftSeries:
    """Shafts in series joined by ``n >= 1`` Hooke joints.

    Parameters
    ----------
    beta_deg : sequence of float
        Operating (bend) angle of each joint, deg, each in ``[0, 90)``.
    phase_deg : sequence of float, optional
        Phase of joint ``k + 1`` relative to joint ``k``, deg, ``n - 1`` entries
        (default 90 deg each: the conventional assembly of a planar column; for a
        non-planar column ``phi_k = 90 + delta_k - gamma_k (mod 180)``, with the
        yoke phasing ``delta_k`` and the bend-plane angle ``gamma_k``; see
        docs/model.md). ``n`` entries are accepted for the paper's inert extra
        phase, which is dropped with an
        :class:`InertPhaseWarning`.
    model : {"exact", "paper"}
        ``"exact"`` drives each joint by its own shaft's angle; ``"paper"`` uses
        the paper's eq. 13/16, where every joint sees the input angle.

    Raises
    ------
    ValueError
        If there are no joints, an angle is NaN, infinite or out of range, the
        angles are too close to 90 deg for float64 to resolve RE
        (:func:`sso._validation.check_chain_conditioning`), the phase list has the wrong
        length, or the model is unknown.
    """

    beta_deg: tuple[float, ...]
    phase_deg: tuple[float, ...]
    model: str = "exact"

    def __init__(self, beta_deg: Sequence[float], phase_deg: Sequence[float] | None = None,
                 model: str = "exact") -> None:
        beta, phase = _checked_angles(beta_deg, phase_deg)
        check_choice("model", model, MODELS)
        # a frozen dataclass's own __init__ stores its fields so (dataclasses' documentation)
        object.__setattr__(self, "beta_deg", beta)
        object.__setattr__(self, "phase_deg", phase)
        object.__setattr__(self, "model", model)

    @property
    def n_joints(self) -> int:
        """Number of joints."""
        return len(self.beta_deg)

    @property
    def beta_rad(self) -> np.ndarray:
        """Operating angles, rad."""
        return np.radians(self.beta_deg)

    @property
    def phase_rad(self) -> np.ndarray:
        """Relative phases, rad."""
        return np.radians(self.phase_deg)

    def with_design(
        self,
        beta_deg: Sequence[float] | None = None,
        phase_deg: Sequence[float] | None = None,
    ) -> ShaftSeries:
        """A copy with new operating angles and/or phases (deg), same model."""
        return ShaftSeries(
            beta_deg=self.beta_deg if beta_deg is None else tuple(beta_deg),
            phase_deg=self.phase_deg if phase_deg is None else tuple(phase_deg),
            model=self.model,
        )

    def speed_ratio(self, theta_deg: Any) -> np.ndarray:
        """Output over input speed ``w_out / w_in`` at input angles ``theta_deg`` (deg).

        The exact model's ratio is the closed form ``det M / |M v|^2`` of the
        chain matrix (:mod:`sso._kinematics.hooke_matrix`).

        Raises
        ------
        ValueError
            If an input angle is NaN or infinite.
        """
        if self.model == "exact":
            theta_rad = np.radians(_finite_angles(theta_deg))
            ratio: np.ndarray = closed_form_speed_ratio(
                np, np.cos(theta_rad), np.sin(theta_rad), list(self.beta_rad),
                list(self.phase_rad))
            return ratio
        chain_ratio: np.ndarray = self._kinematics(theta_deg).speed_ratio
        return chain_ratio

    def output_angle_deg(self, theta_deg: Any) -> np.ndarray:
        """Output shaft angle (deg) at input angles ``theta_deg`` (deg).

        In the exact model this is the true angle (unwrapped, so it advances one
        turn per input turn). In the paper model each joint's eq. 5 deviation is
        evaluated at the angle the paper assumes that joint sees.

        Raises
        ------
        ValueError
            If an input angle is NaN or infinite.
        """
        theta = _finite_angles(theta_deg)
        lag_rad: NDArray[np.float64] = self._kinematics(theta).angle_lag_rad
        return theta + np.degrees(lag_rad)

    def evaluate(self, input_speed_rpm: float = DEFAULT_INPUT_SPEED_RPM,
                 **quadrature: Any) -> Evaluation:
        """Figures of merit of this design at a constant input speed.

        Parameters
        ----------
        input_speed_rpm : float
            Input shaft speed, rpm (finite, > 0).
        **quadrature
            ``quadrature_rtol`` and ``quadrature_atol`` of the adaptive rule.

        Returns
        -------
        sso.Evaluation

        Raises
        ------
        ValueError
            If the speed is not finite and positive, or a keyword is unknown.
        """
        from sso._shafts.evaluation import evaluate

        return evaluate(self, input_speed_rpm=input_speed_rpm, **quadrature)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready description of the design."""
        return {"beta_deg": list(self.beta_deg), "phase_deg": list(self.phase_deg),
                "model": self.model}

    def _kinematics(self, theta_deg: Any) -> ChainKinematics:
        theta_rad = np.radians(_finite_angles(theta_deg))
        beta_rad = list(self.beta_rad)
        phase_rad = list(self.phase_rad)
        return chain_kinematics(np, np.cos(theta_rad), np.sin(theta_rad), beta_rad,
                                phase_rad, self.model)


def _checked_angles(beta_deg: Sequence[float], phase_deg: Sequence[float] | None
                    ) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """A series' operating angles and phases as checked tuples of floats (see
    :class:`ShaftSeries` for what is refused); the paper's inert extra phase is dropped
    with an :class:`InertPhaseWarning` at the line that made the series."""
    beta = as_float_tuple("beta_deg", beta_deg)
    if not beta:
        raise ValueError("beta_deg is empty: a shaft series needs at least 1 joint")
    for index, angle in enumerate(beta):
        if not 0.0 <= angle < BETA_LIMIT_DEG:  # the message is made only for a bad angle
            check_in_range(f"beta_deg[{index}]", angle, 0.0, BETA_LIMIT_DEG, "deg",
                           upper_open=True)
    check_chain_conditioning("beta_deg", beta)
    expected = len(beta) - 1
    if phase_deg is None:
        return beta, (CONVENTIONAL_PHASE_DEG,) * expected
    phase = as_float_tuple("phase_deg", phase_deg)
    if len(phase) == expected + 1 and expected >= 1:
        warnings.warn(
            f"phase_deg has {len(phase)} entries for {len(beta)} joints; "
            f"the last ({phase[-1]:g} deg, the paper's phi_{expected + 1}) "
            "enters no equation and is ignored",
            InertPhaseWarning,
            stacklevel=3,
        )
        return beta, phase[:expected]
    if len(phase) != expected:
        raise ValueError(
            f"phase_deg has {len(phase)} entries; {len(beta)} joints "
            f"need {expected} (phase of each joint relative to the one before)"
        )
    return beta, phase


def checked_series(beta_deg: tuple[float, ...], phase_deg: tuple[float, ...],
                   model: str) -> ShaftSeries:
    """The :class:`ShaftSeries` of a solver's answer, made by its constructor.

    The answer lies inside bounds that were checked against the same ranges, so the
    constructor's checks pass (they cost about 3 us).

    Raises
    ------
    ValueError
        As :class:`ShaftSeries` does.
    """
    return ShaftSeries(beta_deg, phase_deg, model)


def _finite_angles(theta_deg: Any) -> NDArray[np.float64]:
    theta = np.asarray(theta_deg, dtype=float)
    if not np.all(np.isfinite(theta)):
        bad = theta[~np.isfinite(theta)].ravel()[:3]
        raise ValueError(f"theta_deg contains non-finite angles {bad.tolist()}; "
                         "angles must be finite")
    return theta

