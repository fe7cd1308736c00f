"""Values implausible in their unit: the checks a case file's values go through.

A value can pass its range and still be in the wrong unit: ``lock_deg = 1.5`` meant
as turns, ``beta_deg = [0.0524, 0.0873]`` in radians, hardpoints in metres. Each
such value becomes a warning naming the key, the value and the unit it looks like
(:class:`sso._validation.UnitSuspicion`). A case that means the value says so with
``[units] confirm = ["steering.lock_deg"]``, which silences that key's warning only.

The rules (:data:`UNIT_RULES`) are about what each key holds, not its unit alone: a
tolerance of 0.5 deg is plausible, an operating angle of 0.05 deg is not. The
hardpoints' rule needs the column's shafts and runs with the column's practice
notes (:mod:`sso._column.practice`), through the same
:func:`sso._validation.metres_for_mm`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from sso._validation import (
    LARGEST_RADIAN_PHASE,
    UnitSuspicion,
    radians_for_deg,
    shown,
    turns_for_deg,
)

UNITS_TABLE = "units"
CONFIRM_LABEL = "units.confirm"


def _flat(value: Any) -> list[float]:
    """The numbers of a value, a list or a list of pairs, in order."""
    if isinstance(value, (tuple, list)):
        return [number for item in value for number in _flat(item)]
    return [float(value)]


def _radians(label: str, value: Any) -> UnitSuspicion | None:
    return radians_for_deg(label, _flat(value))


def _radian_phases(label: str, value: Any) -> UnitSuspicion | None:
    return radians_for_deg(label, _flat(value), LARGEST_RADIAN_PHASE)


def _turns(label: str, value: Any) -> UnitSuspicion | None:
    return turns_for_deg(label, float(value))


UNIT_RULES: dict[str, Callable[[str, Any], UnitSuspicion | None]] = {
    **{label: _radians for label in (
        "design.beta_deg", "bounds.beta_deg", "reference.beta_deg")},
    **{label: _radian_phases for label in (
        "design.phase_deg", "bounds.phase_deg", "reference.phase_deg",
        "phasing.yoke_phase_deg")},
    "steering.lock_deg": _turns,
    "feel.lock_deg": _turns,
}
"""Dotted label -> its check, applied to the values a case file gives (not defaults)."""


def confirmed_labels(label: str, value: Any) -> tuple[str, ...]:
    """Parser of ``[units] confirm``: a list of dotted key labels, each once."""
    if not isinstance(value, list) or not all(isinstance(item, str) for item in value):
        raise ValueError(f"{label} = {shown(value)} must be a list of dotted keys whose "
                         'values are meant as given, such as ["steering.lock_deg"]')
    if len(set(value)) != len(value):
        raise ValueError(f"{label} = {shown(value)} names a key twice")
    return tuple(value)


def check_confirmed(confirmed: tuple[str, ...], labels: set[str]) -> None:
    """Refuse a confirmed key the case's kind does not have.

    Raises
    ------
    ValueError
        Naming the first such key.
    """
    for index, label in enumerate(confirmed):
        if label not in labels:
            raise ValueError(f"{CONFIRM_LABEL}[{index}] = {shown(label)} is not a key of this "
                             "kind of case; give dotted keys such as \"steering.lock_deg\"")


def unit_warnings(given: dict[str, Any], confirmed: tuple[str, ...]) -> tuple[str, ...]:
    """The warning of each given value implausible in its unit and not confirmed.

    Parameters
    ----------
    given : dict
        The checked values the case file gives, keyed by dotted label.
    confirmed : tuple of str
        The labels of ``[units] confirm``.

    Returns
    -------
    tuple of str
        One line each, in the order of ``given``.
    """
    found = (UNIT_RULES[label](label, value) for label, value in given.items()
             if label in UNIT_RULES and label not in confirmed and value is not None)
    return tuple(suspicion.text for suspicion in found if suspicion is not None)
