"""The tolerance band of a design: how far each yoke phase and operating angle may stray.

For a design (a column and its yoke phasing) and an RE limit:

* per yoke phasing ``delta_k`` (fitter's convention) and per operating angle
  ``beta_k``, the interval ``(lower, upper)`` in deg around the design value over
  which RE stays at or below the limit with everything else at nominal. Each edge
  is a root of ``RE / limit - 1``: bracketed by a scan outward from the design
  value in steps of ``SCAN_STEP_DEG`` and refined with ``scipy.optimize.brentq``
  to ``1e-10`` deg. A phasing whose RE stays under the limit over a whole period
  (180 deg) has no edge; an angle that can fall to 0 without crossing the limit
  has 0 as its lower edge (``lower_at_limit`` False). Operating angles move alone
  (bend-plane angles held): the drawing's angle tolerance, not a hardpoint study;
* the box of phase errors: half-widths ``s * w_k`` with ``w_k`` the smaller side of
  phasing ``k``'s interval, ``s`` in ``(0, 1]`` the largest scale whose worst
  corner stays at the limit (root of ``max over corners RE / limit - 1``, scanned
  on ``BOX_SCAN_POINTS`` values of ``s`` and refined by ``brentq``). Near an
  optimum RE is convex in the phasings, so the worst point of a box is a corner;
  a grid of the whole box (up to ``BOX_GRID_POINTS`` per axis) checks that and
  reports its largest RE (``box_grid_max_re``).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from sso._column.cancel import can_cancel
from sso._column.chain_matrix import residual_error
from sso._column.design import column_design
from sso._column.geometry import ColumnGeometry
from sso._display import Part, Readable, TextTable, format_number, format_numbers
from sso._limits import BETA_LIMIT_DEG, DEFAULT_PHASE_ERROR_POINTS, DEFAULT_PHASE_ERROR_SPAN_DEG
from sso._record import Record, register_record
from sso._validation import finite_in_range, validate_count

SCAN_STEP_DEG = 0.05
EDGE_XTOL_DEG = 1e-10
HALF_TURN_DEG = 180.0
# Largest operating angle the scan reaches, deg (RE grows without bound towards 90).
BETA_SCAN_TOP_DEG = BETA_LIMIT_DEG - 1e-6
BOX_SCAN_POINTS = 400
BOX_GRID_POINTS = 21
# At most about this many grid points in the box (fewer per axis for many shafts).
BOX_GRID_SIZE = 100_000


@register_record
@dataclass(frozen=True)
class Interval:
    """Where one angle may lie with the others at nominal and RE at or below the limit.

    Attributes
    ----------
    name : str
        ``"yoke_phase_deg[k]"`` or ``"beta_deg[k]"`` (0-based).
    nominal_deg, lower_deg, upper_deg : float
        The design value and the edges, deg (``lower <= nominal <= upper``; a
        phasing interval is not wrapped, so it may extend past +-90).
    lower_at_limit, upper_at_limit : bool
        True when RE equals the limit at that edge; False when the edge is the end
        of the range searched (a whole period for a phasing, 0 deg for an angle).
    lower_re, upper_re : float
        RE at the edges.
    """

    name: str
    nominal_deg: float
    lower_deg: float
    upper_deg: float
    lower_at_limit: bool
    upper_at_limit: bool
    lower_re: float
    upper_re: float


@dataclass(frozen=True, eq=False, repr=False)
class ToleranceBand(Record, Readable):
    """Outcome of :func:`tolerance_band`.

    Attributes
    ----------
    re_limit : float
    nominal_re : float
        RE of the design.
    yoke_phase_deg : tuple of float
        The design's yoke phasing, deg (fitter's convention).
    yoke_phase : tuple of Interval
        Per intermediate shaft.
    operating_angle : tuple of Interval
        Per joint.
    box_half_width_deg : tuple of float
        Half-width of the box of phase errors per intermediate shaft, deg.
    box_scale : float
        ``s``: the box's half-widths over the smaller sides of the intervals.
    box_corner_max_re : float
        Largest RE over the box's corners (the limit, unless ``box_scale`` is 1).
    box_grid_max_re : float
        Largest RE over a grid of the whole box (at most the limit when the
        corners decide, as they do where RE is convex).
    geometry : ColumnGeometry
    """

    re_limit: float
    nominal_re: float
    yoke_phase_deg: tuple[float, ...]
    yoke_phase: tuple[Interval, ...]
    operating_angle: tuple[Interval, ...]
    box_half_width_deg: tuple[float, ...]
    box_scale: float
    box_corner_max_re: float
    box_grid_max_re: float
    geometry: ColumnGeometry

    def _repr_text(self) -> str:
        return (f"re_limit={format_number(self.re_limit)}, nominal_re="
                f"{format_number(self.nominal_re)}, yoke_phase_deg "
                f"[{format_numbers(self.yoke_phase_deg)}], box half-widths "
                f"[{format_numbers(self.box_half_width_deg)}] deg")

    def _summary_parts(self) -> list[Part]:
        def row(interval: Interval) -> tuple[str, ...]:
            def edge(value: float, at_limit: bool) -> str:
                return format_number(value) + ("" if at_limit else " (end of range)")

            return (interval.name, format_number(interval.nominal_deg),
                    edge(interval.lower_deg, interval.lower_at_limit),
                    edge(interval.upper_deg, interval.upper_at_limit))

        header = ("angle", "nominal (deg)", "lower (deg)", "upper (deg)")
        return [f"Tolerance band: RE <= {format_number(self.re_limit)} (nominal RE "
                f"{format_number(self.nominal_re)})",
                TextTable(header, tuple(row(item) for item in self.yoke_phase)),
                TextTable(header, tuple(row(item) for item in self.operating_angle)),
                f"box of phase errors: half-widths [{format_numbers(self.box_half_width_deg)}] "
                f"deg (scale {format_number(self.box_scale)}); largest RE at its corners "
                f"{format_number(self.box_corner_max_re)}, over its grid "
                f"{format_number(self.box_grid_max_re)}"]


def tolerance_band(design: Any, re_limit: float) -> ToleranceBand:
    """Tolerance band of a design for an RE limit.

    Parameters
    ----------
    design : (ColumnGeometry, sequence of float) or result
        A column and its yoke phasing (deg, fitter's convention), or any result
        with ``geometry`` and ``yoke_phase_deg`` (:func:`sso.optimise`,
        :func:`optimise_robust`). For :func:`optimise_positions` pass
        ``(result.geometries[name], result.yoke_phase_deg)`` per position.
    re_limit : float
        Largest acceptable RE (dimensionless), at or above the design's RE.

    Returns
    -------
    ToleranceBand

    Raises
    ------
    TypeError
        If ``design`` is neither.
    ValueError
        If ``re_limit`` is not a positive number, lies below the least RE any
        phasing of the column reaches, or below the design's RE.
    """
    geometry, yoke = column_design(design)
    limit = finite_in_range("re_limit", re_limit, 0.0, np.inf, lower_open=True, upper_open=True)
    beta = np.asarray(geometry.beta_deg)
    gamma = np.asarray(geometry.plane_angle_deg)
    delta = np.asarray(yoke)

    def re_at(beta_deg: np.ndarray, delta_deg: np.ndarray) -> np.ndarray:
        return residual_error(np.radians(beta_deg),
                              np.radians(90.0 + delta_deg - gamma))

    nominal = float(re_at(beta, delta))
    least = can_cancel(geometry.beta_deg).minimum_residual_error
    if limit < least:
        raise ValueError(f"re_limit = {limit:g} is below the least RE any yoke phasing of this "
                         f"column reaches ({least:.6g}): no design meets it")
    if limit < nominal:
        raise ValueError(f"re_limit = {limit:g} is below the design's RE ({nominal:.6g}): "
                         "the design itself is outside the band")

    phases = [_interval(f"yoke_phase_deg[{k}]", float(delta[k]),
                        _one_moving(delta, k, lambda rows: re_at(beta, rows)), limit,
                        float(delta[k]) - HALF_TURN_DEG, float(delta[k]) + HALF_TURN_DEG)
              for k in range(len(delta))]
    angles = [_interval(f"beta_deg[{k}]", float(beta[k]),
                        _one_moving(beta, k, lambda rows: re_at(rows, delta)), limit, 0.0,
                        BETA_SCAN_TOP_DEG)
              for k in range(len(beta))]
    widths = np.array([min(interval.nominal_deg - interval.lower_deg,
                           interval.upper_deg - interval.nominal_deg) for interval in phases])
    corners = np.array(list(itertools.product((-1.0, 1.0), repeat=len(delta))))

    def corner_max(scale: np.ndarray) -> np.ndarray:
        rows = delta + scale[:, None, None] * widths * corners  # (scales, corners, shafts)
        worst: np.ndarray = re_at(beta, rows).max(axis=-1)
        return worst

    crossing = _edge(corner_max, limit, 0.0, 1.0, BOX_SCAN_POINTS)
    box_scale = 1.0 if crossing is None else crossing
    half_widths = box_scale * widths
    per_axis = max(3, min(BOX_GRID_POINTS, int(BOX_GRID_SIZE ** (1.0 / len(delta)))))
    axes = [np.linspace(-width, width, per_axis) for width in half_widths]
    grid = delta + np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, len(delta))
    return ToleranceBand(
        re_limit=limit, nominal_re=nominal, yoke_phase_deg=tuple(float(v) for v in delta),
        yoke_phase=tuple(phases), operating_angle=tuple(angles),
        box_half_width_deg=tuple(float(width) for width in half_widths),
        box_scale=box_scale, box_corner_max_re=float(corner_max(np.array([box_scale]))[0]),
        box_grid_max_re=float(re_at(beta, grid).max()), geometry=geometry)


def re_against_phase_error(
    design: Any, span_deg: float = DEFAULT_PHASE_ERROR_SPAN_DEG,
    points: int = DEFAULT_PHASE_ERROR_POINTS,
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """RE against each yoke phasing's error with the others at nominal (a report's figure).

    Parameters
    ----------
    design : (ColumnGeometry, sequence of float) or result
        As :func:`tolerance_band`.
    span_deg : float
        Errors from ``-span_deg`` to ``+span_deg``, deg, in ``(0, 90]``.
    points : int
        Errors per curve, in ``[3, 100000]``.

    Returns
    -------
    dict of str to (numpy.ndarray, numpy.ndarray)
        ``"yoke_phase_deg[k]"`` to (errors in deg, RE at each).

    Raises
    ------
    TypeError, ValueError
        For a bad design or option, naming the field.
    """
    geometry, yoke = column_design(design)
    span = finite_in_range("span_deg", span_deg, 0.0, 90.0, "deg", lower_open=True)
    count = validate_count("points", points, 3, 100_000)
    beta_rad = np.radians(geometry.beta_deg)
    gamma = np.asarray(geometry.plane_angle_deg)
    delta = np.asarray(yoke)
    errors = np.linspace(-span, span, count)
    curves = {}
    for k in range(len(delta)):
        along = _one_moving(delta, k, lambda rows: residual_error(
            beta_rad, np.radians(90.0 + rows - gamma)))
        curves[f"yoke_phase_deg[{k}]"] = (errors, along(delta[k] + errors))
    return curves


def _one_moving(nominal: np.ndarray, index: int,
                evaluate: Callable[[np.ndarray], np.ndarray]) -> Callable[[np.ndarray], np.ndarray]:
    """``values -> evaluate(rows)``: rows of ``nominal`` with entry ``index`` set to each value."""
    def along(values: np.ndarray) -> np.ndarray:
        rows = np.tile(nominal, (len(values), 1))
        rows[:, index] = values
        return evaluate(rows)

    return along


def _interval(name: str, nominal: float, along: Callable[[np.ndarray], np.ndarray],
              limit: float, bottom: float, top: float) -> Interval:
    """The interval around ``nominal`` where ``along`` stays at or below ``limit``."""
    upper = _edge(along, limit, nominal, top)
    lower = _edge(along, limit, nominal, bottom)
    upper_deg = top if upper is None else upper
    lower_deg = bottom if lower is None else lower
    if top - bottom >= 2.0 * HALF_TURN_DEG - 1e-9 and (upper is None or lower is None):
        # A phasing under the limit over a whole period: the band is the circle.
        upper_deg, lower_deg, upper, lower = nominal + 90.0, nominal - 90.0, None, None
    values = along(np.array([lower_deg, upper_deg]))
    return Interval(name, nominal, lower_deg, upper_deg, lower is not None, upper is not None,
                    float(values[0]), float(values[1]))


def _edge(along: Callable[[np.ndarray], np.ndarray], limit: float, start: float,
          end: float, count: int | None = None) -> float | None:
    """First point from ``start`` towards ``end`` where ``along`` reaches ``limit``.

    Scanned on ``count`` points (default: steps of ``SCAN_STEP_DEG``), refined by
    :func:`_root`; None when the scan never exceeds the limit.
    """
    if count is None:
        count = max(2, int(np.ceil(abs(end - start) / SCAN_STEP_DEG)) + 1)
    points = np.linspace(start, end, count)
    above = np.flatnonzero(along(points) > limit)
    if above.size == 0:
        return None
    first = int(above[0])
    if first == 0:
        return start
    return _root(along, limit, float(points[first - 1]), float(points[first]))


def _root(along: Callable[[np.ndarray], np.ndarray], limit: float, inside: float,
          outside: float) -> float:
    from scipy.optimize import brentq

    def excess(value: float) -> float:
        return float(along(np.array([value]))[0]) / limit - 1.0

    root: float = brentq(excess, inside, outside, xtol=EDGE_XTOL_DEG)
    return root
