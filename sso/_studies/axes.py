"""Sweep axes: which case keys vary, over which values, and the points they span.

A sweep starts from a base case (a case file, a :class:`sso._cases.shaft_series.Case`, or a
mapping laid out like a case file) and names the keys to vary as a user writes
them in a case file, optionally with indices into a list-valued key:
``"design.beta_deg[1]"`` is the second joint's operating angle,
``"bounds.beta_deg[1]"`` the upper bound of a single bounds pair,
``"bounds.beta_deg[0][1]"`` joint 1's upper bound when bounds are given per joint,
``"option"``, ``"model"`` and ``"input_speed_rpm"`` the whole value.
"""

from __future__ import annotations

import copy
import difflib
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from sso._cases.column import ColumnCase
from sso._cases.schema import load_case, parse_case, schema
from sso._cases.shaft_series import Case
from sso._record import register_record
from sso._validation import finite_float, shown

MODES = ("product", "listed")
MAX_POINTS = 10_000_000
# Keys that describe or label a case rather than pose its problem.
UNSWEPT_KEYS = ("kind", "name", "description", "output.formats")
_PATH = re.compile(r"^(?P<label>[a-z_]+(\.[a-z_]+)?)(?P<indices>(\[\d+\])*)$")


@register_record
@dataclass(frozen=True)
class Axis:
    """One varied field of a sweep.

    Attributes
    ----------
    path : str
        Case key with optional indices, e.g. ``"design.beta_deg[1]"``.
    values : tuple
        The values the key takes, in order.
    """

    path: str
    values: tuple[Any, ...]


def base_case(base: Any) -> Any:
    """The base case as an :class:`sso._cases.shaft_series.Case` or a column's
    :class:`sso._cases.column.ColumnCase` (every default filled in).

    Parameters
    ----------
    base : str, pathlib.Path, Case, ColumnCase or mapping
        A case file, a case read from one, or a mapping laid out like a case file.

    Raises
    ------
    ValueError
        (:class:`sso._cases.schema.CaseError`) if the case breaks the case-file schema.
    """
    if isinstance(base, (str, Path)):
        case = load_case(base)
    elif isinstance(base, (Case, ColumnCase)):
        case = base
    elif isinstance(base, Mapping):
        case = parse_case(_plain(base), "base-case")
    else:
        raise ValueError(f"base is a {type(base).__name__}; it must be a case file path, a case "
                         "read from one (shaft series or column) or a mapping laid out like a "
                         "case file (a tolerance study also takes an sso.OptimisationResult or "
                         "sso.ShaftSeries, or a column design)")
    if not isinstance(case, (Case, ColumnCase)):
        # Name the kind, not the whole case (its repr holds every value).
        raise ValueError(f"kind = {case.kind!r}: sso sweep and sso tolerance work on "
                         "shaft_series and column cases (a mechanism's angles are its table's "
                         "rows: sso run)")
    return case


def sweepable_keys(document: Mapping[str, Any]) -> list[str]:
    """Keys of a case of this kind that an axis may vary, as dotted labels."""
    return [key.label for key in schema(document.get("kind", "shaft_series"))
            if key.label not in UNSWEPT_KEYS]


def parse_axes(axes: Mapping[str, Any], document: dict[str, Any]) -> tuple[Axis, ...]:
    """Validate axis specifications against a completed case.

    Parameters
    ----------
    axes : mapping of str to values
        Field path to a list of values, or to a range ``{"start", "stop", "num"}``
        (``num`` values, both ends included) or ``{"start", "stop", "step"}``
        (from ``start`` in steps up to and including ``stop`` when it falls on the
        grid).
    document : mapping
        The complete base case document (``base_case(base).to_dict()``).

    Returns
    -------
    tuple of Axis

    Raises
    ------
    ValueError
        Naming the axis, for an unknown key (with the nearest sweepable key), an
        index outside the key's value, an empty list or a malformed range.
    """
    if not isinstance(axes, Mapping) or not axes:
        raise ValueError(f"axes = {shown(axes)} must map one or more case keys to values")
    allowed = sweepable_keys(document)
    parsed = []
    for path, spec in axes.items():
        label, _ = _split_path(path)
        if label not in allowed:
            close = difflib.get_close_matches(label, allowed, n=1, cutoff=0.6)
            hint = f"; did you mean {close[0]!r}?" if close else ""
            raise ValueError(f"axis {shown(path)}: {shown(label)} is not a key that can be "
                             f"swept{hint} "
                             f"Sweepable keys: {', '.join(allowed)}")
        values = _axis_values(path, spec)
        set_field(copy.deepcopy(document), path, values[0])  # do the indices fit the case?
        parsed.append(Axis(path=path, values=values))
    return tuple(parsed)


def expand_points(axes: Sequence[Axis], mode: str = "product") -> list[dict[str, Any]]:
    """The points of a sweep: one mapping of axis path to value per point.

    ``"product"`` takes every combination (the last axis varies fastest);
    ``"listed"`` pairs the ``i``-th values of every axis (all axes equally long).

    Raises
    ------
    ValueError
        If the mode is unknown, listed axes differ in length, or the product is
        larger than :data:`MAX_POINTS`.
    """
    count = point_count(axes, mode)
    positions = [position.tolist() for position in value_positions(axes, mode, range(count))]
    return [{axis.path: axis.values[column[row]] for axis, column in zip(axes, positions,
                                                                         strict=True)}
            for row in range(count)]


def point_count(axes: Sequence[Axis], mode: str) -> int:
    """Points of a sweep over ``axes`` in ``mode`` (see :func:`expand_points`).

    Raises
    ------
    ValueError
        If the mode is unknown, listed axes differ in length, or the product is
        larger than :data:`MAX_POINTS`.
    """
    if mode not in MODES:
        raise ValueError(f"mode = {shown(mode)} is not one of {', '.join(map(repr, MODES))}")
    if mode == "listed":
        lengths = {axis.path: len(axis.values) for axis in axes}
        if len(set(lengths.values())) > 1:
            raise ValueError(f"mode 'listed' needs axes of equal length; got {lengths}")
        return len(axes[0].values)
    count = math.prod(len(axis.values) for axis in axes)
    if count > MAX_POINTS:
        raise ValueError(f"the sweep has {count} points, outside the allowed range "
                         f"[1, {MAX_POINTS}]")
    return count


def value_positions(axes: Sequence[Axis], mode: str, indices: Any) -> tuple[Any, ...]:
    """Per axis, the position of each point's value (``indices``: point indices, an array).

    The inverse of :func:`expand_points`'s order: in ``"product"`` mode the last axis
    varies fastest, in ``"listed"`` mode point ``i`` takes every axis's ``i``-th value.
    """
    indices = np.asarray(indices, dtype=np.int64)
    if mode == "listed":
        return tuple(indices for _ in axes)
    return tuple(np.unravel_index(indices, tuple(len(axis.values) for axis in axes)))


def value_ranges(lengths: Sequence[int], mode: str, first: int,
                 last: int) -> tuple[tuple[int, int], ...]:
    """Per axis, a range ``(low, high)`` of value positions holding the value of every
    point from index ``first`` to ``last`` (any of them, or all): found from the two
    ends alone, with no work per point.

    In ``"product"`` mode axis ``k``'s position is ``(index // stride) % length``:
    it runs through consecutive values between the ends unless it wraps around
    (then the range is the whole axis).
    """
    if mode == "listed":
        return tuple((first, last + 1) for _ in lengths)
    ranges = []
    stride = math.prod(lengths)
    for length in lengths:
        stride //= length
        low, high = first // stride, last // stride
        if high - low >= length or low % length > high % length:
            ranges.append((0, length))
        else:
            ranges.append((low % length, high % length + 1))
    return tuple(ranges)


def point_document(document: Mapping[str, Any], point: Mapping[str, Any]) -> dict[str, Any]:
    """A copy of the case document with the point's axis values set."""
    result = copy.deepcopy(dict(document))
    for path, value in point.items():
        set_field(result, path, value)
    return result


def set_field(document: dict[str, Any], path: str, value: Any) -> None:
    """Set ``document[table][name][i][j]...`` in place (``path`` as in :class:`Axis`).

    Raises
    ------
    ValueError
        If an index does not fit the key's value in ``document``.
    """
    label, indices = _split_path(path)
    *tables, name = label.split(".")
    parent = document
    for table in tables:
        parent = parent.setdefault(table, {})
    if not indices:
        parent[name] = copy.deepcopy(value)
        return
    container = parent.get(name)
    for depth, index in enumerate(indices):
        if not isinstance(container, list) or not 0 <= index < len(container):
            where = label + "".join(f"[{i}]" for i in indices[:depth])
            size = len(container) if isinstance(container, list) else 0
            allowed = f"[0, {size - 1}]" if size else "none (not a list)"
            raise ValueError(f"axis {shown(path)}: index {index} of {where} is outside the "
                             f"allowed range {allowed}")
        if depth == len(indices) - 1:
            container[index] = copy.deepcopy(value)
        else:
            container = container[index]


def _split_path(path: Any) -> tuple[str, list[int]]:
    match = _PATH.match(path) if isinstance(path, str) else None
    if match is None:
        raise ValueError(f"axis {shown(path)} is not a case key with optional [index] parts, "
                         "e.g. 'design.beta_deg[1]' or 'option'")
    return match["label"], [int(index) for index in re.findall(r"\d+", match["indices"])]


def _axis_values(path: str, spec: Any) -> tuple[Any, ...]:
    if isinstance(spec, Mapping):
        return _range_values(path, spec)
    if isinstance(spec, (str, bytes)) or not isinstance(spec, Sequence):
        raise ValueError(f"axis {shown(path)} = {shown(spec)} must be a list of values or a range "
                         "{start, stop, num | step}")
    if len(spec) == 0:
        raise ValueError(f"axis {shown(path)} is empty: give at least 1 value")
    return tuple(_plain(list(spec)))


def _range_values(path: str, spec: Mapping[str, Any]) -> tuple[float, ...]:
    keys = set(spec)
    if keys not in ({"start", "stop", "num"}, {"start", "stop", "step"}):
        raise ValueError(f"axis {shown(path)} range has keys {sorted(keys)}; give start, stop "
                         "and either num or step")
    start = finite_float(f"axis {shown(path)} start", spec["start"])
    stop = finite_float(f"axis {shown(path)} stop", spec["stop"])
    if not math.isfinite(stop - start):
        raise ValueError(f"axis {shown(path)} from {start:g} to {stop:g} spans more than a "
                         "float can hold")
    if "num" in spec:
        num = spec["num"]
        if isinstance(num, bool) or not isinstance(num, int) or not 1 <= num <= MAX_POINTS:
            raise ValueError(f"axis {shown(path)} num = {shown(num)} is outside the allowed range "
                             f"[1, {MAX_POINTS}] (a whole number)")
        step = (stop - start) / (num - 1) if num > 1 else 0.0
    else:
        step = finite_float(f"axis {shown(path)} step", spec["step"])
        if step == 0 or (stop - start) / step < 0:
            raise ValueError(f"axis {shown(path)} step = {step:g} must be non-zero and point "
                             f"from start {start:g} towards stop {stop:g}")
        steps = (stop - start) / step
        if not math.isfinite(steps) or steps >= MAX_POINTS:
            raise ValueError(f"axis {shown(path)} step = {step:g} from {start:g} to {stop:g} "
                             f"spans more values than the allowed range [1, {MAX_POINTS}]; "
                             "give a larger step")
        num = math.floor(steps * (1 + 1e-12) + 1e-9) + 1
        if num > MAX_POINTS:
            raise ValueError(f"axis {shown(path)} spans {num} values, outside the allowed range "
                             f"[1, {MAX_POINTS}]")
    # Twelve significant digits drop the round-off of start + i * step.
    return tuple(float(f"{start + index * step:.12g}") for index in range(num))


def _plain(value: Any) -> Any:
    """Tuples to lists and numpy scalars to Python numbers, recursively."""
    if isinstance(value, Mapping):
        return {key: _plain(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(item) for item in value]
    if hasattr(value, "item") and getattr(value, "ndim", None) == 0:
        return value.item()
    return value
