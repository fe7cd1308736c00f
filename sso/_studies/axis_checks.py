"""An array sweep's axis values read as cases, where its chunks run.

Before a chunk computes its points as arrays (:mod:`sso._studies.array_engine`), it
needs, for each axis value its points take, whether the base case accepts the value
and the warnings it brings: the base case read with the value set, as a case file is
read. A chunk reads the values its points take when it runs, in the worker that runs
it, and the worker keeps what it read for the sweep's next chunks (keyed by the
sweep run and the value's place on its axis; only the latest sweep run's values are
kept). So no step before the chunks waits for these reads, and a worker reads a value
at most once a sweep.
"""

from __future__ import annotations

import copy
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from sso._cases.schema import parse_case
from sso._shafts.options import build_problem
from sso._studies.axes import set_field


@dataclass(frozen=True)
class AxisValues:
    """One axis as a chunk reads it: where it goes, and what each value brings.

    Attributes
    ----------
    target : (str, int)
        ``("beta_deg", joint)``, ``("phase_deg", joint)`` or ``("input_speed_rpm", 0)``.
    accepted : numpy.ndarray of bool
        Whether the case accepts each of the chunk's values (False for a value no
        point of the chunk takes: it is not read).
    notes : tuple of tuple of str
        The warnings each value brings (those of the case read with it, and a start
        moved onto its bounds).
    """

    target: tuple[str, int]
    accepted: np.ndarray
    notes: tuple[tuple[str, ...], ...]


_READ: dict[str, dict[tuple[int, int], tuple[bool, tuple[str, ...]]]] = {}
"""The values this process has read, of the latest sweep run only: its token mapped to
``(axis, position on the axis) -> (accepted, notes)``."""


def chunk_axes(run: str, document: dict[str, Any], action: str, paths: Sequence[str],
               targets: Sequence[tuple[str, int]], values: Sequence[Sequence[Any]],
               value_indices: Sequence[np.ndarray],
               lows: Sequence[int] | None) -> tuple[AxisValues, ...]:
    """Each axis's values that a chunk's points take, read as cases (see the module).

    Parameters
    ----------
    run : str
        The sweep run's token: values read under it are those of this sweep.
    document : dict
        The base case as a complete case-file document.
    action : {"optimise", "evaluate"}
        The sweep's action (optimising, a value may move the start onto its bounds).
    paths, targets : sequence
        Per axis, its path and where its values go (:attr:`AxisValues.target`).
    values : sequence of sequence
        Per axis, the chunk's values.
    value_indices : sequence of numpy.ndarray
        Per axis, the position of each point's value in ``values[k]``.
    lows : sequence of int or None
        Per axis, the position on the sweep's axis of ``values[k][0]``; None when the
        chunk's values have no place on the sweep's axes (then nothing is kept).
    """
    read = _read_values(run) if lows is not None else {}
    axes = []
    for axis, (path, target, chunk_values, positions) in enumerate(
            zip(paths, targets, values, value_indices, strict=True)):
        low = 0 if lows is None else lows[axis]
        taken = np.zeros(len(chunk_values), dtype=bool)
        taken[positions] = True
        wanted = np.flatnonzero(taken).tolist()
        missing = [position for position in wanted if (axis, low + position) not in read]
        if missing:
            accepted, notes = check_values(document, path,
                                           [chunk_values[position] for position in missing],
                                           target, action)
            for position, one, note in zip(missing, accepted.tolist(), notes, strict=True):
                read[(axis, low + position)] = (one, note)
        found = np.zeros(len(chunk_values), dtype=bool)
        found_notes: list[tuple[str, ...]] = [()] * len(chunk_values)
        for position in wanted:
            found[position], found_notes[position] = read[(axis, low + position)]
        axes.append(AxisValues(target, found, tuple(found_notes)))
    return tuple(axes)


def _read_values(run: str) -> dict[tuple[int, int], tuple[bool, tuple[str, ...]]]:
    """The values this process has read in sweep run ``run`` (forgetting any other run's)."""
    read = _READ.get(run)
    if read is None:
        _READ.clear()
        read = _READ[run] = {}
    return read


def check_values(document: dict[str, Any], path: str, values: Sequence[Any],
                 target: tuple[str, int],
                 action: str) -> tuple[np.ndarray, tuple[tuple[str, ...], ...]]:
    """Read the base case with each value set at ``path``, as a case file is read:
    whether the case accepts each value, and the warnings it brings."""
    accepted = np.zeros(len(values), dtype=bool)
    notes: list[tuple[str, ...]] = []
    table = path.split(".", 1)[0].split("[", 1)[0]
    for position, value in enumerate(values):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            notes.append(())
            continue
        # A copy of the table the value goes into; the rest is shared (read only).
        trial = {**document, table: copy.deepcopy(document.get(table))}
        try:
            set_field(trial, path, value)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                case = parse_case(trial, "axis value")
                moved = (build_problem(case.beta_deg, case.phase_deg, case.model, case.option,
                                       case.beta_bounds_deg, case.phase_bounds_deg).moved_starts
                         if action == "optimise" else ())
        except ValueError:
            notes.append(())
            continue
        accepted[position] = True
        field, index = target
        notes.append((*case.warnings,
                      *(message for message in moved
                        if message.startswith(f"start {field}[{index}] "))))
    return accepted, tuple(notes)
