"""When can yoke phasing cancel the speed fluctuation of a joint chain?

Scaled to unit determinant, joint ``k`` (``D_k = diag(1, cos beta_k)``) moves the base
point of the hyperbolic plane by ``l_k = -ln cos beta_k`` and a phase turns about
that point by ``2 phi``. The chain ``M`` moves it by ``d = ln(s_max / s_min)`` and
``RE = cosh(d) - 1``. With every phase free, ``d`` can be made any value between
``max(0, l_max - sum of the other l)`` and ``sum of all l`` (polygon inequality), so

* the least RE any phasing reaches is ``cosh(max(0, l_max - sum l_other)) - 1``;
* RE = 0 is reachable exactly when ``cos(beta_max) >= prod cos(beta_other)``
  (for 2 joints: equal angles; for 1 joint: a straight joint);
* for small angles ``-ln cos b ~ b^2 / 2`` and the rule becomes Spicer's
  ``beta_max^2 <= sum of beta_other^2``.

For 3 joints the cancelling phases follow from requiring ``D_2 R(phi_1) D_1`` to
have the distortion of ``D_3^-1``: with ``c_k = cos beta_k``, ``s_k = sin beta_k``,

    cos^2 phi_1 = (c_1 c_2 (1 + c_3^2) / c_3 - c_1^2 - c_2^2) / (s_1^2 s_2^2)

and ``phi_2`` from the same formula on the reversed chain (3, 2, 1). Of the four
sign choices, ``phi_1, phi_2`` both in ``[0, 90]`` cancel, and so does their mirror
``180 - phi_1, 180 - phi_2``.

When RE = 0 is out of reach the least RE needs the chain's path to be one straight
line: the largest joint one way, every other joint back the other way. Two joints
that move the same way sit at phase 0, opposite ways at 90 deg, so the minimising
phasing is unique: ``phi_k = 90`` where joint ``k`` or ``k + 1`` is the largest,
else 0 (its mirror ``-phi`` is itself mod 180).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction

from sso._display import Part, Readable, TextTable, format_number
from sso._limits import BETA_LIMIT_DEG
from sso._record import Record
from sso._validation import as_float_tuple, check_chain_conditioning, check_in_range

RULE_SINGLE = "one joint: the fluctuation cancels only if the joint is straight"
RULE_PAIR = "two joints: the fluctuation cancels only if both operating angles are equal"
RULE_CHAIN = ("three or more joints: the fluctuation cancels if cos(beta_max) >= "
              "product of cos(beta) of the other joints")


@dataclass(frozen=True, eq=False, repr=False)
class CancelVerdict(Record, Readable):
    """Whether free yoke phasing can make the output turn evenly.

    Attributes
    ----------
    possible : bool
        True when some phasing gives RE = 0 (``margin >= 0``).
    margin : float
        ``cos(beta_max) - prod cos(beta_other)`` (dimensionless): 0 on the
        boundary, positive inside, negative when RE = 0 is out of reach. Never
        positive for 1 or 2 joints.
    minimum_residual_error : float
        Least RE any phasing reaches (exact model), ``cosh(max(0, l_max - sum
        l_other)) - 1`` with ``l = -ln cos beta``.
    limiting_joint : int
        Number (1-based, as ``P1 .. Pn``) of the joint with the largest angle.
    small_angle_margin_deg2 : float
        Spicer's small-angle form ``sum beta_other^2 - beta_max^2``, deg^2.
    rule : str
        The rule applied, in words.
    """

    possible: bool
    margin: float
    minimum_residual_error: float
    limiting_joint: int
    small_angle_margin_deg2: float
    rule: str

    def _repr_text(self) -> str:
        return (f"possible={self.possible}, margin={format_number(self.margin)}, "
                f"minimum_residual_error={format_number(self.minimum_residual_error)}, "
                f"limiting joint P{self.limiting_joint}")

    def _summary_parts(self) -> list[Part]:
        verdict = ("yes: some yoke phasing cancels the fluctuation (RE = 0)" if self.possible
                   else "no: no yoke phasing cancels the fluctuation")
        return [f"Can the fluctuation cancel? {verdict}", TextTable(("figure", "value"), (
            ("margin cos(beta_max) - prod cos(beta_other)", format_number(self.margin)),
            ("least RE of any phasing", format_number(self.minimum_residual_error)),
            ("limiting joint (largest angle)", f"P{self.limiting_joint}"),
            ("small-angle margin (deg^2)", format_number(self.small_angle_margin_deg2)))),
            f"rule: {self.rule}"]


def can_cancel(beta_deg: Sequence[float]) -> CancelVerdict:
    """Can some yoke phasing cancel the fluctuation of joints with these angles?

    Parameters
    ----------
    beta_deg : sequence of float
        Operating angle of each joint, deg, each in ``[0, 90)``, at least one.

    Returns
    -------
    CancelVerdict

    Raises
    ------
    ValueError
        If the list is empty, an angle is not finite or out of range, or the angles
        are too close to 90 deg for float64 to resolve RE
        (:func:`sso._validation.check_chain_conditioning`).
    """
    angles = _validated(beta_deg)
    largest = max(range(len(angles)), key=lambda index: angles[index])
    margin = _margin(angles, largest)
    # d = l_max - sum l_other = ln(prod cos_other / cos_max), and the least RE is
    # cosh(d) - 1 = 2 sinh(d / 2)^2: both written so that a tiny d keeps its digits.
    cos_largest = _cos_deg(angles[largest])
    distance = math.log1p(-margin / cos_largest) if margin < 0.0 else 0.0
    rule = {1: RULE_SINGLE, 2: RULE_PAIR}.get(len(angles), RULE_CHAIN)
    return CancelVerdict(
        possible=margin >= 0.0,
        margin=margin,
        minimum_residual_error=2.0 * math.sinh(0.5 * distance) ** 2,
        limiting_joint=largest + 1,
        small_angle_margin_deg2=sum(beta**2 for beta in angles) - 2 * angles[largest] ** 2,
        rule=rule,
    )


def cancelling_phases_deg(beta_deg: Sequence[float]) -> tuple[tuple[float, ...], ...]:
    """Phasings that give RE = 0 exactly, in closed form, for 2 or 3 joints.

    Parameters
    ----------
    beta_deg : sequence of float
        Operating angles of 2 or 3 joints, deg.

    Returns
    -------
    tuple of tuple of float
        Model phases ``phi`` (deg, in ``[0, 180)``) of each cancelling phasing:
        empty when none exists; for 2 equal angles ``((90,),)``; for 3 joints the
        solution and its mirror ``(180 - phi_1, 180 - phi_2)`` (one pair when they
        coincide).

    Raises
    ------
    ValueError
        If there are not 2 or 3 joints, or an angle is out of range.
    """
    angles = _validated(beta_deg)
    if len(angles) not in (2, 3):
        raise ValueError(f"beta_deg has {len(angles)} joints; closed-form cancelling phases "
                         "exist for 2 or 3 joints (more joints cancel on a continuum)")
    if not can_cancel(angles).possible:
        return ()
    if len(angles) == 2:
        return ((90.0,),)
    if 0.0 in angles:
        return (_straight_joint_phases_deg(angles),)
    first = _first_phase_deg(angles[0], angles[1], angles[2])
    second = _first_phase_deg(angles[2], angles[1], angles[0])
    solution = (first, second)
    mirror = (math.fmod(180.0 - first, 180.0), math.fmod(180.0 - second, 180.0))
    return (solution,) if mirror == solution else (solution, mirror)


def minimising_phases_deg(beta_deg: Sequence[float]) -> tuple[tuple[float, ...], ...] | None:
    """Every phasing (model phases, deg, mod 180) that reaches the least RE, in closed form.

    Parameters
    ----------
    beta_deg : sequence of float
        Operating angles of at least 2 joints, deg.

    Returns
    -------
    tuple of tuple of float, or None
        The minimising phasings, each in ``[0, 180)``; ``None`` when they form a
        continuum (4 or more joints that can cancel, or a straight joint), which
        has no finite list.

    Raises
    ------
    ValueError
        If there are fewer than 2 joints or an angle is out of range.
    """
    angles = _validated(beta_deg)
    if len(angles) < 2:
        raise ValueError(f"beta_deg has {len(angles)} joint; phasing needs at least 2 joints")
    verdict = can_cancel(angles)
    if 0.0 in angles:
        return None
    if verdict.possible:
        return cancelling_phases_deg(angles) if len(angles) <= 3 else None
    largest = verdict.limiting_joint
    return (tuple(90.0 if largest in (joint, joint + 1) else 0.0
                  for joint in range(1, len(angles))),)


def _first_phase_deg(first_deg: float, middle_deg: float, last_deg: float) -> float:
    """``phi_1`` in ``[0, 90]`` of a cancelling 3-joint chain (angles in order)."""
    c1, c2, c3 = (math.cos(math.radians(beta)) for beta in (first_deg, middle_deg, last_deg))
    s1_squared, s2_squared = 1.0 - c1 * c1, 1.0 - c2 * c2
    cos_squared = (c1 * c2 * (1.0 + c3 * c3) / c3 - c1 * c1 - c2 * c2) / (s1_squared * s2_squared)
    return math.degrees(math.acos(math.sqrt(min(1.0, max(0.0, cos_squared)))))


def _straight_joint_phases_deg(angles: tuple[float, ...]) -> tuple[float, ...]:
    """One cancelling phasing of 3 joints of which at least one is straight.

    A straight joint passes its input on unchanged, so the two bent joints (equal
    angles, else ``can_cancel`` said no) act as a pair whose phases must add up
    to 90 deg; the phase beside a straight end joint is free (0 is returned).
    Such a chain cancels on a continuum of phasings; this is one of them.
    """
    _, middle, last = (beta == 0.0 for beta in angles)
    if middle or last:
        return (90.0, 0.0)
    return (0.0, 90.0)


def _margin(angles: tuple[float, ...], largest: int) -> float:
    """``cos(beta_max) - prod cos(beta_other)`` without cancellation where it is tiny.

    One joint: ``cos b - 1 = -2 sin(b / 2)^2``; two: ``cos a - cos b = -2 sin((a + b) / 2)
    sin((a - b) / 2)``, exact in the given angles; more: the product and the difference
    of the rounded cosines in exact rational arithmetic.
    """
    radians = [math.radians(beta) for beta in angles]
    if len(angles) == 1:
        return -2.0 * math.sin(0.5 * radians[0]) ** 2 + 0.0  # + 0.0: never -0.0
    if len(angles) == 2:
        other = radians[1 - largest]
        difference = math.radians(angles[largest] - angles[1 - largest])
        return (-2.0 * math.sin(0.5 * (radians[largest] + other)) * math.sin(0.5 * difference)
                + 0.0)  # never -0.0 (equal angles print as 0)
    product = math.prod((Fraction(_cos_deg(beta)) for index, beta in enumerate(angles)
                         if index != largest), start=Fraction(1))
    return float(Fraction(_cos_deg(angles[largest])) - product)


def _cos_deg(beta_deg: float) -> float:
    """``cos(beta)`` to full relative precision up to 90 deg: ``sin(90 - beta)`` above
    45 deg, where ``90 - beta`` is exact and ``cos(radians(beta))`` would carry the
    rounding of ``radians`` (up to 1.1e-16 rad: 14 % of the cosine at the largest
    float below 90 deg)."""
    if beta_deg > 45.0:
        return math.sin(math.radians(90.0 - beta_deg))
    return math.cos(math.radians(beta_deg))


def _validated(beta_deg: Sequence[float]) -> tuple[float, ...]:
    angles = as_float_tuple("beta_deg", beta_deg)
    if not angles:
        raise ValueError("beta_deg is empty: give the operating angle of at least 1 joint")
    for index, beta in enumerate(angles):
        check_in_range(f"beta_deg[{index}]", beta, 0.0, BETA_LIMIT_DEG, "deg", upper_open=True)
    check_chain_conditioning("beta_deg", angles)
    return angles
