"""The yoke phasing (and, within a box, the layout) a driveline engineer would choose.

The criterion is the driveline's, not the residual error, and it is lexicographic
(:data:`CRITERION`, the one statement of it):

1. the largest margin under the excitation limits over every named position: the
   least largest ratio ``r*`` of an excitation (inertia drive, inertia coast,
   torsional) to its limit;
2. among the phasings and layouts whose largest ratio is within
   :data:`MARGIN_TOLERANCE` of ``r*``, the least torsional excitation at the design
   position (the joints cancelling at ride height: a planar shaft's pinion set for
   equal angles, its yokes in phase);
3. then the least sum of the squared ratios over every position (so a figure that
   nothing changes leaves the others as low as they go); of the points within
   :data:`AS_GOOD` of the optimum in tiers 2 and 3, a phasing of 0 or 90 deg per shaft
   is said, and the layout nearest the one given is kept.

The search scans the yoke phasings (the column's ``delta_k``, period 180 deg) and the
layout box (:class:`sso._driveline.layout_box.LayoutBox`) on a grid, then refines the
best points with SLSQP (SciPy) on the sampled figures, one stage per tier with the
earlier tiers as constraints: the first in epigraph form (least ``t`` with every ratio
at most ``t``), the second on the squared ratio (smooth where the joints cancel).

The named positions are the column's geometry (one :class:`ColumnGeometry` each, sharing
the yoke phasing as the column's positions do), but not the column's scenario NLP
(:mod:`sso._column.scenarios`): that one minimises the closed-form RE with each
scenario's joint angles and planes fixed, while here the figures are peaks over a
revolution with a limit each, and the layout variables move the angles and planes.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from scipy.optimize import minimize

from sso._column.geometry import ColumnGeometry, wrap_half_turn
from sso._display import Part, TextTable, format_number, format_numbers
from sso._driveline.excitation import excitations
from sso._driveline.layout_box import LayoutBox, laid_out_geometries, pinion_slope_of
from sso._driveline.motion import PEAK_SAMPLES
from sso._record import register_record

if TYPE_CHECKING:
    from sso._driveline.model import Driveline

FIGURES = ("inertia drive", "inertia coast", "torsional")
MARGIN_TOLERANCE = 0.02
"""How far (in ratio to a limit, here 2 % of it) above the largest margin's ratio a
phasing or layout may go to cancel better at the design position."""
REFINED_STARTS = 3
GRID_SAMPLES = 64
"""Samples of a half revolution per peak while scanning the grid."""
SEARCH_SAMPLES = 512
"""Samples of a half revolution per peak while refining (the peak's sampling error is then
below 1e-4 of it; the advice's figures are computed exactly afterwards)."""
LAYOUT_GRID = 9
"""Grid points across each layout variable's box, at most."""
GRID_BUDGET = 2000
"""Grid points scanned at most where several layout variables multiply the phasings'
(each layout variable then gets fewer points, two at least: its box's ends)."""
STAGE_FTOL = 1e-12
STAGE_ITERATIONS = 60
"""SLSQP's tolerance on each tier's objective and its iteration limit (where a tier ends
at the limit, on a kink of the sampled peaks, it has long stopped moving: the car
one-piece case gives the same pinion slope to 1e-11 deg with 200)."""
SAME_POINT = 0.5
"""First-tier optima this close (deg of phasing, mm or deg of layout) are refined once."""
HELD = 1e-9
"""What a later stage may give up of an earlier stage's ratio."""
TIE = 1e-9
"""Ratios (of an excitation to its limit) this close are equal."""
AS_GOOD = 1e-3
"""A point this close (in ratio to a limit, 0.1 % of it) to the optimum in the second
and third tiers is as good: the rest is below what the limits, which are rules of thumb,
can tell apart. Of points as good, a textbook phasing (0 or 90 deg per shaft) is said,
and the layout nearest the one given is kept."""
CRITERION = ("first the largest margin under the excitation limits over every position "
             "(least largest ratio r* of an excitation to its limit); then, within "
             f"{MARGIN_TOLERANCE:g} of r*, the least torsional excitation at the design "
             "position (cancellation: equal angles, yokes in phase for a planar shaft); then "
             "the least sum of squared ratios; of points within "
             f"{AS_GOOD:g} of that, a phasing of 0 or 90 deg per shaft and the layout "
             "nearest the given one are preferred")


@register_record
@dataclass(frozen=True)
class PhasingRow:
    """One excitation at one position with the given and the recommended layout, rad/s^2."""

    position: str
    figure: str
    given_rad_s2: float
    recommended_rad_s2: float
    limit_rad_s2: float


@register_record
@dataclass(frozen=True)
class PhasingAdvice:
    """The recommended yoke phasing (and layout, where a box was given) and what it changes.

    Attributes
    ----------
    yoke_phase_deg : tuple of float
        Recommended phasing of each propshaft, deg in ``[-90, 90)`` (0 in phase).
    given_yoke_phase_deg : tuple of float
        The driveline's phasing as given, deg.
    worst_ratio_given, worst_ratio_recommended : float
        Largest excitation over its limit, over every position and figure.
    least_worst_ratio : float
        The least largest ratio any phasing (and layout in the box) reaches: the first
        tier's ``r*`` (the search's sampled figures); the recommendation is within
        :data:`MARGIN_TOLERANCE` of it.
    rows : tuple of PhasingRow
    criterion : str
    box : LayoutBox or None
        The layout box searched (None: the phasing alone).
    layout_values, given_layout_values : tuple of float
        The layout variables recommended and as given, in :attr:`LayoutBox.bounds`
        order: the design position's pinion slope, deg, then each centre bearing's
        height change, mm (0 as given).
    """

    yoke_phase_deg: tuple[float, ...]
    given_yoke_phase_deg: tuple[float, ...]
    worst_ratio_given: float
    worst_ratio_recommended: float
    rows: tuple[PhasingRow, ...]
    criterion: str
    least_worst_ratio: float
    box: LayoutBox | None = None
    layout_values: tuple[float, ...] = ()
    given_layout_values: tuple[float, ...] = ()

    @property
    def trades(self) -> tuple[PhasingRow, ...]:
        """The rows where the recommendation is worse than the layout as given."""
        return tuple(row for row in self.rows
                     if row.recommended_rad_s2 > row.given_rad_s2 + TIE * row.limit_rad_s2)

    @property
    def pinion_slope_deg(self) -> float | None:
        """The recommended pinion slope, deg (None when the box leaves it as given)."""
        if self.box is None or self.box.pinion_slope_deg is None:
            return None
        return self.layout_values[0]

    @property
    def centre_bearing_height_mm(self) -> tuple[float, ...]:
        """The recommended height change of each centre bearing in the box, mm."""
        if self.box is None:
            return ()
        return self.layout_values[len(self.layout_values)
                                  - len(self.box.centre_bearing_height_mm):]

    def layout_words(self) -> str:
        """The recommended layout in words (empty without a box)."""
        if self.box is None:
            return ""
        words = []
        pinion = self.pinion_slope_deg
        if pinion is not None and self.box.pinion_slope_deg is not None:
            low, high = self.box.pinion_slope_deg
            words.append(f"pinion slope {format_number(pinion)} deg (given "
                         f"{format_number(self.given_layout_values[0])}, box "
                         f"[{format_number(low)}, {format_number(high)}])")
        for index, (height, (low, high)) in enumerate(zip(
                self.centre_bearing_height_mm, self.box.centre_bearing_height_mm,
                strict=True), start=1):
            words.append(f"centre bearing {index} raised {format_number(height)} mm (box "
                         f"[{format_number(low)}, {format_number(high)}])")
        return "; ".join(words)

    def summary_parts(self) -> list[Part]:
        """The advice for a summary."""
        layout = self.layout_words()
        parts: list[Part] = [
            f"Recommended yoke phasing (deg): [{format_numbers(self.yoke_phase_deg)}] "
            f"(given [{format_numbers(self.given_yoke_phase_deg)}])"
            + (f"; layout: {layout}" if layout else "")
            + f"; largest excitation over its limit {format_number(self.worst_ratio_given)} "
            f"-> {format_number(self.worst_ratio_recommended)} (least reachable "
            f"{format_number(self.least_worst_ratio)}; {self.criterion})",
            TextTable(("position", "excitation", "given (rad/s^2)", "recommended (rad/s^2)",
                       "limit (rad/s^2)"),
                      tuple((row.position, row.figure, format_number(row.given_rad_s2),
                             format_number(row.recommended_rad_s2),
                             format_number(row.limit_rad_s2)) for row in self.rows))]
        trades = self.trades
        parts.append("Trade: " + ("; ".join(
            f"{row.position} {row.figure} rises {format_number(row.given_rad_s2)} -> "
            f"{format_number(row.recommended_rad_s2)} rad/s^2" for row in trades)
            if trades else "no excitation gets worse"))
        return parts


def _figures(geometries: Sequence[ColumnGeometry], phasing: tuple[float, ...],
             speed_rpm: float, samples: int = PEAK_SAMPLES,
             refine: bool = True) -> list[tuple[float, float, float]]:
    values = []
    for geometry in geometries:
        found = excitations(geometry, phasing, speed_rpm, samples, refine)
        values.append((found.inertia_drive_rad_s2, found.inertia_coast_rad_s2,
                       found.torsional_rad_s2))
    return values


class _Search:
    """The variables (phasings, then the layout) and the ratios they give."""

    def __init__(self, driveline: Driveline, box: LayoutBox | None) -> None:
        self.driveline = driveline
        self.box = box
        self.named = list(driveline.named_geometries().values())
        self._last: tuple[tuple[float, ...], list[ColumnGeometry]] | None = None
        self._last_ratios: tuple[tuple[float, ...], np.ndarray] | None = None

    @property
    def shafts(self) -> int:
        return self.driveline.joint_count - 1

    @property
    def bounds(self) -> np.ndarray:
        layout = () if self.box is None else self.box.bounds
        return np.array([(-np.inf, np.inf)] * self.shafts + list(layout), dtype=float)

    @property
    def limits(self) -> np.ndarray:
        inertia = self.driveline.inertia_limit_rad_s2
        return np.array([inertia, inertia, self.driveline.torsional_limit_rad_s2])

    def geometries(self, x: np.ndarray) -> list[ColumnGeometry]:
        """Each position's geometry at the variables ``x`` (design first)."""
        named = self.named
        if self.box is None:
            return named
        layout = tuple(float(v) for v in np.clip(x[self.shafts:], self.bounds[self.shafts:, 0],
                                                 self.bounds[self.shafts:, 1]))
        if self._last is None or self._last[0] != layout:
            # The grid scans the phasings at one layout after another: built once each.
            self._last = (layout, laid_out_geometries(
                [geometry.points_mm for geometry in named], self.box, layout))
        return self._last[1]

    def ratios(self, x: np.ndarray, samples: int = SEARCH_SAMPLES) -> np.ndarray:
        """Excitation over limit, shape (positions, 3); infinite where no driveline is made."""
        asked = (samples, *(float(v) for v in x))
        if self._last_ratios is not None and self._last_ratios[0] == asked:
            return self._last_ratios[1]  # the objective and the constraints at one point
        ratio = self._ratios(x, samples)
        self._last_ratios = (asked, ratio)
        return ratio

    def _ratios(self, x: np.ndarray, samples: int) -> np.ndarray:
        try:
            geometries = self.geometries(x)
        except ValueError:
            return np.full((len(self.driveline.positions) + 1, len(FIGURES)), np.inf)
        values = np.array(_figures(geometries, tuple(float(v) for v in x[:self.shafts]),
                                   self.driveline.max_shaft_speed_rpm, samples, refine=False))
        ratio: np.ndarray = values / self.limits
        return ratio

    def given(self) -> np.ndarray:
        """The variables of the driveline as given."""
        layout: tuple[float, ...] = ()
        if self.box is not None:
            pinion = (() if self.box.pinion_slope_deg is None
                      else (pinion_slope_of(self.driveline.points_mm),))
            layout = (*pinion, *(0.0,) * len(self.box.centre_bearing_height_mm))
        return np.array((*self.driveline.phasing_deg, *layout), dtype=float)


def recommend_phasing(driveline: Driveline, box: LayoutBox | None = None) -> PhasingAdvice:
    """The phasing (and layout within ``box``) of :data:`CRITERION` (module notes).

    Parameters
    ----------
    driveline : sso.Driveline
    box : LayoutBox, optional
        The pinion slope and centre-bearing heights to choose as well.

    Raises
    ------
    ValueError
        If the driveline has a single joint (no propshaft to phase), or the box names
        more centre bearings than it has.
    """
    if driveline.joint_count < 2:
        raise ValueError("a driveline of one joint has no propshaft to phase or lay out")
    if box is not None:
        box.check_fits(driveline.joint_count)
    search = _Search(driveline, box)
    shafts, bounds = search.shafts, search.bounds
    step = 10.0 if shafts <= 2 else 20.0
    phasings = list(itertools.product(np.arange(-90.0, 90.0, step), repeat=shafts))
    layout_count = len(bounds) - shafts
    across = LAYOUT_GRID if layout_count == 0 else max(2, min(LAYOUT_GRID, int(
        (GRID_BUDGET / len(phasings)) ** (1.0 / layout_count))))
    layouts = itertools.product(*(np.unique(np.linspace(low, high, across))
                                  for low, high in bounds[shafts:]))
    points = [(*phasing, *layout) for layout in layouts for phasing in phasings]
    scored = sorted((float(np.max(search.ratios(np.array(point), GRID_SAMPLES))), point)
                    for point in points)
    # The best grid points, and the best phasing at each of the best layouts (so that a
    # layout where no phasing matters, such as a joint run straight, does not take every
    # start).
    best_layouts: dict[tuple[float, ...], tuple[float, ...]] = {}
    for _, grid_point in scored:
        best_layouts.setdefault(grid_point[shafts:], grid_point)
    given_layout = search.given()[shafts:]
    at_given = min((float(np.max(search.ratios(np.array(point), GRID_SAMPLES))), point)
                   for point in ((*phasing, *given_layout) for phasing in phasings))[1]
    chosen = [at_given, *(grid_point for _, grid_point in scored[:REFINED_STARTS]
                          if grid_point != at_given)]
    chosen += [grid_point for grid_point in list(best_layouts.values())[:REFINED_STARTS]
               if grid_point not in chosen]
    starts = [np.array(grid_point) for grid_point in chosen]
    limits_box = [(None, None)] * shafts + [(float(low), float(high))
                                            for low, high in bounds[shafts:]]

    def solve(objective: Callable[[np.ndarray], float],
              constraint: Callable[[np.ndarray], np.ndarray], start: np.ndarray,
              box: Sequence[tuple[float | None, float | None]]) -> np.ndarray:
        found = minimize(objective, start, method="SLSQP", bounds=box,
                         constraints=[{"type": "ineq", "fun": constraint}],
                         options={"ftol": STAGE_FTOL, "maxiter": STAGE_ITERATIONS})
        point: np.ndarray = found.x
        return point

    def worst(x: np.ndarray) -> float:
        return float(np.max(search.ratios(x)))

    # Tier 1 in epigraph form: least t with every ratio at most t.
    first = [solve(lambda z: float(z[-1]),
                   lambda z: z[-1] - search.ratios(z[:-1]).ravel(),
                   np.append(start, worst(start)), [*limits_box, (None, None)])[:-1]
             for start in starts]
    least = min(worst(x) for x in first)
    allowed = least + MARGIN_TOLERANCE

    def within(x: np.ndarray) -> np.ndarray:
        margin: np.ndarray = allowed - search.ratios(x).ravel()
        return margin

    def key(x: np.ndarray) -> tuple[bool, float, float]:
        ratio = search.ratios(x)
        return (float(np.max(ratio)) > allowed + HELD, round(float(ratio[0, 2]), 9),
                float(np.sum(ratio**2)))

    candidates = []
    for x in _distinct(first, shafts):
        # Tier 2: the design position's torsional ratio (squared: smooth where it cancels).
        second = solve(lambda x: float(search.ratios(x)[0, 2] ** 2), within, x, limits_box)
        held = float(search.ratios(second)[0, 2]) + HELD

        def kept(x: np.ndarray, held: float = held) -> np.ndarray:
            return np.append(within(x), held - search.ratios(x)[0, 2])

        candidates.append(solve(lambda x: float(np.sum(search.ratios(x) ** 2)), kept, second,
                                limits_box))
    best_key = min(key(x) for x in candidates)
    # Of layouts as good, the one that changes the driveline least (a pinion may cancel
    # nose up or nose down: the side it was fitted on is kept).
    best = min((x for x in candidates if _as_good(key(x), best_key)),
               key=lambda x: float(np.sum((x[shafts:] - given_layout) ** 2)))
    # A textbook phasing (each shaft in phase or at 90 deg) as good as the optimum is said
    # as such, not as its round-off neighbour.
    for textbook in itertools.product((0.0, 90.0), repeat=shafts):
        point = np.array((*textbook, *best[shafts:]))
        candidate = key(point)
        if _as_good(candidate, best_key):
            best = point
            break
    # A planar driveline's mirror phasing (every delta negated) gives the same figures:
    # of the two, the one whose first turned propshaft turns positive is said.
    wrapped = wrap_half_turn(best[:shafts])
    turned = wrapped[np.abs(wrapped) > TIE]
    mirror = np.array((*(-wrapped), *best[shafts:]))
    if turned.size and turned[0] < 0.0 and _same_key(key(mirror), best_key):
        best = mirror
    recommended = tuple(float(v) for v in wrap_half_turn(best[:shafts]))
    given = search.given()
    speed = driveline.max_shaft_speed_rpm
    given_values = _figures(search.geometries(given), driveline.phasing_deg, speed)
    recommended_values = _figures(search.geometries(best), recommended, speed)
    limits = search.limits
    rows = tuple(PhasingRow(position=name, figure=figure, given_rad_s2=before[index],
                            recommended_rad_s2=after[index], limit_rad_s2=float(limits[index]))
                 for name, before, after in zip(driveline.named_geometries(), given_values,
                                                recommended_values, strict=True)
                 for index, figure in enumerate(FIGURES))
    return PhasingAdvice(
        yoke_phase_deg=recommended, given_yoke_phase_deg=driveline.phasing_deg,
        worst_ratio_given=max(row.given_rad_s2 / row.limit_rad_s2 for row in rows),
        worst_ratio_recommended=max(row.recommended_rad_s2 / row.limit_rad_s2 for row in rows),
        rows=rows, criterion=CRITERION, least_worst_ratio=least, box=box,
        layout_values=tuple(float(v) for v in best[shafts:]),
        given_layout_values=tuple(float(v) for v in given[shafts:]))


def _distinct(points: Sequence[np.ndarray], shafts: int) -> list[np.ndarray]:
    """The points that differ (phasings modulo 180 deg) by more than :data:`SAME_POINT`."""
    kept: list[np.ndarray] = []
    for point in points:
        if all(np.max(np.abs(np.concatenate((wrap_half_turn(point[:shafts] - other[:shafts]),
                                             point[shafts:] - other[shafts:])))) > SAME_POINT
               for other in kept):
            kept.append(point)
    return kept


def _same_key(first: tuple[bool, float, float], second: tuple[bool, float, float]) -> bool:
    """Two points' criterion keys equal within :data:`TIE`."""
    return (first[0] == second[0] and abs(first[1] - second[1]) <= TIE
            and abs(first[2] - second[2]) <= TIE)


def _as_good(candidate: tuple[bool, float, float], best: tuple[bool, float, float]) -> bool:
    """A point's key within :data:`AS_GOOD` of the best key in the second and third tiers."""
    return (not candidate[0] and candidate[1] <= best[1] + AS_GOOD
            and candidate[2] <= best[2] + AS_GOOD)
