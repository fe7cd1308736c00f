"""The paper's three design-variable options, bounds, and the design vector layout."""

from __future__ import annotations

import functools
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from sso._limits import BETA_LIMIT_DEG
from sso._record import built_from
from sso._validation import check_chain_conditioning, per_item_bounds
from sso._warning_origin import user_stacklevel

OPTION_NAMES = {1: "phase", 2: "angle", 3: "both"}
OPTION_FIXED_PHASE_DEG = 90.0
PHASE_LIMIT_DEG = 360.0


class StartMovedWarning(UserWarning):
    """A start value lay outside its bounds and was moved onto the nearer bound."""


def parse_option(option: Any) -> int:
    """Return the option number 1, 2 or 3 from a number or a name.

    Raises
    ------
    ValueError
        If ``option`` is neither 1, 2, 3 nor one of ``"phase"``, ``"angle"``, ``"both"``.
    """
    if isinstance(option, str) and option.strip().lower() in OPTION_NAMES.values():
        name = option.strip().lower()
        return next(number for number, known in OPTION_NAMES.items() if known == name)
    if (isinstance(option, (int, np.integer)) and not isinstance(option, bool)
            and option in OPTION_NAMES):
        return int(option)
    raise ValueError(
        f"option = {option!r} is not one of 1, 2, 3, 'phase', 'angle', 'both'"
    )


@dataclass(frozen=True)
class DesignProblem:
    """One option of one series: which angles are free, their bounds and start.

    The design vector ``x`` (rad) holds the free operating angles first, then the
    free phases; ``parameters`` (rad) holds the fixed ones in the same order.

    Attributes
    ----------
    n_joints : int
    option : int
        1 = phases, 2 = operating angles (phases fixed at 90 deg), 3 = both.
    model : str
    beta_free, phase_free : bool
        Whether the operating angles / phases are design variables.
    lower_rad, upper_rad : numpy.ndarray
        Bounds of ``x``.
    start_values_deg : tuple of float
        The user's start (deg), moved onto the bounds where it lay outside
        (``start_deg`` as an array).
    parameter_values_deg : tuple of float
        The fixed angles (deg), kept in degrees so they come back exactly
        (``parameters_deg`` as an array).
    beta_bounds_deg, phase_bounds_deg : tuple of (float, float)
        Per-joint / per-phase bounds as given (deg).
    moved_starts : tuple of str
        One message for each start value that lay outside its bounds and was moved
        onto the nearer one (raise them with :func:`warn_moved_starts`).
    """

    n_joints: int
    option: int
    model: str
    beta_free: bool
    phase_free: bool
    lower_rad: np.ndarray
    upper_rad: np.ndarray
    start_values_deg: tuple[float, ...]
    parameter_values_deg: tuple[float, ...]
    beta_bounds_deg: tuple[tuple[float, float], ...]
    phase_bounds_deg: tuple[tuple[float, float], ...]
    moved_starts: tuple[str, ...] = ()

    # Arrays made on first use: the direct path of "lm" alone reads the plain floats only.
    @functools.cached_property
    def start_deg(self) -> NDArray[np.float64]:
        """The start of the design vector, deg."""
        return np.array(self.start_values_deg, dtype=float)

    @functools.cached_property
    def parameters_deg(self) -> NDArray[np.float64]:
        """The fixed angles, deg."""
        return np.array(self.parameter_values_deg, dtype=float)

    @functools.cached_property
    def bounds_deg(self) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """Lower and upper bounds of the design vector, deg (the bounds as given)."""
        pairs = [*(self.beta_bounds_deg if self.beta_free else ()),
                 *(self.phase_bounds_deg if self.phase_free else ())]
        return tuple(low for low, _ in pairs), tuple(high for _, high in pairs)

    @property
    def option_name(self) -> str:
        """``"phase"``, ``"angle"`` or ``"both"``."""
        return OPTION_NAMES[self.option]

    @property
    def start_rad(self) -> NDArray[np.float64]:
        """The start of the design vector, rad."""
        return np.radians(self.start_deg)

    @property
    def parameters_rad(self) -> NDArray[np.float64]:
        """The fixed angles, rad."""
        return np.radians(self.parameters_deg)

    @property
    def n_free(self) -> int:
        """Length of the design vector."""
        return len(self.lower_rad)

    def split(self, free: Sequence[Any], fixed: Sequence[Any]
              ) -> tuple[Sequence[Any], Sequence[Any]]:
        """Operating angles and phases from the design vector's values ``free`` and the
        fixed ``parameters`` values ``fixed`` (lists, in one unit).

        Works on numbers, numpy columns and CasADi symbols alike; the parts are slices
        of the lists given, or the lists themselves, never changed.
        """
        if self.beta_free and self.phase_free:
            return free[:self.n_joints], free[self.n_joints:]
        return (free, fixed) if self.beta_free else (fixed, free)

    def design_deg(self, x_deg: Sequence[float] | NDArray[np.float64]
                   ) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """Operating angles and phases (deg) of the design vector ``x_deg`` (deg); a list or
        tuple is taken to hold Python floats (a tuple's parts are its slices)."""
        beta, phase = self.split(x_deg if isinstance(x_deg, (list, tuple))
                                 else np.asarray(x_deg, dtype=float).tolist(),
                                 self.parameter_values_deg)
        return tuple(beta), tuple(phase)

    @property
    def beta_upper_rad(self) -> list[float]:
        """Largest operating angle each joint can take (rad), for the quadrature."""
        if self.beta_free:
            return [float(upper) for upper in self.upper_rad[: self.n_joints]]
        return [float(beta) for beta in self.parameters_rad[: self.n_joints]]


def free_angles(option_number: int) -> tuple[bool, bool]:
    """Whether option 1, 2 or 3 frees the operating angles and the phases."""
    return option_number in (2, 3), option_number in (1, 3)


def validate_option_and_bounds(
    option: Any, n_joints: int, beta_bounds_deg: Any, phase_bounds_deg: Any
) -> tuple[int, tuple[tuple[float, float], ...], tuple[tuple[float, float], ...]]:
    """The option number and per-joint / per-phase bounds (deg) of an ``n_joints`` chain.

    The one check of an option and its bounds, for :func:`build_problem` and for
    :func:`sso.optimise_batch`.

    Raises
    ------
    ValueError
        For an unknown option, option 1 with one joint, or bad bounds (naming the
        field, the value and the allowed range), among them upper bounds on free
        operating angles with which float64 cannot resolve RE
        (:func:`sso._validation.check_chain_conditioning`).
    """
    option_number = parse_option(option)
    if option_number == 1 and n_joints < 2:
        raise ValueError(
            "option = 1 (phases) needs at least 2 joints: a single joint has no phase to optimise"
        )
    beta_bounds = per_item_bounds("beta_bounds_deg", beta_bounds_deg, n_joints, 0.0,
                                  BETA_LIMIT_DEG, "deg", upper_open=True)
    phase_bounds = per_item_bounds("phase_bounds_deg", phase_bounds_deg, n_joints - 1,
                                   -PHASE_LIMIT_DEG, PHASE_LIMIT_DEG, "deg")
    if option_number != 1:  # the operating angles are free: every one may reach its upper bound
        check_chain_conditioning("beta_bounds_deg (their upper bounds)",
                            [upper for _, upper in beta_bounds])
    return option_number, beta_bounds, phase_bounds


@dataclass(frozen=True)
class BoundsLayout:
    """The checked option and bounds of one chain length: what every start of it shares.

    Attributes
    ----------
    option : int
    beta_free, phase_free : bool
    beta_bounds_deg, phase_bounds_deg : tuple of (float, float)
        Per-joint / per-phase bounds (deg), checked.
    lower_deg, upper_deg : tuple of float
        Bounds of the design vector (deg).
    lower_rad, upper_rad : numpy.ndarray
        The same in rad, read-only (shared by every problem of the layout).
    moved_messages : dict
        The messages of starts given again with values outside these bounds
        (:func:`build_problem`), by the values given.
    """

    option: int
    beta_free: bool
    phase_free: bool
    beta_bounds_deg: tuple[tuple[float, float], ...]
    phase_bounds_deg: tuple[tuple[float, float], ...]
    lower_deg: tuple[float, ...]
    upper_deg: tuple[float, ...]
    lower_rad: np.ndarray
    upper_rad: np.ndarray
    moved_messages: dict[tuple[float, ...], tuple[str, ...]] = field(
        default_factory=dict, compare=False, repr=False)


LAYOUT_CACHE_SIZE = 64
"""Layouts of (chain length, option, bounds) kept for reuse; the oldest go first."""

_layouts: dict[Any, BoundsLayout] = {}


def bounds_layout(option: Any, n_joints: int, beta_bounds_deg: Any,
                  phase_bounds_deg: Any) -> BoundsLayout:
    """The option and bounds of an ``n_joints`` chain, checked and laid out once.

    A single solve of a few joints costs less than checking its bounds again, so the
    layout of bounds given as plain numbers (int, float, tuples and lists of them)
    and an option given as a number or a name is kept for the next call with equal
    values. Anything else (numpy arrays, booleans, ...) is checked on every call.

    Raises
    ------
    ValueError
        As :func:`validate_option_and_bounds`.
    """
    beta_key, phase_key = _plain_key(beta_bounds_deg), _plain_key(phase_bounds_deg)
    key = (None if beta_key is None or phase_key is None
           or not (type(option) is int or type(option) is str)
           else (option, n_joints, beta_key, phase_key))
    layout = None if key is None else _layouts.get(key)
    if layout is None:
        layout = _layout(option, n_joints, beta_bounds_deg, phase_bounds_deg)
        if key is not None:
            if len(_layouts) >= LAYOUT_CACHE_SIZE:
                del _layouts[next(iter(_layouts))]
            _layouts[key] = layout
    return layout


def _plain_key(value: Any) -> Any:
    """Bounds as a hashable key when they hold only ints, floats, tuples and lists (a list
    becomes a tagged tuple), else None. Booleans and numpy numbers give None: their
    checks differ from a plain number's, so they are checked on every call."""
    kind = type(value)
    if kind is tuple and len(value) == 2:
        first, second = type(value[0]), type(value[1])
        if (first is float or first is int) and (second is float or second is int):
            return value
    if kind is int or kind is float:
        return value
    if kind is tuple or kind is list:
        items = tuple(_plain_key(item) for item in value)
        return None if None in items else (kind is list, items)
    return None


def _layout(option: Any, n_joints: int, beta_bounds_deg: Any,
            phase_bounds_deg: Any) -> BoundsLayout:
    option_number, beta_bounds, phase_bounds = validate_option_and_bounds(
        option, n_joints, beta_bounds_deg, phase_bounds_deg)
    beta_free, phase_free = free_angles(option_number)
    pairs = [*(beta_bounds if beta_free else ()), *(phase_bounds if phase_free else ())]
    lower = tuple(low for low, _ in pairs)
    upper = tuple(high for _, high in pairs)
    lower_rad, upper_rad = np.radians([lower, upper]).reshape(2, len(pairs))
    lower_rad.flags.writeable = False
    upper_rad.flags.writeable = False
    return BoundsLayout(option_number, beta_free, phase_free, beta_bounds, phase_bounds,
                        lower, upper, lower_rad, upper_rad)


def build_problem(
    beta_deg: Sequence[float],
    phase_deg: Sequence[float],
    model: str,
    option: Any,
    beta_bounds_deg: Any,
    phase_bounds_deg: Any,
) -> DesignProblem:
    """Lay out the design vector, bounds and start of an option.

    Parameters
    ----------
    beta_deg, phase_deg : sequence of float
        The user's design (deg): the start of the free angles, the value of the
        fixed ones (option 2 fixes every phase at 90 deg whatever is given).
    model : str
        Chain model.
    option : int or str
        1/2/3 or ``"phase"``/``"angle"``/``"both"``.
    beta_bounds_deg : (float, float) or sequence of pairs
        Bounds of the operating angles (deg), within ``[0, 90)``.
    phase_bounds_deg : (float, float) or sequence of pairs
        Bounds of the phases (deg), within ``[-360, 360]``.

    Returns
    -------
    DesignProblem
        Start values outside their bounds are moved onto them and listed in its
        ``moved_starts`` (no warning is raised here). Its ``lower_rad`` and
        ``upper_rad`` are read-only (shared with other problems of the same bounds).

    Raises
    ------
    ValueError
        For an unknown option, option 1 with one joint, or bad bounds.
    """
    n_joints = len(beta_deg)
    layout = bounds_layout(option, n_joints, beta_bounds_deg, phase_bounds_deg)
    beta_free, phase_free = layout.beta_free, layout.phase_free
    if layout.option == 2:
        phase_deg = [OPTION_FIXED_PHASE_DEG] * (n_joints - 1)
    given = [*(beta_deg if beta_free else ()), *(phase_deg if phase_free else ())]
    parameters = [*(() if beta_free else beta_deg), *(() if phase_free else phase_deg)]
    start = [low if value < low else high if value > high else value
             for value, low, high in zip(given, layout.lower_deg, layout.upper_deg, strict=True)]
    moved_starts: tuple[str, ...] = ()
    if start != given:
        moved_starts = _moved_starts(given, start, layout, n_joints)
    return built_from(DesignProblem, {
        "n_joints": n_joints, "option": layout.option, "model": model, "beta_free": beta_free,
        "phase_free": phase_free, "lower_rad": layout.lower_rad, "upper_rad": layout.upper_rad,
        "start_values_deg": tuple(start), "parameter_values_deg": tuple(parameters),
        "beta_bounds_deg": layout.beta_bounds_deg, "phase_bounds_deg": layout.phase_bounds_deg,
        "moved_starts": moved_starts})


MOVED_MESSAGES_KEPT = 256
"""Starts outside their bounds whose messages a layout keeps (the oldest go first)."""


def _moved_starts(given: list[float], start: list[float], layout: BoundsLayout,
                  n_joints: int) -> tuple[str, ...]:
    """The messages of the start values moved onto the bounds, kept by the layout for a
    start given again (formatting them costs a single solve more than its arithmetic).
    A start holding a zero is formatted anew: 0 and -0 are one key and print apart."""
    key = tuple(given)
    messages = layout.moved_messages.get(key)
    if messages is None:
        messages = tuple(_moved_messages(given, start, layout, n_joints))
        if 0.0 not in key:
            if len(layout.moved_messages) >= MOVED_MESSAGES_KEPT:
                del layout.moved_messages[next(iter(layout.moved_messages))]
            layout.moved_messages[key] = messages
    return messages


def _moved_messages(given: list[float], start: list[float], layout: BoundsLayout,
                    n_joints: int) -> list[str]:
    """One message for each start value moved onto its bounds."""
    first_phase = n_joints if layout.beta_free else 0
    messages = []
    for index, (value, moved) in enumerate(zip(given, start, strict=True)):
        if moved != value:
            field, number = (("phase_deg", index - first_phase)
                             if layout.phase_free and index >= first_phase
                             else ("beta_deg", index))
            messages.append(f"start {field}[{number}] = {value:g} deg lies outside its bounds "
                            f"[{layout.lower_deg[index]:g}, {layout.upper_deg[index]:g}] deg; "
                            f"moved onto {moved:g} deg")
    return messages


def warn_moved_starts(problem: DesignProblem) -> None:
    """Raise a :class:`StartMovedWarning` for each start value ``problem`` moved onto its
    bounds, naming the user's line that called into the package."""
    if problem.moved_starts:
        stacklevel = user_stacklevel()
        for message in problem.moved_starts:
            warnings.warn(message, StartMovedWarning, stacklevel=stacklevel)
