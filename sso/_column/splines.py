"""Yokes on splines: the best tooth positions of a column, found exactly.

A yoke on a spline of ``N`` teeth can only be turned in steps of ``360 / N`` deg, so
the yoke phasing ``delta_k`` of intermediate shaft ``k`` is ``j_k * 360 / N_k`` with a
whole tooth offset ``j_k`` from the in-phase position (tooth 0 puts the two pin
axes of the shaft parallel). A pin axis is a line, so offsets ``360 / N`` * j that
differ by 180 deg are one assembly; each is listed once, by its smallest offset.

Small cases are enumerated (every combination, vectorised closed form). Larger
ones use a depth-first branch and bound over the shafts: after the yokes of the
first shafts are placed, the partial chain moves the base point of the hyperbolic
plane by ``d`` (see :mod:`sso._column.cancel`); the joints still to come move it by
some ``r`` between ``max(0, l_max - sum of the other l)`` and ``sum l`` of their own
``l = -ln cos beta``, so ``RE >= cosh(max(0, d - r_max, r_min - d)) - 1``;
a branch whose bound exceeds the best complete assembly so far is dropped. Both
give the exact optimum over the teeth (the tests check them against each other and
against brute force).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from sso._column.cancel import can_cancel
from sso._column.chain_matrix import (
    chain_matrix,
    distortion_distance,
    matrix_residual_error,
)
from sso._column.geometry import ColumnGeometry, wrap_half_turn
from sso._display import Part, Readable, TextTable, format_number
from sso._limits import CONVENTIONAL_PHASE_DEG, DEFAULT_SPLINE_TEETH, SPLINE_ENUMERATION_LIMIT
from sso._record import Record, register_record
from sso._validation import validate_count

CHUNK_ROWS = 65_536
# Assemblies whose RE is within this of the best are reported as ties (round-off).
TIE_RELATIVE, TIE_ABSOLUTE = 1e-12, 1e-18
METHODS = ("auto", "enumeration", "branch_and_bound")
MAX_TEETH = 1000


@register_record
@dataclass(frozen=True)
class YokeInstruction:
    """How a fitter sets the yoke at the downstream end of one intermediate shaft.

    Attributes
    ----------
    shaft : int
        Intermediate shaft number ``k`` (1-based), from joint ``k`` to joint ``k + 1``.
    teeth : int
        Teeth of its spline.
    tooth_offset : int
        Signed teeth from the in-phase position (positive: right-hand rule about
        the shaft direction, i.e. clockwise looking from joint ``k`` to ``k + 1``).
    offset_deg : float
        ``tooth_offset * 360 / teeth``, deg.
    text : str
        The instruction in words.
    """

    shaft: int
    teeth: int
    tooth_offset: int
    offset_deg: float
    text: str


@dataclass(frozen=True, eq=False, repr=False)
class SplineResult(Record, Readable):
    """Best tooth positions of a column's yokes.

    Attributes
    ----------
    teeth : tuple of int
        Spline teeth of each intermediate shaft.
    tooth_offset : tuple of int
        Best tooth offset from in-phase per shaft.
    yoke_phase_deg : tuple of float
        The yoke phasing they give, deg.
    residual_error : float
        RE at the best teeth (dimensionless).
    continuous_residual_error : float
        Least RE of any (continuous) phasing, closed form.
    loss : float
        ``residual_error - continuous_residual_error`` (>= 0).
    ties : tuple of tuple of int
        Every tooth assignment with the best RE (round-off ties, e.g. mirrors),
        the reported one first.
    instructions : tuple of YokeInstruction
        One per intermediate shaft.
    method : str
        ``"enumeration"`` or ``"branch_and_bound"``.
    assemblies_evaluated : int
        Complete and partial assemblies whose RE or bound was computed.
    objective : str
        What ``residual_error`` and ``continuous_residual_error`` measure: ``"RE"``
        (the column at its hardpoints) or the case's own objective, e.g. ``"worst-
        position RE"`` (:func:`best_teeth_for_objective`).
    """

    teeth: tuple[int, ...]
    tooth_offset: tuple[int, ...]
    yoke_phase_deg: tuple[float, ...]
    residual_error: float
    continuous_residual_error: float
    loss: float
    ties: tuple[tuple[int, ...], ...]
    instructions: tuple[YokeInstruction, ...]
    method: str
    assemblies_evaluated: int
    objective: str = "RE"

    def _repr_text(self) -> str:
        return (f"teeth {list(self.teeth)}, tooth_offset {list(self.tooth_offset)}, "
                f"{self.objective} {format_number(self.residual_error, 4)} (continuous optimum "
                f"{format_number(self.continuous_residual_error, 4)}), {self.method}")

    def _summary_parts(self) -> list[Part]:
        rows = tuple((str(index + 1), str(teeth), str(offset), format_number(phase))
                     for index, (teeth, offset, phase) in enumerate(
                         zip(self.teeth, self.tooth_offset, self.yoke_phase_deg, strict=True)))
        title = (f"Spline teeth ({self.method}): {self.objective} "
                 f"{format_number(self.residual_error)} (continuous optimum "
                 f"{format_number(self.continuous_residual_error)}), loss "
                 f"{format_number(self.loss)}")
        return [title, TextTable(("intermediate shaft", "teeth", "tooth offset",
                                  "yoke phase (deg)"), rows),
                *self.assembly_text().splitlines()]

    def assembly_text(self) -> str:
        """The instructions, one line per yoke."""
        return "\n".join(instruction.text for instruction in self.instructions)


def best_spline_teeth(geometry: ColumnGeometry,
                      teeth: int | Sequence[int] = DEFAULT_SPLINE_TEETH, *,
                      method: str = "auto",
                      enumeration_limit: int = SPLINE_ENUMERATION_LIMIT) -> SplineResult:
    """Exact best tooth positions of the yokes on the intermediate shafts.

    Parameters
    ----------
    geometry : ColumnGeometry
        The column, at least 2 joints.
    teeth : int or sequence of int
        Spline teeth per intermediate shaft (one number for all), each in ``[1, 1000]``.
    method : {"auto", "enumeration", "branch_and_bound"}
        ``"auto"`` enumerates when there are at most ``enumeration_limit``
        distinct assemblies, else branches and bounds.
    enumeration_limit : int
        Largest number of assemblies ``"auto"`` enumerates.

    Returns
    -------
    SplineResult

    Raises
    ------
    TypeError
        If ``geometry`` is not a :class:`ColumnGeometry`.
    ValueError
        If the column has 1 joint, a tooth count is not a whole number in range,
        or the method is unknown.
    """
    if not isinstance(geometry, ColumnGeometry):
        raise TypeError(f"geometry must be a ColumnGeometry, not {type(geometry).__name__}")
    shafts = geometry.joint_count - 1
    if shafts < 1:
        raise ValueError("geometry has 1 joint: there is no intermediate shaft to set on a spline")
    counts = _validated_teeth(teeth, shafts)
    if method not in METHODS:
        raise ValueError(f"method = {method!r} is not one of {', '.join(map(repr, METHODS))}")
    offsets = [_distinct_offsets(count) for count in counts]
    phase_choices = [np.radians(np.mod(CONVENTIONAL_PHASE_DEG + offset * 360.0 / count - gamma,
                                       180.0))
                     for offset, count, gamma in zip(offsets, counts, geometry.plane_angle_deg,
                                                      strict=True)]
    beta_rad = np.radians(geometry.beta_deg)
    total = math.prod(len(choice) for choice in offsets)
    if method == "auto":
        method = "enumeration" if total <= enumeration_limit else "branch_and_bound"
    if method == "enumeration":
        best_re, best_rows, evaluated = _enumerate(
            phase_choices, lambda phases: matrix_residual_error(chain_matrix(beta_rad, phases)))
    else:
        best_re, best_rows, evaluated = _branch_and_bound(beta_rad, phase_choices)
    best_offsets = [tuple(int(offsets[k][index]) for k, index in enumerate(row))
                    for row in best_rows]
    best_offsets.sort(key=lambda row: (sum(abs(value) for value in row), [-v for v in row]))
    chosen = best_offsets[0]
    continuous = can_cancel(geometry.beta_deg).minimum_residual_error
    return SplineResult(
        teeth=counts,
        tooth_offset=chosen,
        yoke_phase_deg=tuple(offset * 360.0 / count for offset, count in zip(chosen, counts,
                                                                              strict=True)),
        residual_error=best_re,
        continuous_residual_error=continuous,
        loss=max(0.0, best_re - continuous),
        ties=tuple(best_offsets),
        instructions=tuple(_instruction(k + 1, count, offset)
                           for k, (count, offset) in enumerate(zip(counts, chosen, strict=True))),
        method=method,
        assemblies_evaluated=evaluated,
    )


def best_teeth_for_objective(shafts: int, teeth: int | Sequence[int],
                             objective: Callable[[np.ndarray], np.ndarray], *,
                             continuous_yoke_phase_deg: Sequence[float],
                             objective_name: str,
                             enumeration_limit: int = SPLINE_ENUMERATION_LIMIT) -> SplineResult:
    """Best tooth positions for an objective of the yoke phasing itself.

    For a column optimised over several positions, under tolerances or for the
    steering feel, the teeth are searched for that objective (the worst position's
    RE, the tail of RE over built columns, ...), not for the RE of one position.
    Every distinct assembly is evaluated when there are at most ``enumeration_limit``;
    beyond, the assemblies of each shaft's four tooth offsets nearest the continuous
    phasing.

    Parameters
    ----------
    shafts : int
        Intermediate shafts (joints - 1), at least 1.
    teeth : int or sequence of int
        Spline teeth per intermediate shaft, each in ``[1, 1000]``.
    objective : callable
        ``yoke_phase_deg`` of shape ``(m, shafts)`` -> values of shape ``(m,)``, lower
        is better.
    continuous_yoke_phase_deg : sequence of float
        The continuous optimum of the same objective, deg (for ``loss``).
    objective_name : str
        What the objective measures, for the record (``SplineResult.objective``).
    enumeration_limit : int
        Largest number of assemblies evaluated one by one.

    Returns
    -------
    SplineResult
        ``residual_error`` is the objective at the chosen teeth,
        ``continuous_residual_error`` at ``continuous_yoke_phase_deg``.

    Raises
    ------
    ValueError
        If a tooth count is not a whole number in range.
    """
    counts = _validated_teeth(teeth, shafts)
    continuous = np.asarray(continuous_yoke_phase_deg, dtype=float)
    offsets = [_distinct_offsets(count) for count in counts]
    if math.prod(len(choice) for choice in offsets) > enumeration_limit:
        offsets = [_nearest_offsets(choice, count, target)
                   for choice, count, target in zip(offsets, counts, continuous, strict=True)]
    choices = [choice * 360.0 / count for choice, count in zip(offsets, counts, strict=True)]
    best_value, best_rows, evaluated = _enumerate(choices, lambda yokes: np.asarray(
        objective(yokes), dtype=float))
    best_offsets = sorted((tuple(int(offsets[k][index]) for k, index in enumerate(row))
                           for row in best_rows),
                          key=lambda row: (sum(abs(value) for value in row), [-v for v in row]))
    chosen = best_offsets[0]
    continuous_value = float(np.asarray(objective(continuous[np.newaxis, :]), dtype=float)[0])
    return SplineResult(
        teeth=counts, tooth_offset=chosen,
        yoke_phase_deg=tuple(offset * 360.0 / count
                             for offset, count in zip(chosen, counts, strict=True)),
        residual_error=best_value, continuous_residual_error=continuous_value,
        loss=max(0.0, best_value - continuous_value), ties=tuple(best_offsets),
        instructions=tuple(_instruction(k + 1, count, offset)
                           for k, (count, offset) in enumerate(zip(counts, chosen, strict=True))),
        method="enumeration", assemblies_evaluated=evaluated, objective=objective_name)


def _nearest_offsets(offsets: np.ndarray, teeth: int, target_deg: float) -> np.ndarray:
    """The four offsets whose phasing is nearest ``target_deg`` (mod 180 deg)."""
    distance = np.abs(wrap_half_turn(offsets * 360.0 / teeth - target_deg))
    return np.sort(offsets[np.argsort(distance, kind="stable")[:4]])


def _validated_teeth(teeth: Any, shafts: int) -> tuple[int, ...]:
    if isinstance(teeth, (int, np.integer)) and not isinstance(teeth, bool):
        return (validate_count("teeth", teeth, 1, MAX_TEETH),) * shafts
    try:
        items = list(teeth)
    except TypeError:
        raise ValueError(f"teeth = {teeth!r} must be a whole number or one per intermediate "
                         f"shaft ({shafts})") from None
    if len(items) != shafts:
        raise ValueError(f"teeth has {len(items)} entries; the column has {shafts} "
                         "intermediate shafts")
    return tuple(validate_count(f"teeth[{index}]", item, 1, MAX_TEETH)
                 for index, item in enumerate(items))


def _distinct_offsets(teeth: int) -> np.ndarray:
    """Tooth offsets giving distinct phasings mod 180 deg, each the smallest in size."""
    chosen: dict[int, int] = {}
    for offset in sorted(range(-teeth, teeth + 1), key=lambda value: (abs(value), -value)):
        key = round(float(wrap_half_turn(offset * 360.0 / teeth)) * 1e6)
        chosen.setdefault(key, offset)
    return np.array(sorted(chosen.values()))


def _enumerate(choices: list[np.ndarray], evaluate: Callable[[np.ndarray], np.ndarray]
               ) -> tuple[float, list[tuple[int, ...]], int]:
    """Every combination of ``choices`` (one array per shaft), in blocks: ``evaluate``
    maps a block of rows of chosen values to their objective values."""
    indices = itertools.product(*(range(len(choice)) for choice in choices))
    best_re, evaluated = math.inf, 0
    best_rows: list[tuple[int, ...]] = []
    while True:
        block = np.array(list(itertools.islice(indices, CHUNK_ROWS)), dtype=int)
        if block.size == 0:
            break
        values = evaluate(np.stack([choices[k][block[:, k]] for k in range(len(choices))],
                                   axis=1))
        evaluated += len(values)
        best_re, best_rows = _merge_best(best_re, best_rows, values, block)
    return best_re, best_rows, evaluated


def _merge_best(best_re: float, best_rows: list[tuple[int, ...]], values: np.ndarray,
                rows: np.ndarray) -> tuple[float, list[tuple[int, ...]]]:
    lowest = float(values.min())
    if lowest < best_re:
        best_rows = [row for row in best_rows if _tied(best_re, lowest)]
        best_re = lowest
    tied = values <= best_re + TIE_RELATIVE * best_re + TIE_ABSOLUTE
    best_rows = best_rows + [tuple(int(i) for i in row) for row in rows[tied]]
    return best_re, best_rows


def _tied(value: float, best: float) -> bool:
    return value <= best + TIE_RELATIVE * best + TIE_ABSOLUTE


def _branch_and_bound(beta_rad: np.ndarray, choices: list[np.ndarray]
                      ) -> tuple[float, list[tuple[int, ...]], int]:
    cosines = np.cos(beta_rad)
    lengths = -np.log(cosines)
    # Joints after level k's partial chain (joints 1..k+2 placed): reach of the rest
    # of the chain, at most its sum, at least its largest minus the others.
    rest_sum = np.array([lengths[level + 2:].sum() for level in range(len(lengths) - 1)])
    rest_least = np.array([max(0.0, 2.0 * lengths[level + 2:].max(initial=0.0)
                               - lengths[level + 2:].sum())
                           for level in range(len(lengths) - 1)])
    start = np.array([[1.0, 0.0], [0.0, cosines[0]]])[None]
    stack: list[tuple[int, np.ndarray, np.ndarray]] = [(0, start, np.zeros((1, 0), dtype=int))]
    best_re, evaluated = math.inf, 0
    best_rows: list[tuple[int, ...]] = []
    shafts = len(choices)
    while stack:
        level, matrices, rows = stack.pop()
        phase = choices[level]
        cos_phase, sin_phase = np.cos(phase), np.sin(phase)
        rotated_top = (cos_phase[None, :, None] * matrices[:, None, 0, :]
                       - sin_phase[None, :, None] * matrices[:, None, 1, :])
        rotated_bottom = (sin_phase[None, :, None] * matrices[:, None, 0, :]
                          + cos_phase[None, :, None] * matrices[:, None, 1, :])
        children = np.stack([rotated_top, cosines[level + 1] * rotated_bottom], axis=-2)
        children = children.reshape(-1, 2, 2)
        child_rows = np.concatenate([np.repeat(rows, len(phase), axis=0),
                                     np.tile(np.arange(len(phase)), len(rows))[:, None]], axis=1)
        evaluated += len(children)
        if level + 1 == shafts:
            best_re, best_rows = _merge_best(best_re, best_rows,
                                             matrix_residual_error(children), child_rows)
            continue
        distance = distortion_distance(children)
        gap = np.maximum(distance - rest_sum[level], rest_least[level] - distance)
        bound = np.cosh(np.maximum(0.0, gap)) - 1.0
        keep = bound <= best_re * (1.0 + 1e-9) + TIE_ABSOLUTE
        children, child_rows, bound = children[keep], child_rows[keep], bound[keep]
        order = np.argsort(-bound)  # most promising last, so it is popped first
        children, child_rows = children[order], child_rows[order]
        for first in range(0, len(children), CHUNK_ROWS)[::-1]:
            stack.append((level + 1, children[first:first + CHUNK_ROWS],
                          child_rows[first:first + CHUNK_ROWS]))
    return best_re, best_rows, evaluated


def _instruction(shaft: int, teeth: int, offset: int) -> YokeInstruction:
    degrees = offset * 360.0 / teeth
    # "yoke at joint 3: 8 teeth" cannot be misread as "joint 38".
    where = (f"Intermediate shaft {shaft} (joint {shaft} to joint {shaft + 1}, {teeth} teeth), "
             f"yoke at joint {shaft + 1}: ")
    if offset == 0:
        text = (f"{where}0 teeth, in phase with the yoke at joint {shaft} (pin axes "
                "parallel).")
    else:
        direction = "clockwise" if offset > 0 else "anticlockwise"
        plural = "tooth" if abs(offset) == 1 else "teeth"
        text = (f"{where}{abs(offset)} {plural} ({abs(degrees):.1f} deg) {direction} from the "
                f"in-phase position, looking along the shaft from joint {shaft} towards joint "
                f"{shaft + 1}.")
    return YokeInstruction(shaft=shaft, teeth=teeth, tooth_offset=offset, offset_deg=degrees,
                           text=text)
