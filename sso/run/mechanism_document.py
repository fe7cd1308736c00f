"""The result document of a mechanism case, built by calling the public API.

Layout (``schema_version`` as :data:`sso.run.document.SCHEMA_VERSION`)::

    schema_version, kind, mode ("analyse" | "optimise" | "evaluate"), created_utc,
    case, case_file, length_unit, crank_speed_rad_s, crank_accel_rad_s2,
    linkages: {role -> {type, parameters, grashof?, swing_deg?}},
    tables: {role -> MechanismTable.to_dict()},
    extremes: {role -> [{column, unit, min, min_at_deg, max, max_at_deg}]},
    method_difference? (in-line slider-crank), design? (fourbar_design, optimised),
    success, verdict, warnings, versions

Roles are ``given`` for an analysis, ``initial`` and ``optimum`` for a design.
Everything the reports draw is recomputed from ``linkages`` and ``case`` alone,
so :mod:`sso.reports.mechanism_report` needs nothing but this document.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import asdict
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from sso.cases.mechanism import DESIGN_KIND, DESIGN_LINKS, MechanismCase, angle_grid
from sso.linkages.mechanisms import (
    FourBar,
    SliderCrank,
    slider_crank_method_difference,
)
from sso.linkages.registry import Mechanism, OnUnassembled, linkage_of
from sso.linkages.table import MechanismTable
from sso.run.document import document_header, package_versions

if TYPE_CHECKING:
    from sso.linkages.fourbar_swing import FourBarDesignResult

FINE_STEP_DEG = 0.1
"""Crank-angle step of the extremes (deg): finer than any paper's grid."""


def mechanism_document(case: MechanismCase, optimising: bool,
                       result: FourBarDesignResult | None = None) -> dict[str, Any]:
    """Analyse (or design, then analyse) a mechanism case into its result document.

    Parameters
    ----------
    case : MechanismCase
        A checked case (:mod:`sso.cases.mechanism`).
    optimising : bool
        For a ``fourbar_design`` case: solve the design problem (``sso run``) or
        only analyse the start linkage (``sso evaluate``). Analysis kinds ignore it.
    result : sso.FourBarDesignResult, optional
        The design already solved (its document is wanted, not a new solve).

    Returns
    -------
    dict
        JSON-ready; solver failures and disagreements are recorded, never raised.

    Raises
    ------
    ValueError
        If the API refuses the case's values.
    """
    start = case.mechanism()
    document: dict[str, Any] = {
        **document_header(case, "analyse"),
        "length_unit": case.length_unit,
        "crank_speed_rad_s": case.crank_speed_rad_s,
        "crank_accel_rad_s2": case.crank_accel_rad_s2,
    }
    caught_messages: list[str] = []
    linkages: dict[str, Mechanism]
    if case.kind != DESIGN_KIND:
        linkages = {"given": start}
        document.update(success=True, verdict=_analysis_verdict(case))
    elif optimising or result is not None:
        if result is None:
            from sso.linkages.fourbar_swing import design_fourbar

            if not isinstance(start, FourBar):
                raise TypeError(f"a {DESIGN_KIND} case starts from a FourBar, not {start!r}")
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                result = design_fourbar(start, **case.design_options())
            caught_messages = [str(warning.message) for warning in caught]
        linkages = {"initial": start, "optimum": result.optimum}
        document.update(mode="optimise", design=result._document_dict(), success=result.success,
                        verdict=result.verdict)
    else:
        linkages = {"initial": start}
        document.update(mode="evaluate", success=True,
                        verdict="start linkage analysed as given; no optimisation")
    document["linkages"] = {role: linkage_dict(mechanism) for role, mechanism in linkages.items()}
    document["tables"] = {role: analysis_table(mechanism, case)._document_dict()
                          for role, mechanism in linkages.items()}
    document["extremes"] = {role: extremes(mechanism, case)
                            for role, mechanism in linkages.items()}
    if isinstance(start, SliderCrank) and start.offset == 0.0:
        difference = slider_crank_method_difference(
            start.crank, start.rod, case.crank_speed_rad_s, case.crank_angles_deg())
        document["method_difference"] = difference._document_dict()
    document["warnings"] = list(dict.fromkeys([*case.warnings, *caught_messages]))
    document["versions"] = package_versions()
    return document


def fourbar_design_document(result: FourBarDesignResult) -> dict[str, Any]:
    """The result document of a four-bar design made in Python, as ``sso run`` writes it.

    Its case is built from what the result records (start linkage, link and
    transmission-angle bounds, solvers); the drive and plot settings take their
    defaults, and so do the solver settings the result does not record.
    """
    from sso.cases.schema import parse_case

    start = result.initial
    case = parse_case({
        "kind": DESIGN_KIND,
        "name": "fourbar_design",
        "description": "A four-bar design made with sso.optimise in Python.",
        "start": {**{name: getattr(start, name) for name in DESIGN_LINKS},
                  "branch": start.branch},
        "bounds": {**{name: list(result.link_bounds[name]) for name in DESIGN_LINKS},
                   "transmission_angle_deg": list(result.transmission_angle_bounds_deg)},
        "solver": {"solvers": list(result.solutions)},
    }, "<sso.optimise>")
    return mechanism_document(case, True, result)


def linkage_dict(mechanism: Mechanism) -> dict[str, Any]:
    """JSON-ready description of a linkage; :func:`mechanism_from_dict` reads it back."""
    entry: dict[str, Any] = {"type": type(mechanism).__name__, "parameters": asdict(mechanism)}
    if isinstance(mechanism, FourBar):
        entry["grashof"] = mechanism.grashof()
        entry["swing_deg"] = (mechanism.swing_angle_deg()
                              if entry["grashof"] == "crank-rocker" else None)
    return entry


def mechanism_from_dict(entry: Mapping[str, Any]) -> Mechanism:
    """The linkage described by :func:`linkage_dict` (e.g. read from ``result.json``)."""
    return linkage_of(entry["type"]).mechanism(**entry["parameters"])


def analysis_table(mechanism: Mechanism, case: MechanismCase,
                   crank_angles_deg: np.ndarray | None = None,
                   on_unassembled: OnUnassembled | None = None) -> MechanismTable:
    """The mechanism's table over the case's crank angles (or ``crank_angles_deg``).

    A four-bar's table gains ``coupler_point_x`` and ``coupler_point_y``: the path
    of the case's coupler point (``plots.coupler_point``, in coupler lengths along
    and to the left of A -> B).
    """
    angles = case.crank_angles_deg() if crank_angles_deg is None else crank_angles_deg
    table = mechanism.analyse(angles, crank_speed=case.crank_speed_rad_s,
                              crank_accel=case.crank_accel_rad_s2,
                              on_unassembled=on_unassembled or case.on_unassembled)
    if not linkage_of(mechanism).coupler_point:
        return table
    if not isinstance(mechanism, FourBar):
        raise TypeError(f"coupler points are computed for a FourBar, not {mechanism!r}")
    point = coupler_point(mechanism, table, case.values["plots.coupler_point"])
    columns = {**table.columns, "coupler_point_x": point.real, "coupler_point_y": point.imag}
    units = {**table.units, "coupler_point_x": "length", "coupler_point_y": "length"}
    return MechanismTable(name=table.name, columns=columns, units=units)


def coupler_point(fourbar: FourBar, table: MechanismTable,
                  point_in_coupler_lengths: tuple[float, float]) -> NDArray[np.complex128]:
    """Positions of a point fixed to the coupler, as complex numbers (length units).

    Parameters
    ----------
    fourbar : FourBar
    table : MechanismTable
        The four-bar's table (joint A and the coupler angle).
    point_in_coupler_lengths : (float, float)
        The point's distance along A -> B and to the left of it, in coupler lengths.
    """
    along, across = point_in_coupler_lengths
    joint_a = table["joint_a_x"] + 1j * table["joint_a_y"]
    direction: NDArray[np.complex128] = np.exp(1j * np.radians(table["coupler_angle_deg"]))
    return joint_a + fourbar.coupler * (along + 1j * across) * direction


def case_from_document(document: Mapping[str, Any]) -> MechanismCase:
    """The case stored in a result document, checked again."""
    from sso.cases.schema import parse_case

    case = parse_case(document["case"], document["case_file"])
    if not isinstance(case, MechanismCase):
        raise ValueError(f"the document's case kind {document['case'].get('kind')!r} is not "
                         "a mechanism kind")
    return case


def revolution_stop_deg(case: MechanismCase) -> float:
    """End of the curves and extremes: at least one revolution from the case's start (deg)."""
    start, stop = case.values["drive.start_deg"], case.values["drive.stop_deg"]
    return float(max(stop, start + 360.0))


def fine_crank_angles_deg(case: MechanismCase) -> np.ndarray:
    """From the case's start to :func:`revolution_stop_deg` at :data:`FINE_STEP_DEG` (deg)."""
    return angle_grid(case.values["drive.start_deg"], revolution_stop_deg(case), FINE_STEP_DEG)


def extremes(mechanism: Mechanism,
             case: MechanismCase) -> list[dict[str, Any]]:
    """Smallest and largest value of the main columns over a whole crank revolution.

    Sampled every :data:`FINE_STEP_DEG` deg from the case's start over at least one
    revolution (:func:`fine_crank_angles_deg`), so the extremes are the true ones to
    that resolution, not the grid samples the papers quote.
    """
    angles = fine_crank_angles_deg(case)
    table = analysis_table(mechanism, case, angles, on_unassembled="mark")
    rows = []
    for column in linkage_of(mechanism).extreme_columns:
        if column not in table.columns:
            continue
        values = np.asarray(table[column], dtype=float)
        if not np.isfinite(values).any():
            continue
        low, high = int(np.nanargmin(values)), int(np.nanargmax(values))
        rows.append({"column": column, "unit": table.units[column],
                     "min": float(values[low]), "min_at_deg": float(angles[low]),
                     "max": float(values[high]), "max_at_deg": float(angles[high])})
    return rows


def _analysis_verdict(case: MechanismCase) -> str:
    angles = case.crank_angles_deg()
    values = case.values
    return (f"analysed over {len(angles)} crank angles, {values['drive.start_deg']:g} to "
            f"{angles[-1]:g} deg in steps of {values['drive.step_deg']:g} deg, at "
            f"{case.crank_speed_rad_s:g} rad/s and {case.crank_accel_rad_s2:g} rad/s^2")
