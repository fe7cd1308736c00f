"""The fitter's table of a column report: one assembly, the one recommended.

Every row of the table and its text describe the recommended assembly: its teeth,
tooth offsets and yoke phasing on the splines, and the continuous optimum it came
from, with why that optimum: the best phasing for RE at the hardpoints (the teeth
nearest one of its equivalent optima, named), or the optimum of the case's own
objective (positions, tolerances or steering feel), whose teeth the fitter gets. The
nominal optimum that is not recommended is listed apart, for comparison.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from sso._column.geometry import wrap_half_turn
from sso._reports.summary import Block, Paragraph, Table, number
from sso._run.column import ColumnRun

SAME_PHASING_DEG = 1e-6
"""Two continuous optima closer than this in every delta (deg) are one (the solvers' own
copies of an optimum differ in the last digits)."""
WHY = {
    "positions": "the case's objective: one phasing for every position of "
                 "[hardpoints.positions] (the column is used at each)",
    "robust": "the case's objective: the phasing production's errors ([tolerances]) hurt "
              "least",
    "on_centre": "the case's objective: the steering feel of [feel]",
}


@dataclass(frozen=True)
class Origin:
    """The continuous optimum the recommended assembly came from."""

    label: str
    yoke_phase_deg: tuple[float, ...]
    why: str


def recommended_origin(run: ColumnRun) -> Origin | None:
    """Where the recommended assembly came from, or None for an analysis."""
    phasing, splines = run.phasing, run.splines
    if phasing is None:
        return None
    if splines is not None and splines.objective != "RE" and run.robust is not None:
        for design in run.robust.designs:
            if design.role.endswith("_splines") and design.splines == splines:
                role = design.role.removesuffix("_splines")
                (base,) = (item for item in run.robust.designs if item.role == role)
                return Origin(base.label, base.yoke_phase_deg,
                              f"{WHY[role]}; the teeth are the best whole-teeth assembly for "
                              f"that objective ({splines.objective}), searched over the "
                              "assemblies, not this phasing rounded")
    optima = phasing.equivalent_yoke_phase_deg or (phasing.yoke_phase_deg,)
    if splines is None:
        return Origin("best yoke phasing (continuous)", phasing.yoke_phase_deg,
                      "the least RE at the hardpoints (the case gives no [splines])")
    nearest = min(optima, key=lambda optimum: _distance(optimum, splines.yoke_phase_deg))
    if _distance(nearest, phasing.yoke_phase_deg) <= SAME_PHASING_DEG:
        nearest = phasing.yoke_phase_deg
    label = ("best yoke phasing (continuous)" if nearest == phasing.yoke_phase_deg
             else "an equivalent best yoke phasing (continuous; the same least RE)")
    return Origin(label, tuple(nearest),
                  "the least RE at the hardpoints; the teeth are the best whole-teeth assembly "
                  "for RE, and of the continuous optima this is the one they lie nearest")


def _distance(first: Sequence[float], second: Sequence[float]) -> float:
    return float(np.max(np.abs(wrap_half_turn(np.subtract(first, second)))))


def fitter_blocks(run: ColumnRun) -> list[Block]:
    """The recommended assembly in words, its table and the nominal optimum apart."""
    origin = recommended_origin(run)
    phasing, splines = run.phasing, run.splines
    as_built = run.assemblies[0]  # the assembly as built comes first
    header = ["intermediate shaft", "gamma (deg)", "delta as built (deg)"]
    if origin is None:
        built = tuple((f"{shaft + 1} (joint {shaft + 1} to {shaft + 2})", number(gamma, ".3f"),
                       number(as_built.yoke_phase_deg[shaft], ".3f"))
                      for shaft, gamma in enumerate(run.geometry.plane_angle_deg))
        return [Paragraph("Analysis of the assembly as built: nothing is recommended."),
                Table(tuple(header), built)]
    recommended = run.assembly(run.recommended)
    header.append(f"its optimum: {origin.label}, delta (deg)")
    if splines is not None:
        header += ["teeth", "tooth offset", "recommended delta on the splines (deg)",
                   "direction"]
    rows: list[tuple[str, ...]] = []
    for shaft, gamma in enumerate(run.geometry.plane_angle_deg):
        row = [f"{shaft + 1} (joint {shaft + 1} to {shaft + 2})", number(gamma, ".3f"),
               number(as_built.yoke_phase_deg[shaft], ".3f"),
               number(origin.yoke_phase_deg[shaft], ".3f")]
        if splines is not None:
            offset = splines.tooth_offset[shaft]
            direction = ("in phase" if offset == 0 else
                         "clockwise" if offset > 0 else "anticlockwise")
            row += [str(splines.teeth[shaft]), f"{offset:+d}",
                    number(splines.yoke_phase_deg[shaft], ".3f"),
                    f"{direction}, looking from joint {shaft + 1} to joint {shaft + 2}"
                    if offset else direction]
        rows.append(tuple(row))
    blocks: list[Block] = [
        Paragraph(f"Recommended assembly: {recommended.label}, yoke phasing "
                  f"{_angles(recommended.yoke_phase_deg)} deg. Its optimum: the {origin.label}, "
                  f"delta {_angles(origin.yoke_phase_deg)} deg, chosen for {origin.why}. Every "
                  "row below describes this assembly."),
        Table(tuple(header), tuple(rows))]
    assert phasing is not None  # an origin comes from an optimisation
    others = [optimum for optimum in phasing.equivalent_yoke_phase_deg
              if _distance(optimum, origin.yoke_phase_deg) > SAME_PHASING_DEG]
    if all(_distance(optimum, origin.yoke_phase_deg) > SAME_PHASING_DEG
           for optimum in (phasing.yoke_phase_deg, *phasing.equivalent_yoke_phase_deg)):
        optima = "; ".join(_angles(optimum) for optimum in phasing.equivalent_yoke_phase_deg)
        blocks.append(Paragraph(
            f"Not recommended, for comparison: the nominal optimum (least RE at the "
            f"hardpoints), best delta {_angles(phasing.yoke_phase_deg)} deg; every equivalent "
            f"optimum, mod 180: {optima} deg."))
    elif others:
        blocks.append(Paragraph(
            f"The other equivalent optima (the same least RE, mod 180; not recommended): "
            f"{'; '.join(_angles(optimum) for optimum in others)} deg."))
    return blocks


def _angles(values: Sequence[float]) -> str:
    return ", ".join(number(value, ".3f") for value in values)
