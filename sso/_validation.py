"""Checks of user input that fail with a message naming the field, value and range."""

from __future__ import annotations

import functools
import math
import reprlib
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np

from sso._limits import (
    ANGLE_SPACING_RAD,
    CROSS_CHECK_SOLVERS,
    MAX_INPUT_SPEED_RPM,
    RESIDUAL_RESOLUTION,
)


class _ShortRepr(reprlib.Repr):
    """``repr`` cut to a readable length, safe for any value a file can hold."""

    def __init__(self) -> None:
        super().__init__()
        self.maxlevel = 3
        self.maxstring = 60
        self.maxother = 60
        self.maxlist = self.maxtuple = self.maxdict = 8

    def repr_int(self, value: int, level: int) -> str:
        # repr() of an int beyond 4300 digits raises ValueError; count digits instead
        digits = int(abs(value).bit_length() * math.log10(2))  # this or one more
        digits += abs(value) >= 10**digits
        return super().repr_int(value, level) if digits <= 30 else f"<integer of {digits} digits>"


_SHORT_REPR = _ShortRepr()


def shown(value: Any) -> str:
    """A short, safe ``repr`` of a user's value for an error message.

    Long strings, huge integers and deeply nested lists are abbreviated, so the
    message itself can neither fail nor run to megabytes.
    """
    try:
        return _SHORT_REPR.repr(value)
    except Exception:  # a value whose repr fails is still named by its type
        return f"<{type(value).__name__}>"


def as_float_tuple(field: str, values: Any) -> tuple[float, ...]:
    """Convert a scalar or a sequence of numbers to a tuple of finite floats.

    Raises
    ------
    ValueError
        If an entry is not a number, or is NaN or infinite.
    """
    if isinstance(values, (str, bytes)):
        raise ValueError(f"{field} = {shown(values)} must be a number or a list of numbers")
    if type(values) is np.ndarray and values.ndim == 1 and values.dtype.kind == "f":
        items = values.tolist()  # Python floats: the checks below take their fast path
        if math.isfinite(sum(items)):  # no entry is NaN or infinite
            return tuple(items)
    else:
        try:
            items = list(values)
        except TypeError:
            items = [values]
    return tuple(item if type(item) is float and math.isfinite(item)
                 else finite_float(f"{field}[{index}]", item) for index, item in enumerate(items))


def finite_float(field: str, value: Any) -> float:
    """Return ``value`` as a finite float.

    Raises
    ------
    ValueError
        If ``value`` is not a real number, or is NaN or infinite.
    """
    if type(value) is float and math.isfinite(value):
        return value
    if isinstance(value, bool):
        raise ValueError(f"{field} = {shown(value)} must be a number, not a boolean")
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{field} = {shown(value)} must be a number") from None
    except OverflowError:
        raise ValueError(f"{field} = {shown(value)} is too large for a float") from None
    if not math.isfinite(number):
        raise ValueError(f"{field} = {shown(value)} must be finite (not NaN or infinite)")
    return number


def finite_in_range(
    field: str,
    value: Any,
    lower: float,
    upper: float,
    unit: str = "",
    *,
    lower_open: bool = False,
    upper_open: bool = False,
) -> float:
    """Return ``value`` as a finite float inside the interval, else raise.

    Raises
    ------
    ValueError
        If ``value`` is not a real number, is NaN or infinite, or lies outside the
        interval; the message names the field, the value and the interval.
    """
    if type(value) is float and lower < value < upper:  # inside either kind of interval
        return value
    return check_in_range(field, finite_float(field, value), lower, upper, unit,
                          upper_open=upper_open, lower_open=lower_open)


def validate_speed(field: str, value: Any) -> float:
    """Return a positive speed of at most :data:`sso._limits.MAX_INPUT_SPEED_RPM`, or
    raise naming the field."""
    return finite_in_range(field, value, 0.0, MAX_INPUT_SPEED_RPM, "rpm", lower_open=True)


def check_in_range(
    field: str,
    value: float,
    lower: float,
    upper: float,
    unit: str = "",
    upper_open: bool = False,
    lower_open: bool = False,
) -> float:
    """Return ``value`` if it lies in the interval, else raise.

    Raises
    ------
    ValueError
        Naming the field, the value and the allowed interval.
    """
    too_low = value <= lower if lower_open else value < lower
    too_high = value >= upper if upper_open else value > upper
    if too_low or too_high:
        left = "(" if lower_open else "["
        right = ")" if upper_open else "]"
        suffix = f" {unit}" if unit else ""
        raise ValueError(
            f"{field} = {value:g} is outside the allowed range "
            f"{left}{lower:g}, {upper:g}{right}{suffix}"
        )
    return value


def check_choice(field: str, value: Any, allowed: Iterable[Any]) -> Any:
    """Return ``value`` if it is one of ``allowed``, else raise naming the choices."""
    allowed = tuple(allowed)
    if value not in allowed:
        raise ValueError(f"{field} = {shown(value)} is not one of {', '.join(map(repr, allowed))}")
    return value


def per_item_bounds(
    field: str,
    bounds: Any,
    count: int,
    lower_limit: float,
    upper_limit: float,
    unit: str,
    upper_open: bool = False,
) -> tuple[tuple[float, float], ...]:
    """Expand one ``(lower, upper)`` pair, or one pair per item, into per-item bounds.

    Raises
    ------
    ValueError
        If the shape is wrong, a bound is not finite or lies outside
        ``[lower_limit, upper_limit]``, or an interval is inverted (an equal pair pins the item).
    """
    if _is_pair_of_numbers(bounds):
        pair = _checked_pair(field, bounds, lower_limit, upper_limit, unit, upper_open)
        return (pair,) * count
    try:
        pairs = list(bounds)
    except TypeError:
        raise ValueError(
            f"{field} = {shown(bounds)} must be one (lower, upper) pair or {count} pairs"
        ) from None
    if len(pairs) != count or not all(_is_pair_of_numbers(pair) for pair in pairs):
        raise ValueError(
            f"{field} = {shown(bounds)} must be one (lower, upper) pair or {count} pairs"
        )
    return tuple(_checked_pair(f"{field}[{index}]", pair, lower_limit, upper_limit, unit,
                               upper_open) for index, pair in enumerate(pairs))


def _checked_pair(name: str, pair: Any, lower_limit: float, upper_limit: float, unit: str,
                  upper_open: bool) -> tuple[float, float]:
    """One ``(lower, upper)`` pair as floats inside the limits, not inverted, else raise."""
    lower, upper = pair
    # Plain numbers inside the limits and in order pass at once (NaN and infinity fail
    # these comparisons); anything else takes the checks that name what is wrong.
    if (type(lower) in _PLAIN_NUMBERS and type(upper) in _PLAIN_NUMBERS
            and lower_limit <= lower <= upper
            and (upper < upper_limit if upper_open else upper <= upper_limit)):
        return float(lower), float(upper)
    lower_name, upper_name = f"{name} lower", f"{name} upper"
    lower = check_in_range(lower_name, finite_float(lower_name, lower), lower_limit, upper_limit,
                           unit, upper_open=upper_open)
    upper = check_in_range(upper_name, finite_float(upper_name, upper), lower_limit, upper_limit,
                           unit, upper_open=upper_open)
    if lower > upper:
        raise ValueError(
            f"{name} = ({lower:g}, {upper:g}) {unit} is inverted (empty): "
            "the lower bound must not exceed the upper bound"
        )
    return lower, upper


def _is_pair_of_numbers(value: Any) -> bool:
    if (type(value) is tuple and len(value) == 2 and type(value[0]) in _PLAIN_NUMBERS
            and type(value[1]) in _PLAIN_NUMBERS):
        return True
    if isinstance(value, (str, bytes)):
        return False
    try:
        items = list(value)
    except TypeError:
        return False
    return len(items) == 2 and _is_number(items[0]) and _is_number(items[1])


def _is_number(item: Any) -> bool:
    return isinstance(item, _NUMBER_TYPES) and not isinstance(item, bool)


_NUMBER_TYPES = (int, float, np.integer, np.floating)
_PLAIN_NUMBERS = (int, float)




def validate_solvers(solvers: Iterable[str] | str,
                     allowed: tuple[str, ...] = CROSS_CHECK_SOLVERS) -> tuple[str, ...]:
    """Solver names as a tuple, or raise naming the bad entry and the ``allowed`` choices."""
    if (type(solvers) is tuple and len(solvers) == 1 and type(solvers[0]) is str
            and solvers[0] in allowed):
        return solvers  # one known name, as a single solve gives it
    names = (solvers,) if isinstance(solvers, str) else tuple(solvers)
    if not names:
        raise ValueError(f"solvers is empty; choose one or more of {', '.join(allowed)}")
    for index, name in enumerate(names):
        if name not in allowed:
            raise ValueError(f"solvers[{index}] = {shown(name)} is not one of "
                             f"{', '.join(allowed)}")
    if len(set(names)) != len(names):
        raise ValueError(f"solvers = {list(names)} names a solver twice")
    return names


def validate_solver_tol(value: Any) -> float:
    """The solvers' stopping tolerance in ``(0, 1)``, or raise naming the field and range."""
    return finite_in_range("solver_tol", value, 0.0, 1.0, lower_open=True, upper_open=True)


def validate_count(field: str, value: Any, lower: int, upper: int) -> int:
    """A whole number in ``[lower, upper]``, or raise naming the field and range."""
    if type(value) is int and lower <= value <= upper:
        return value
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise ValueError(f"{field} = {shown(value)} must be a whole number in [{lower}, {upper}]")
    if not lower <= value <= upper:
        raise ValueError(f"{field} = {value} is outside the allowed range [{lower}, {upper}]")
    return int(value)


def _power_of_ten(log10_value: float, decimals: int) -> str:
    """``10 ** log10_value`` written as ``m.mme±x`` even beyond the range of floats."""
    exponent = math.floor(log10_value)
    mantissa = round(10.0 ** (log10_value - exponent), decimals)
    if mantissa >= 10.0:
        mantissa, exponent = mantissa / 10.0, exponent + 1
    return f"{mantissa:.{decimals}f}e{exponent:+03d}"


def least_cosine_product(joints: int) -> float:
    """Least product of the operating angles' cosines with which float64 resolves RE.

    The bound ``(2 n - 1) ANGLE_SPACING_RAD / sqrt(2 det M)`` on the residuals'
    rounding (see :data:`sso._limits.RESIDUAL_RESOLUTION`) reaches the allowed
    resolution at ``det M = ((2 n - 1) ANGLE_SPACING_RAD / RESIDUAL_RESOLUTION)^2 / 2``.

    Parameters
    ----------
    joints : int
        Number of joints ``n >= 1`` of the chain.
    """
    return ((2 * joints - 1) * ANGLE_SPACING_RAD / RESIDUAL_RESOLUTION) ** 2 / 2.0


LARGEST_TANGENT_SUM = 2.0 * RESIDUAL_RESOLUTION / ANGLE_SPACING_RAD
"""Largest sum of the operating angles' tangents with which float64 resolves RE: a
rounding of ``beta_k`` changes ``det M`` by ``tan(beta_k) ANGLE_SPACING_RAD`` of itself,
and the residuals (divided by ``sqrt(2 det M)``) by half that (7.1e7; one joint may
reach 89.9999992 deg)."""


def _beyond_resolution(joints: int, log_product: Any, tangent_sum: Any) -> Any:
    """Whether chains of ``joints`` joints with these sums of ``ln cos beta`` and of
    ``tan beta`` (floats or arrays) break either bound of :func:`check_chain_conditioning`."""
    return (log_product < _least_log_cosine_product(joints)) | (
        tangent_sum > LARGEST_TANGENT_SUM)


@functools.cache
def _least_log_cosine_product(joints: int) -> float:
    """``ln`` of :func:`least_cosine_product`, kept per chain length (every series made
    checks it)."""
    return math.log(least_cosine_product(joints))


def unresolvable_chains(beta_deg: np.ndarray) -> np.ndarray:
    """Which chains (rows of operating angles, deg) float64 cannot resolve RE of.

    Either rounding bound of :func:`check_chain_conditioning` exceeds what
    :data:`sso._limits.RESIDUAL_RESOLUTION` allows: the product of the cosines is below
    :func:`least_cosine_product` or the tangents sum to more than
    :data:`LARGEST_TANGENT_SUM`. Angles must lie in ``[0, 90)`` deg.
    """
    beta_rad = np.radians(np.asarray(beta_deg, dtype=float))
    return np.asarray(_beyond_resolution(beta_rad.shape[-1],
                                         np.sum(np.log(np.cos(beta_rad)), axis=-1),
                                         np.sum(np.tan(beta_rad), axis=-1)), dtype=bool)


def check_chain_conditioning(field: str, beta_deg: Iterable[float]) -> None:
    """Refuse operating angles with which float64 cannot resolve a chain's RE.

    Whatever the phases (an optimiser may reach any), rounding the chain's ``2 n - 1``
    angles by a float spacing ``h`` moves its residuals ``r`` (``RE = |r|^2``) by up to
    ``(2 n - 1) h / sqrt(2 prod cos beta) + |r| (h / 2) sum tan beta``
    (docs/model.md, "Numerical limits"); both terms, the second relative to ``|r|``,
    must stay within :data:`sso._limits.RESIDUAL_RESOLUTION`.

    Parameters
    ----------
    field : str
        Name of the angles in the message (``beta_deg``, or a bound).
    beta_deg : iterable of float
        Operating angle of each joint, deg, each already checked to lie in ``[0, 90)``.

    Raises
    ------
    ValueError
        If either bound exceeds the resolution, naming the field, the bound and what
        the joints may have: the least product of cosines and the largest equal
        angle, or the largest sum of tangents.
    """
    angles = list(map(math.radians, beta_deg))
    joints = len(angles)
    log_product = math.fsum(map(math.log, map(math.cos, angles)))
    tangents = math.fsum(map(math.tan, angles))
    if not _beyond_resolution(joints, log_product, tangents):
        return
    log10_product = log_product / math.log(10.0)
    least = least_cosine_product(joints)
    start = (f"{field}: float64 cannot resolve RE of a chain of {joints} "
             f"joint{'s' if joints > 1 else ''}")
    if log_product < math.log(least):
        log10_rounding = (math.log10((2 * joints - 1) * ANGLE_SPACING_RAD / math.sqrt(2.0))
                          - 0.5 * log10_product)
        largest_equal_deg = math.degrees(math.acos(least ** (1.0 / joints)))
        raise ValueError(
            f"{start}: the product of cos(beta) is {_power_of_ten(log10_product, 2)}, so "
            "one rounding of the angles can move sqrt(RE) by up to "
            f"{_power_of_ten(log10_rounding, 1)}, above the allowed "
            f"{RESIDUAL_RESOLUTION:.2g}; {joints} joints need a product of at least "
            f"{least:.3g} (equal angles up to {largest_equal_deg:.10g} deg): lower the "
            "operating angles or the number of joints"
        )
    raise ValueError(
        f"{start}: the operating angles' tangents sum to {tangents:.3g}, so one rounding "
        "of the angles can change sqrt(RE) by up to "
        f"{0.5 * ANGLE_SPACING_RAD * tangents:.2g} of itself, above the allowed "
        f"{RESIDUAL_RESOLUTION:.2g}; the tangents may sum to at most "
        f"{LARGEST_TANGENT_SUM:.3g} (one joint up to "
        f"{math.degrees(math.atan(LARGEST_TANGENT_SUM)):.10g} deg): lower the operating "
        "angles nearest 90 deg"
    )


# ---------------------------------------------------------------- units that look wrong

SHORTEST_SHAFT_MM = 10.0
"""Below this a shaft given in mm was most likely typed in metres (steering columns and
drivelines have shafts of tens to thousands of mm; an sso plausibility check)."""
LARGEST_RADIAN_ANGLE = 1.58
"""Operating angles all at most this (in magnitude) look like radians: a joint bent
0.05 deg is no design anyone means, 0.05 rad (3 deg) is; a joint bends less than 90 deg,
pi/2 = 1.5708 rad (rounded up, so that a rounded pi/2 counts)."""
LARGEST_RADIAN_PHASE = 6.29
"""Phase angles all at most this (in magnitude), not all whole numbers, look like
radians: phases in deg are 0, 90 or tens of deg (a yoke turns by whole spline teeth),
in radians up to a turn, 2 pi = 6.2832 (rounded up)."""
SMALLEST_LOCK_DEG = 10.0
"""A steering lock below this many deg looks like turns: vehicles steer a quarter turn
(racing cars) to about three turns (trucks) from straight ahead to each lock."""


@dataclass(frozen=True)
class UnitSuspicion:
    """A value implausible in its unit, and the unit it looks like.

    Attributes
    ----------
    key : str
        The key as the user wrote it (``"steering.lock_deg"``).
    value : str
        The value as given (``"1.5"``).
    looks_like : str
        The unit the value looks like, with the value in the key's unit
        (``"turns (1.5 turns = 540 deg)"``).
    reason : str
        Why the value is implausible in the key's unit.
    """

    key: str
    value: str
    looks_like: str
    reason: str

    @property
    def text(self) -> str:
        """One line naming the key, the value, the unit it looks like and how to keep it."""
        return (f"{self.key} = {self.value} looks like {self.looks_like}: {self.reason}; "
                f"if it is meant, list \"{self.key}\" in [units] confirm")


def metres_for_mm(key: str, shortest_mm: float, what: str) -> UnitSuspicion | None:
    """Lengths given in metres where mm are asked for, told by the shortest shaft.

    Parameters
    ----------
    key : str
        The points' key.
    shortest_mm : float
        The shortest shaft the points make, mm.
    what : str
        Which shaft it is (``"intermediate shaft 1, P1 to P2"``).

    Returns
    -------
    UnitSuspicion or None
        None when the shaft is at least :data:`SHORTEST_SHAFT_MM` long.
    """
    if shortest_mm >= SHORTEST_SHAFT_MM:
        return None
    return UnitSuspicion(key, f"points {shortest_mm:.3g} mm apart ({what})",
                         f"metres ({shortest_mm:.3g} m = {1000.0 * shortest_mm:.4g} mm)",
                         "shafts of steering columns and drivelines are tens to thousands of "
                         "mm long; give mm")


def radians_for_deg(key: str, angles_deg: Iterable[float],
                    largest: float = LARGEST_RADIAN_ANGLE) -> UnitSuspicion | None:
    """Operating or phase angles given in radians where deg are asked for.

    Parameters
    ----------
    key : str
        The angles' key.
    angles_deg : iterable of float
        The values as given (bounds flattened).

    Returns
    -------
    UnitSuspicion or None
        None when any angle exceeds ``largest`` in magnitude (:data:`LARGEST_RADIAN_ANGLE`
        for operating angles, :data:`LARGEST_RADIAN_PHASE` for phases), or every angle
        is a whole number (0, 1 deg) or 0.
    """
    angles = [float(angle) for angle in angles_deg]
    if not angles or any(abs(angle) > largest for angle in angles) \
            or all(angle == round(angle) for angle in angles):
        return None
    given = ", ".join(f"{angle:g}" for angle in angles)
    converted = ", ".join(f"{math.degrees(angle):.4g}" for angle in angles)
    return UnitSuspicion(key, f"[{given}]", f"radians ([{given}] rad = [{converted}] deg)",
                         f"every angle is within {largest:.4g} deg and not all are whole, "
                         "where an operating or phase angle in deg is tens of deg; give deg")


def turns_for_deg(key: str, lock_deg: float) -> UnitSuspicion | None:
    """A steering lock given in turns where deg are asked for.

    Returns
    -------
    UnitSuspicion or None
        None when the lock is at least :data:`SMALLEST_LOCK_DEG`.
    """
    if lock_deg >= SMALLEST_LOCK_DEG:
        return None
    return UnitSuspicion(key, f"{lock_deg:g}",
                         f"turns ({lock_deg:g} turns = {360.0 * lock_deg:g} deg)",
                         "a steering lock is a quarter turn to about three turns (90 to 1080 "
                         "deg) from straight ahead; give deg")
