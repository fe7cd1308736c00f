"""Sweep points as arrays: a chunk's designs built, solved, evaluated and laid out at once.

A sweep whose axes vary only design values (``design.beta_deg[i]``,
``design.phase_deg[i]``) and the input speed of an exact-model shaft series, and
that evaluates or optimises with ``"lm"`` alone, needs no case per point: every
point shares the base case's problem (joints, option, bounds, solver settings) and
differs only in numbers. Its chunk is then array work:

1. the points' angles and speeds: the base design with the axes' columns set;
2. optimising: one :func:`sso.optimise_batch` call over every point's own start,
   then one over the other starts of the points whose own start stopped above
   round-off zero (``sso.optimise`` stops there too); the starts are those
   ``sso.optimise`` draws (the Halton points depend on the bounds and the seed, not
   on the point), and each point keeps its best start (converged first, then the
   lowest RE);
3. the figures of each design: the exact model's closed forms in one numpy pass
   (:mod:`sso._kinematics.hooke_matrix`, as :meth:`sso.ShaftSeries.evaluate`);
4. the rows: a :class:`sso._studies.columns.RowTable`.

Each axis value a chunk's points take is read as a case where the chunk runs
(:mod:`sso._studies.axis_checks`: the base case with that value set, as a case file
is read): a point holding a value the case refuses takes the point-by-point path,
which records its error as every sweep does. The warnings of a point are those of
its values.
"""

from __future__ import annotations

import re
import secrets
import time
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from sso._kinematics.hooke_matrix import peak_ratio_slope, ratio_extremes, residual_error
from sso._shafts.batch import optimise_batch
from sso._shafts.evaluation import RPM_TO_RAD_S
from sso._shafts.options import build_problem
from sso._solvers.lm import MESSAGES as STATUS_MESSAGES
from sso._solvers.starts import start_points
from sso._studies.axes import Axis
from sso._studies.axis_checks import AxisValues
from sso._studies.columns import RowTable
from sso._studies.element_columns import element_names, split_columns

ZERO_OBJECTIVE = 1e-20
"""RE at or below this is a global minimum: ``sso.optimise`` stops its starts there."""
MOST_CHECKED_VALUES = 20_000
"""Most axis values of an array sweep; a sweep with more takes the point path (a worker
reads every value its chunks take, at most every value of every axis)."""
_DESIGN_PATH = re.compile(r"^design\.(?P<field>beta_deg|phase_deg)\[(?P<index>\d+)\]$")
SOLVER = "lm"
FIGURE_COLUMNS = ("residual_error", "residual_error_rpm2", "fluctuation",
                  "max_output_accel_rad_s2")
"""The figures of a design, each a number per point (:func:`_figures`)."""


@dataclass(frozen=True)
class ArrayPlan:
    """What every point of an array sweep shares (the base case's problem)."""

    action: str
    beta_deg: tuple[float, ...]
    phase_deg: tuple[float, ...]
    input_speed_rpm: float
    option: int
    beta_bounds_deg: tuple[tuple[float, float], ...]
    phase_bounds_deg: tuple[tuple[float, float], ...]
    solver_tol: float
    max_iterations: int
    other_starts_deg: np.ndarray
    free: tuple[int, ...]
    base_notes: tuple[str, ...]
    targets: tuple[tuple[str, int], ...]
    run: str


def array_plan(case: Any, axes: Sequence[Axis], action: str) -> ArrayPlan | None:
    """The plan of a sweep the engine can run, or None (the point-by-point path).

    Each call is a new sweep run (:attr:`ArrayPlan.run`): the chunks of its plan read
    their axis values afresh.
    """

    if (case.kind != "shaft_series" or case.model != "exact"
            or (action == "optimise" and tuple(case.solvers) != (SOLVER,))
            or sum(len(axis.values) for axis in axes) > MOST_CHECKED_VALUES):
        return None
    targets = [_target(axis.path) for axis in axes]
    if any(target is None for target in targets):
        return None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        problem = build_problem(case.beta_deg, case.phase_deg, case.model, case.option,
                                case.beta_bounds_deg, case.phase_bounds_deg)
    swept = {target for target in targets if target is not None}
    base_moved = tuple(message for message in problem.moved_starts
                       if not any(message.startswith(f"start {field}[{index}] ")
                                  for field, index in swept))
    free = [*(range(problem.n_joints) if problem.beta_free else ()),
            *(problem.n_joints + index for index in range(problem.n_joints - 1)
              if problem.phase_free)]
    starts_rad = start_points(problem.start_rad, problem.lower_rad, problem.upper_rad,
                              case.starts, case.seed)[1:]
    free_bounds = np.array([*(problem.beta_bounds_deg if problem.beta_free else ()),
                            *(problem.phase_bounds_deg if problem.phase_free else ())],
                           dtype=float).reshape(-1, 2)
    other_starts = np.clip(np.degrees(starts_rad), free_bounds[:, 0], free_bounds[:, 1])
    return ArrayPlan(
        action=action, beta_deg=tuple(case.beta_deg), phase_deg=tuple(case.phase_deg),
        input_speed_rpm=float(case.input_speed_rpm), option=problem.option,
        beta_bounds_deg=tuple(problem.beta_bounds_deg),
        phase_bounds_deg=tuple(problem.phase_bounds_deg), solver_tol=float(case.solver_tol),
        max_iterations=int(case.max_iterations), other_starts_deg=other_starts,
        free=tuple(free), base_notes=(*case.warnings, *base_moved),
        targets=tuple(target for target in targets if target is not None),
        run=secrets.token_hex(8))


def _target(path: str) -> tuple[str, int] | None:
    if path == "input_speed_rpm":
        return ("input_speed_rpm", 0)
    match = _DESIGN_PATH.match(path)
    return None if match is None else (match["field"], int(match["index"]))


def number_columns(plan: ArrayPlan,
                   axes: Sequence[Axis]) -> dict[str, tuple[np.dtype, tuple[int, ...]]]:
    """The number columns of every chunk :func:`run_array_points` makes for a sweep
    over ``axes``: each one's dtype and the shape of one row (each element of a
    design's angles a column of its own)."""
    whole, number = np.dtype(np.int64), np.dtype(float)
    kinds: dict[str, tuple[np.dtype, tuple[int, ...]]] = {"point": (whole, ())}
    kinds.update({axis.path: (number, ()) for axis in axes
                  if all(isinstance(value, float) for value in axis.values)})
    if plan.action == "optimise":
        kinds.update({f"{SOLVER}_residual_error": (number, ()), f"{SOLVER}_status": (whole, ()),
                      f"{SOLVER}_kkt_per_rad": (number, ()), f"{SOLVER}_time_s": (number, ())})
    kinds.update({name: (number, ()) for name in (*FIGURE_COLUMNS, "time_s")})
    kinds.update({name: (number, ()) for name in (
        *element_names("design_beta_deg", (len(plan.beta_deg),)),
        *element_names("design_phase_deg", (len(plan.phase_deg),)))})
    return kinds


def run_array_points(plan: ArrayPlan, axes: Sequence[AxisValues], header: Sequence[str],
                     paths: Sequence[str], indices: np.ndarray,
                     value_indices: Sequence[np.ndarray],
                     values: Sequence[Sequence[Any]]) -> RowTable:
    """The rows of a chunk's points, every one accepted by the case (see the module).

    Parameters
    ----------
    plan : ArrayPlan
        The sweep's plan.
    axes : sequence of AxisValues
        Per axis, the chunk's values as read (:func:`sso._studies.axis_checks.chunk_axes`).
    header : sequence of str
        The columns of ``sweep.csv``.
    paths : sequence of str
        The axes' paths.
    indices : numpy.ndarray
        The points' indices.
    value_indices : sequence of numpy.ndarray
        Per axis, the position of each point's value in ``values[k]``.
    values : sequence of sequence
        Per axis, the chunk's values.
    """
    started = time.perf_counter()
    count = len(indices)
    beta = np.tile(np.asarray(plan.beta_deg, dtype=float), (count, 1))
    phase = np.tile(np.asarray(plan.phase_deg, dtype=float), (count, 1)).reshape(
        count, len(plan.phase_deg))
    speed = np.full(count, plan.input_speed_rpm)
    columns: dict[str, np.ndarray] = {"point": np.asarray(indices, dtype=np.int64)}
    for path, axis, positions, axis_values in zip(paths, axes, value_indices, values,
                                                  strict=True):
        numbers = np.asarray(axis_values, dtype=float)[positions]
        if all(isinstance(value, float) for value in axis_values):
            columns[path] = numbers
        else:  # whole numbers stay whole numbers, as in a case file
            cells = np.empty(len(axis_values), dtype=object)
            cells[:] = list(axis_values)
            columns[path] = cells[positions]
        field, index = axis.target
        if field == "beta_deg":
            beta[:, index] = numbers
        elif field == "phase_deg":
            phase[:, index] = numbers
        else:
            speed = numbers
    if plan.action == "optimise":
        beta, phase, solver_cells = _optimise(plan, beta, phase)
        columns.update(solver_cells)
    columns.update(_figures(beta, phase, speed))
    columns["status"] = _repeated("ok", count)
    columns["warnings"] = _notes(plan, axes, value_indices, count)
    columns["time_s"] = np.full(count, (time.perf_counter() - started) / max(count, 1))
    return RowTable(tuple(header), columns, count)


def _optimise(plan: ArrayPlan, beta: np.ndarray,
              phase: np.ndarray) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]:
    """Each point's best design over its starts, and its solver columns."""

    started = time.perf_counter()
    count = len(beta)
    settings: dict[str, Any] = {"option": plan.option, "beta_bounds_deg": plan.beta_bounds_deg,
                "phase_bounds_deg": plan.phase_bounds_deg, "solver_tol": plan.solver_tol,
                "max_iterations": plan.max_iterations}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # each point's moved start is in its own notes
        own = optimise_batch(beta, phase, **settings)
    fun = own.fun.copy()
    success = own.success.copy()
    status = own.status.copy()
    kkt = own.kkt.copy()
    best_beta = own.beta_deg.copy()
    best_phase = own.phase_deg.copy()
    tried = np.ones(count)
    others = len(plan.other_starts_deg)
    rest = (np.flatnonzero(~(own.success & (own.fun <= ZERO_OBJECTIVE))) if others
            else np.zeros(0, dtype=np.int64))
    if len(rest):
        full = np.hstack([beta[rest], phase[rest]])
        designs = np.repeat(full, others, axis=0)
        designs[:, list(plan.free)] = np.tile(plan.other_starts_deg, (len(rest), 1))
        joints = beta.shape[1]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            more = optimise_batch(designs[:, :joints], designs[:, joints:], **settings)
        more_fun = more.fun.reshape(len(rest), others)
        more_success = more.success.reshape(len(rest), others)
        # The first start of the lowest RE among the converged ones (or among all, if
        # none converged): min over (not converged, RE), the point path's choice.
        score = np.where(more_success, more_fun, np.inf)
        chosen = np.where(more_success.any(axis=1), np.argmin(score, axis=1),
                          np.argmin(more_fun, axis=1))
        picked = np.arange(len(rest)) * others + chosen
        own_failed = ~success[rest]
        other_failed = ~more.success[picked]
        better = (other_failed < own_failed) | ((other_failed == own_failed)
                                                & (more.fun[picked] < fun[rest]))
        take = rest[better]
        source = picked[better]
        fun[take] = more.fun[source]
        success[take] = more.success[source]
        status[take] = more.status[source]
        kkt[take] = more.kkt[source]
        best_beta[take] = more.beta_deg[source]
        best_phase[take] = more.phase_deg[source]
        tried[rest] += others
    per_start_s = (time.perf_counter() - started) / tried.sum()
    messages = np.empty(len(STATUS_MESSAGES), dtype=object)
    codes = sorted(STATUS_MESSAGES)
    messages[:] = [STATUS_MESSAGES[code] for code in codes]
    cells = {
        "success": _flags(success),
        "best_solver": _repeated(SOLVER, count),
        f"{SOLVER}_residual_error": fun,
        f"{SOLVER}_status": status.astype(np.int64),
        f"{SOLVER}_success": _flags(success),
        f"{SOLVER}_message": messages[np.searchsorted(codes, status)],
        f"{SOLVER}_kkt_per_rad": kkt,
        f"{SOLVER}_time_s": per_start_s * tried,
    }
    return best_beta, best_phase, cells


def _figures(beta_deg: np.ndarray, phase_deg: np.ndarray,
             speed_rpm: np.ndarray) -> dict[str, np.ndarray]:
    """The exact model's figures of each design, as :meth:`sso.ShaftSeries.evaluate`."""
    beta = list(np.radians(beta_deg).T)
    phase = list(np.radians(phase_deg).T)
    error = np.asarray(residual_error(np, beta, phase), dtype=float)
    least, greatest = ratio_extremes(np, beta, phase)
    slope = np.asarray(peak_ratio_slope(np, beta, phase), dtype=float)
    return {
        "residual_error": error,
        "residual_error_rpm2": speed_rpm**2 * error,
        "fluctuation": np.asarray(greatest - least, dtype=float) * np.ones(len(beta_deg)),
        "max_output_accel_rad_s2": (speed_rpm * RPM_TO_RAD_S) ** 2 * slope,
        **split_columns("design_beta_deg", beta_deg),
        **split_columns("design_phase_deg", phase_deg),
    }


def _notes(plan: ArrayPlan, axes: Sequence[AxisValues], value_indices: Sequence[np.ndarray],
           count: int) -> np.ndarray:
    """Each point's warnings: the base case's, then its values', once each."""
    column = np.empty(count, dtype=object)
    if not plan.base_notes and not any(any(axis.notes) for axis in axes):
        column[:] = ""
        return column
    keys = np.stack(value_indices, axis=1) if value_indices else np.zeros((count, 0), int)
    cache: dict[tuple[int, ...], str] = {}
    for row, key in enumerate(map(tuple, keys.tolist())):
        text = cache.get(key)
        if text is None:
            notes = [*plan.base_notes, *(note for axis, position in zip(axes, key,
                                                                        strict=True)
                                         for note in axis.notes[position])]
            text = cache[key] = " | ".join(dict.fromkeys(notes))
        column[row] = text
    return column


def _flags(values: np.ndarray) -> np.ndarray:
    column = np.empty(len(values), dtype=object)
    column[:] = [bool(value) for value in values.tolist()]
    return column


def _repeated(text: str, count: int) -> np.ndarray:
    column = np.empty(count, dtype=object)
    column[:] = text
    return column
