"""Case files of the planar mechanisms: kinds ``fourbar``, ``slider_crank``,
``quick_return`` (analysis over crank angles) and ``fourbar_design`` (the
rocker-swing design problem of :func:`sso.optimise` of a four-bar).

Each kind registers its keys and builder with :func:`sso._cases.schema.register_case_kind`,
so the mechanism cases get the same checks as the shaft series: unknown keys with
suggestions, every value checked against its range, messages naming key, value,
range and line. The builder also checks the keys against each other: the angle
grid, and that the linkage assembles at every tabulated crank angle (or the
message names the angles where it does not).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from sso._cases.schema import (
    REQUIRED,
    Key,
    TabledCase,
    choice,
    number,
    number_list,
    register_case_kind,
    text,
)
from sso._cases.shaft_series import checked_solvers, solver_keys
from sso._limits import DEFAULT_FOURBAR_SOLVER_TOL, TRANSMISSION_BAND_DEG
from sso._linkages.registry import Linkage, Mechanism, OnUnassembled, linkage_of_kind, linkages
from sso._record import register_record
from sso._validation import per_item_bounds

# Analysis kinds come from the linkage registry: one per registered mechanism.
ANALYSIS_KINDS = tuple(linkages())
DESIGN_KIND = "fourbar_design"
MECHANISM_KINDS = (*ANALYSIS_KINDS, DESIGN_KIND)
MAX_ROWS = 10_000
MAX_PLOTTED_POSITIONS = 12
DEFAULT_PLOTTED_POSITIONS = 8
# A four-bar design case describes its start linkage as a four-bar analysis case does.
DESIGN_LINKAGE_KIND = "fourbar"
DESIGN_LINKS = ("crank", "coupler", "rocker", "ground")
POSITIVE = "(0, inf)"


def _linkage(kind: str) -> Linkage:
    return linkage_of_kind(DESIGN_LINKAGE_KIND if kind == DESIGN_KIND else kind)


def _link_names(kind: str) -> tuple[str, ...]:
    return DESIGN_LINKS if kind == DESIGN_KIND else _linkage(kind).links


def _positive_length() -> Callable[[str, Any], float]:
    return number(0.0, math.inf, "length units", lower_open=True, upper_open=True)


def length_pair(label: str, value: Any) -> tuple[float, float]:
    """Parser of one ``[lower, upper]`` pair of lengths, both > 0 (equal pins the length)."""
    if not (isinstance(value, list) and len(value) == 2):
        raise ValueError(f"{label} = {value!r} must be one [lower, upper] pair of lengths, "
                         f"each in {POSITIVE} length units")
    lower, upper = per_item_bounds(label, value, 1, 0.0, math.inf, "length units")[0]
    if lower <= 0.0:
        raise ValueError(f"{label} lower = {lower:g} is outside the allowed range "
                         f"{POSITIVE} length units")
    return (lower, upper)


def angle_pair(label: str, value: Any) -> tuple[float, float]:
    """Parser of transmission-angle limits: ``[lower, upper]`` inside (0, 180) deg."""
    if not (isinstance(value, list) and len(value) == 2):
        raise ValueError(f"{label} = {value!r} must be one [lower, upper] pair in (0, 180) deg")
    lower, upper = per_item_bounds(label, value, 1, 0.0, 180.0, "deg")[0]
    if lower <= 0.0 or upper >= 180.0:
        raise ValueError(f"{label} = [{lower:g}, {upper:g}] is outside the allowed range "
                         "(0, 180) deg")
    return (lower, upper)


def _default_plotted_angles(values: dict[str, Any], path: str) -> tuple[float, ...]:
    start, stop = values["drive.start_deg"], values["drive.stop_deg"]
    span = min(stop - start, 360.0)
    return tuple(float(start + span * index / DEFAULT_PLOTTED_POSITIONS)
                 for index in range(DEFAULT_PLOTTED_POSITIONS))


def _default_ground_bounds(values: dict[str, Any], path: str) -> tuple[float, float]:
    ground = values["start.ground"]
    return (ground, ground)


def _link_keys(table: str, kind: str) -> tuple[Key, ...]:
    linkage = _linkage(kind)
    keys = [Key(table, name, _positive_length(), REQUIRED, "length", POSITIVE)
            for name in _link_names(kind)]
    if linkage.extra == "offset":
        keys.append(Key(table, "offset", number(-math.inf, math.inf, "length units",
                                                lower_open=True, upper_open=True),
                        0.0, "length",
                        "any finite number (slider line height above the crank pivot)"))
    else:
        keys.append(Key(table, "branch", choice(("open", "crossed")), linkage.default_branch, "",
                        "'open' or 'crossed'"))
    keys.append(Key(table, "length_unit", text(20), "", "",
                    "free text, at most 20 characters (e.g. 'mm'; labels only)"))
    return tuple(keys)


DRIVE_KEYS: tuple[Key, ...] = (
    Key("drive", "crank_speed_rad_s", number(-math.inf, math.inf, "rad/s", lower_open=True,
                                             upper_open=True),
        1.0, "rad/s", "any finite number, counter-clockwise positive"),
    Key("drive", "crank_accel_rad_s2", number(-math.inf, math.inf, "rad/s^2", lower_open=True,
                                              upper_open=True),
        0.0, "rad/s^2", "any finite number, counter-clockwise positive"),
    Key("drive", "start_deg", number(-3600.0, 3600.0, "deg"), 0.0, "deg", "[-3600, 3600]"),
    Key("drive", "stop_deg", number(-3600.0, 3600.0, "deg"), 360.0, "deg",
        "[-3600, 3600], not below drive.start_deg"),
    Key("drive", "step_deg", number(0.0, 360.0, "deg", lower_open=True), 10.0, "deg",
        f"(0, 360], at most {MAX_ROWS} rows"),
    Key("drive", "on_unassembled", choice(("raise", "mark")), "raise", "",
        "'raise' (refuse the case) or 'mark' (tabulate the other angles)"),
)
PLOT_ANGLE_KEY = Key("plots", "crank_angles_deg",
                     number_list(-3600.0, 3600.0, "deg", max_length=MAX_PLOTTED_POSITIONS),
                     _default_plotted_angles, "deg",
                     f"1-{MAX_PLOTTED_POSITIONS} crank angles, each in [-3600, 3600]")
COUPLER_POINT_KEY = Key("plots", "coupler_point",
                        number_list(-10.0, 10.0, "", max_length=2), (0.5, 0.0), "coupler lengths",
                        "[along A->B, to the left of A->B], each in [-10, 10] coupler lengths")
# The shaft series' [solver] keys, with the four-bar design's defaults.
DESIGN_SOLVER_DEFAULTS = {"solver_tol": DEFAULT_FOURBAR_SOLVER_TOL}
SOLVER_KEYS: tuple[Key, ...] = solver_keys(DESIGN_SOLVER_DEFAULTS)
DESIGN_KEYS: tuple[Key, ...] = (
    *_link_keys("start", DESIGN_KIND),
    *[Key("bounds", name, length_pair, REQUIRED, "length",
          f"[lower, upper], each in {POSITIVE}, lower <= upper") for name in DESIGN_LINKS[:3]],
    Key("bounds", "ground", length_pair, _default_ground_bounds, "length",
        f"[lower, upper] in {POSITIVE}; default pins it at start.ground"),
    Key("bounds", "transmission_angle_deg", angle_pair, TRANSMISSION_BAND_DEG, "deg",
        "[lower, upper] inside (0, 180)"),
    *SOLVER_KEYS,
    *DRIVE_KEYS,
    PLOT_ANGLE_KEY,
    COUPLER_POINT_KEY,
)


def kind_keys(kind: str) -> tuple[Key, ...]:
    """The keys of one mechanism kind (without the common keys)."""
    if kind == DESIGN_KIND:
        return DESIGN_KEYS
    plot_keys = ((PLOT_ANGLE_KEY, COUPLER_POINT_KEY) if _linkage(kind).coupler_point
                 else (PLOT_ANGLE_KEY,))
    return (*_link_keys("linkage", kind), *DRIVE_KEYS, *plot_keys)


@register_record
@dataclass(frozen=True)
class MechanismCase(TabledCase):
    """A planar-mechanism case as read from a case file, after defaults.

    Attributes: those of :class:`sso._cases.schema.TabledCase`; ``kind`` is one of
    ``"fourbar"``, ``"slider_crank"``, ``"quick_return"`` and ``"fourbar_design"``.
    """

    @property
    def link_table(self) -> str:
        """TOML table holding the link lengths: ``linkage``, or ``start`` for a design."""
        return "start" if self.kind == DESIGN_KIND else "linkage"

    @property
    def length_unit(self) -> str:
        """Unit of the lengths for labels (``"length units"`` when the case names none)."""
        return str(self.values[f"{self.link_table}.length_unit"] or "length units")

    @property
    def crank_speed_rad_s(self) -> float:
        """Crank angular velocity, rad/s."""
        return float(self.values["drive.crank_speed_rad_s"])

    @property
    def crank_accel_rad_s2(self) -> float:
        """Crank angular acceleration, rad/s^2."""
        return float(self.values["drive.crank_accel_rad_s2"])

    @property
    def on_unassembled(self) -> OnUnassembled:
        """``"raise"`` or ``"mark"``, as :meth:`sso.FourBar.analyse` takes it."""
        # The schema admits only these two (DRIVE_KEYS); the comparison narrows the type.
        return "mark" if self.values["drive.on_unassembled"] == "mark" else "raise"

    def crank_angles_deg(self) -> np.ndarray:
        """The tabulated crank angles: start to stop (inclusive when on the grid) by step, deg."""
        return angle_grid(self.values["drive.start_deg"], self.values["drive.stop_deg"],
                          self.values["drive.step_deg"])

    def mechanism(self) -> Mechanism:
        """The linkage as given (the start linkage of a design case)."""
        return build_mechanism(self.kind, self.values, self.link_table)

    def design_options(self) -> dict[str, Any]:
        """Keyword arguments of :func:`sso.optimise` of a four-bar for a ``fourbar_design`` case."""
        bounds = {f"{name}_bounds": self.values[f"bounds.{name}"] for name in DESIGN_LINKS}
        solver = {name: self.values[f"solver.{name}"]
                  for name in ("solvers", "starts", "solver_tol", "max_iterations", "seed")}
        return {**bounds, "transmission_angle_bounds_deg":
                self.values["bounds.transmission_angle_deg"], **solver}

    def summary(self) -> str:
        """One line for ``sso validate``."""
        lengths = ", ".join(f"{name} {self.values[f'{self.link_table}.{name}']:g}"
                            for name in _link_names(self.kind))
        rows = len(self.crank_angles_deg())
        return f"{self.kind}: {lengths} {self.length_unit}; {rows} crank angles"

    def with_overrides(self, solvers: tuple[str, ...] | None = None,
                       formats: tuple[str, ...] | None = None) -> MechanismCase:
        """A copy with the solvers (design cases only) and/or report formats replaced.

        Raises
        ------
        ValueError
            If ``solvers`` breaks the ``solver.solvers`` key (``"lm"`` included: these
            problems have no residual form).
        """
        values = dict(self.values)
        if solvers is not None and self.kind == DESIGN_KIND:
            values["solver.solvers"] = checked_solvers(DESIGN_KEYS, solvers)
        return replace(self, values=values,
                       formats=self.formats if formats is None else tuple(formats))

    def to_dict(self) -> dict[str, Any]:
        """The case in the case-file layout, every default filled in.

        :func:`sso._cases.schema.parse_case` reads this dictionary back into an equal case.
        """
        document: dict[str, Any] = {"kind": self.kind, "name": self.name,
                                    "description": self.description,
                                    "output": {"formats": list(self.formats)}}
        # in the schema's order, so a case read back saves the same bytes
        order = {f"{key.table}.{key.name}": index
                 for index, key in enumerate(kind_keys(self.kind))}
        for label, value in sorted(self.values.items(),
                                   key=lambda item: order.get(item[0], len(order))):
            if "." not in label:
                continue
            table, name = label.split(".", 1)
            document.setdefault(table, {})[name] = _plain(value)
        return document


def angle_grid(start_deg: float, stop_deg: float, step_deg: float) -> np.ndarray:
    """Crank angles from ``start_deg`` by ``step_deg`` up to ``stop_deg`` (included when
    on the grid to within 1e-9 of a step), deg."""
    count = int(math.floor((stop_deg - start_deg) / step_deg + 1e-9)) + 1
    return start_deg + step_deg * np.arange(max(count, 0), dtype=float)


def build_mechanism(kind: str, values: dict[str, Any],
                    table: str) -> Mechanism:
    """The mechanism of ``kind`` from checked values keyed by dotted label."""
    linkage = _linkage(kind)
    arguments = {name: values[f"{table}.{name}"] for name in (*_link_names(kind), linkage.extra)}
    return linkage.mechanism(**arguments)


def _plain(value: Any) -> Any:
    return [_plain(item) for item in value] if isinstance(value, tuple) else value


def _build(values: dict[str, Any], path: str) -> MechanismCase:
    """Check the keys against each other, then build the :class:`MechanismCase`."""
    kind = values["kind"]
    start, stop, step = (values[f"drive.{name}"] for name in ("start_deg", "stop_deg", "step_deg"))
    if stop < start:
        raise ValueError(f"drive.stop_deg = {stop:g} is below drive.start_deg = {start:g}")
    rows = math.floor((stop - start) / step + 1e-9) + 1
    if rows > MAX_ROWS:
        raise ValueError(f"drive.step_deg = {step:g} gives {rows} crank angles from "
                         f"drive.start_deg = {start:g} to drive.stop_deg = {stop:g}; "
                         f"at most {MAX_ROWS} are allowed")
    if _linkage(kind).coupler_point:
        if len(values["plots.coupler_point"]) != 2:
            raise ValueError(f"plots.coupler_point = {list(values['plots.coupler_point'])} must "
                             "have 2 entries: [along A->B, to the left of A->B]")
    table = "start" if kind == DESIGN_KIND else "linkage"
    case = MechanismCase(kind=kind, name=values["name"], description=values["description"],
                         values={label: value for label, value in values.items()
                                 if "." in label and not label.startswith("output.")},
                         formats=values["output.formats"], source=path)
    if kind == DESIGN_KIND:
        _check_design_start(values)
    _check_assembly(case, table)
    return case


def _check_assembly(case: MechanismCase, table: str) -> None:
    """Refuse a linkage that cannot be assembled at some tabulated angles (unless marked).

    A design case's start linkage is tabulated too, so it is checked the same way.
    """
    angles = case.crank_angles_deg()
    lengths = ", ".join(f"{table}.{name} = {case.values[f'{table}.{name}']:g}"
                        for name in _link_names(case.kind))
    try:
        table_of_motion = case.mechanism().analyse(angles, crank_speed=case.crank_speed_rad_s,
                                                   crank_accel=case.crank_accel_rad_s2,
                                                   on_unassembled="mark")
    except ValueError as error:
        raise ValueError(f"{lengths}: {error}") from None
    assembled = table_of_motion["assembled"]
    if not assembled.any():
        raise ValueError(f"{lengths}: the linkage cannot be assembled at any crank angle "
                         f"from drive.start_deg to drive.stop_deg")
    if case.on_unassembled == "raise" and not assembled.all():
        failing = ", ".join(f"{angle:g}" for angle in angles[~assembled][:12])
        more = f", ... ({int((~assembled).sum())} in all)" if (~assembled).sum() > 12 else ""
        raise ValueError(f"{lengths}: the linkage cannot be assembled at crank angle(s) "
                         f"[{failing}{more}] deg; change the lengths, the angle range, or set "
                         "drive.on_unassembled = 'mark' to tabulate the other angles")


def _check_design_start(values: dict[str, Any]) -> None:
    for name in DESIGN_LINKS:
        lower, upper = values[f"bounds.{name}"]
        given = values[f"start.{name}"]
        if not lower <= given <= upper:
            raise ValueError(f"start.{name} = {given:g} lies outside bounds.{name} = "
                             f"[{lower:g}, {upper:g}]")


for _kind in MECHANISM_KINDS:
    register_case_kind(_kind, kind_keys(_kind), _build,
                       optional_tables=frozenset())
