"""The yoke phasing that keeps a driveline's excitations furthest under their limits.

The criterion is the driveline's, not the residual error: over every named position,
the largest ratio of an excitation (inertia drive, inertia coast, torsional) to its
limit is made as small as it can be (the largest margin); among phasings that reach
it, the sum of the squared ratios is least (so a figure that no phasing changes, such
as a one-piece shaft's inertia excitation, leaves the others as low as they go). The
search scans the yoke phasings on a grid (the column's ``delta_k``, period 180 deg),
then refines the best points with Nelder-Mead (SciPy) on the exact figures, first on
the largest ratio and then on the sum of squares with the largest ratio held.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from scipy.optimize import minimize

from sso._column.geometry import ColumnGeometry, wrap_half_turn
from sso._display import Part, TextTable, format_number, format_numbers
from sso._driveline.excitation import excitations
from sso._driveline.motion import PEAK_SAMPLES
from sso._record import register_record

if TYPE_CHECKING:
    from sso._driveline.model import Driveline

FIGURES = ("inertia drive", "inertia coast", "torsional")
CRITERION = ("largest margin under the limits over every position (least largest ratio of "
             "an excitation to its limit), then least sum of squared ratios; a phasing of 0 "
             "or 90 deg per shaft as good is preferred")
REFINED_STARTS = 3
GRID_SAMPLES = 64
"""Samples of a half revolution per peak while scanning the grid of phasings."""
SEARCH_SAMPLES = 512
"""Samples of a half revolution per peak while refining (the peak's sampling error is then
below 1e-4 of it; the advice's figures are computed exactly afterwards)."""
HELD_RATIO = 1e-9
TIE = 1e-9
"""Ratios (of an excitation to its limit) this close are equal."""


@register_record
@dataclass(frozen=True)
class PhasingRow:
    """One excitation at one position with the given and the recommended phasing, rad/s^2."""

    position: str
    figure: str
    given_rad_s2: float
    recommended_rad_s2: float
    limit_rad_s2: float


@register_record
@dataclass(frozen=True)
class PhasingAdvice:
    """The recommended yoke phasing and what it changes.

    Attributes
    ----------
    yoke_phase_deg : tuple of float
        Recommended phasing of each propshaft, deg in ``[-90, 90)`` (0 in phase).
    given_yoke_phase_deg : tuple of float
        The driveline's phasing as given, deg.
    worst_ratio_given, worst_ratio_recommended : float
        Largest excitation over its limit, over every position and figure.
    rows : tuple of PhasingRow
    criterion : str
    """

    yoke_phase_deg: tuple[float, ...]
    given_yoke_phase_deg: tuple[float, ...]
    worst_ratio_given: float
    worst_ratio_recommended: float
    rows: tuple[PhasingRow, ...]
    criterion: str

    @property
    def trades(self) -> tuple[PhasingRow, ...]:
        """The rows where the recommended phasing is worse than the given one."""
        return tuple(row for row in self.rows
                     if row.recommended_rad_s2 > row.given_rad_s2 + TIE * row.limit_rad_s2)

    def summary_parts(self) -> list[Part]:
        """The advice for a summary."""
        parts: list[Part] = [
            f"Recommended yoke phasing (deg): [{format_numbers(self.yoke_phase_deg)}] "
            f"(given [{format_numbers(self.given_yoke_phase_deg)}]); largest excitation over "
            f"its limit {format_number(self.worst_ratio_given)} -> "
            f"{format_number(self.worst_ratio_recommended)} ({self.criterion})",
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


def recommend_phasing(driveline: Driveline) -> PhasingAdvice:
    """The phasing of :data:`CRITERION` for ``driveline`` (module notes).

    Raises
    ------
    ValueError
        If the driveline has a single joint (no propshaft to phase).
    """
    shafts = driveline.joint_count - 1
    if shafts < 1:
        raise ValueError("a driveline of one joint has no propshaft to phase")
    named = driveline.named_geometries()
    geometries = list(named.values())
    speed = driveline.max_shaft_speed_rpm
    limits = np.array([driveline.inertia_limit_rad_s2, driveline.inertia_limit_rad_s2,
                       driveline.torsional_limit_rad_s2])

    def ratios(phasing: np.ndarray, samples: int = SEARCH_SAMPLES) -> np.ndarray:
        values = np.array(_figures(geometries, tuple(float(v) for v in phasing), speed,
                                   samples, refine=False))
        ratio: np.ndarray = (values / limits).ravel()
        return ratio

    step = 10.0 if shafts <= 2 else 20.0
    grid = np.arange(-90.0, 90.0, step)
    scored = sorted((float(np.max(ratios(np.array(point), GRID_SAMPLES))), point)
                    for point in itertools.product(grid, repeat=shafts))

    def refined(start: tuple[float, ...]) -> tuple[tuple[float, float], np.ndarray]:
        """The sort key (largest ratio, sum of squares) and the phasing refined from start."""
        first = minimize(lambda x: float(np.max(ratios(x))), np.array(start),
                         method="Nelder-Mead", options={"xatol": 1e-7, "fatol": 1e-12,
                                                        "initial_simplex": _simplex(start, step)})
        held = float(first.fun) * (1.0 + HELD_RATIO)

        def penalised(x: np.ndarray) -> float:
            ratio = ratios(x)
            excess = max(float(np.max(ratio)) - held, 0.0)
            return float(np.sum(ratio**2)) + 1e6 * excess

        second = minimize(penalised, first.x, method="Nelder-Mead",
                          options={"xatol": 1e-9, "fatol": 1e-15,
                                   "initial_simplex": _simplex(tuple(first.x), step / 2)})
        final = ratios(second.x)
        return (round(float(np.max(final)), 12), float(np.sum(final**2))), second.x

    best_key, best_point = min((refined(start) for _, start in scored[:REFINED_STARTS]),
                               key=lambda candidate: candidate[0])
    # A textbook phasing (each shaft in phase or at 90 deg) as good as the optimum is said
    # as such, not as its round-off neighbour.
    for textbook in itertools.product((0.0, 90.0), repeat=shafts):
        final = ratios(np.array(textbook))
        if (float(np.max(final)) <= best_key[0] + TIE
                and float(np.sum(final**2)) <= best_key[1] + TIE):
            best_point = np.array(textbook)
            break
    recommended = tuple(float(v) for v in wrap_half_turn(best_point))
    given = driveline.phasing_deg
    given_values = _figures(geometries, given, speed)
    recommended_values = _figures(geometries, recommended, speed)
    rows = tuple(PhasingRow(position=name, figure=figure, given_rad_s2=before[index],
                            recommended_rad_s2=after[index], limit_rad_s2=float(limits[index]))
                 for name, before, after in zip(named, given_values, recommended_values,
                                                strict=True)
                 for index, figure in enumerate(FIGURES))
    return PhasingAdvice(
        yoke_phase_deg=recommended, given_yoke_phase_deg=given,
        worst_ratio_given=max(row.given_rad_s2 / row.limit_rad_s2 for row in rows),
        worst_ratio_recommended=max(row.recommended_rad_s2 / row.limit_rad_s2 for row in rows),
        rows=rows, criterion=CRITERION)


def _simplex(start: Sequence[float], size: float) -> np.ndarray:
    centre = np.asarray(start, dtype=float)
    simplex: np.ndarray = np.vstack([centre, centre + size * np.eye(len(centre))])
    return simplex
