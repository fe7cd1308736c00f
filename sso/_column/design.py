"""A design to analyse: a column and its yoke phasing, given either way."""

from __future__ import annotations

from typing import Any

from sso._column.geometry import ColumnGeometry
from sso._validation import as_float_tuple


def column_design(design: Any) -> tuple[ColumnGeometry, tuple[float, ...]]:
    """``(geometry, yoke_phase_deg)`` of ``design``.

    Parameters
    ----------
    design : (ColumnGeometry, sequence of float) or result
        A column and its yoke phasing (deg, fitter's convention), or any result with
        ``geometry`` and ``yoke_phase_deg`` attributes (a phasing or robust result).

    Raises
    ------
    TypeError
        If ``design`` is neither.
    ValueError
        If the phasing is not one finite angle per intermediate shaft.
    """
    if isinstance(design, tuple) and len(design) == 2 and isinstance(design[0], ColumnGeometry):
        geometry, yoke = design
    elif isinstance(getattr(design, "geometry", None), ColumnGeometry):
        geometry, yoke = design.geometry, design.yoke_phase_deg
    else:
        raise TypeError("design must be (ColumnGeometry, yoke_phase_deg) or a result with "
                        f"geometry and yoke_phase_deg, not {type(design).__name__}")
    values = as_float_tuple("yoke_phase_deg", yoke)
    if len(values) != geometry.joint_count - 1:
        raise ValueError(f"yoke_phase_deg has {len(values)} entries; a column of "
                         f"{geometry.joint_count} joints has {geometry.joint_count - 1} "
                         "intermediate shafts")
    return geometry, values
