"""One registry of planar mechanisms: everything the case, run and report layers
need to know about a mechanism, in one :class:`Linkage` entry per mechanism.

A mechanism module in :mod:`sso._linkages` defines its class and calls
:func:`register` once at import; :func:`linkages` imports every module of the
package the first time it is asked, so a new mechanism is one new module (plus its
tests) and nothing else names it.
"""

from __future__ import annotations

import importlib
import pkgutil
from dataclasses import Field, dataclass
from typing import Any, ClassVar, Literal, Protocol

from numpy.typing import ArrayLike

from sso._linkages.table import MechanismTable

OnUnassembled = Literal["raise", "mark"]
# Each panel of a series plot: (y label, with {length} for the length unit, curves);
# each curve: (table column or "left-right" difference, legend label[, line style]).
Panel = tuple[str, tuple[tuple[str, ...], ...]]
SeriesPlot = tuple[str, str, tuple[Panel, ...]]


class Mechanism(Protocol):
    """What the case, run and report layers use of a registered mechanism's instances.

    A frozen dataclass of link lengths (so :func:`dataclasses.asdict` gives its
    parameters) whose ``analyse`` tabulates its kinematics over crank angles, as
    :class:`sso._linkages.mechanisms.CrankDriven` does.
    """

    __dataclass_fields__: ClassVar[dict[str, Field[Any]]]

    def analyse(
        self,
        crank_angle_deg: ArrayLike,
        *,
        crank_speed: float,
        crank_accel: float = 0.0,
        on_unassembled: OnUnassembled = "raise",
    ) -> MechanismTable: ...


@dataclass(frozen=True)
class Linkage:
    """What sso knows of one planar mechanism.

    Attributes
    ----------
    kind : str
        Case-file ``kind`` of its analysis cases, e.g. ``"fourbar"``.
    mechanism : type of Mechanism
        Its class: a frozen dataclass of link lengths with ``analyse``; its name is
        the ``type`` written in result documents.
    links : tuple of str
        Link-length fields, in the order of the class's constructor (case keys
        ``linkage.<name>``).
    extra : {"branch", "offset"}
        The one non-length field: assembly branch, or slider offset.
    default_branch : {"open", "crossed"}
        Default of ``linkage.branch`` (``extra == "branch"``).
    coupler_point : bool
        Its table and plots carry the path of a point on the coupler
        (``plots.coupler_point``).
    report_columns : tuple of str
        Columns shown in the report's table (every column is in the CSV).
    extreme_columns : tuple of str
        Columns whose true extremes over a revolution the result lists.
    series_plots : tuple of SeriesPlot
        Plots against crank angle: (file name, title, panels).
    transmission_plot : bool
        Draw ``transmission_angle.png`` (the table has ``transmission_angle_deg``).
    drawing : {"joints", "fourbar_like", "slider_crank"}
        How ``linkage.png`` draws its positions: ``"joints"`` (the default, for any
        mechanism) draws the crank and the path and positions of every joint its
        table has (``joint_<name>_x``/``_y``); the others draw those linkages' parts.
    """

    kind: str
    mechanism: type[Mechanism]
    links: tuple[str, ...]
    extra: Literal["branch", "offset"]
    report_columns: tuple[str, ...]
    extreme_columns: tuple[str, ...]
    series_plots: tuple[SeriesPlot, ...]
    default_branch: Literal["open", "crossed"] = "open"
    coupler_point: bool = False
    transmission_plot: bool = False
    drawing: Literal["joints", "fourbar_like", "slider_crank"] = "joints"

    @property
    def type_name(self) -> str:
        """The class name, as result documents record it."""
        return self.mechanism.__name__


_REGISTRY: dict[str, Linkage] = {}
_discovered = False


def register(linkage: Linkage) -> Linkage:
    """Add ``linkage`` to the registry (once per kind); returns it."""
    known = _REGISTRY.get(linkage.kind)
    if known is not None and known.mechanism is not linkage.mechanism:
        raise ValueError(f"linkage kind {linkage.kind!r} is registered twice "
                         f"({known.type_name} and {linkage.type_name})")
    _REGISTRY[linkage.kind] = linkage
    return linkage


def linkages() -> dict[str, Linkage]:
    """Every registered linkage by kind, in the order the modules register them."""
    global _discovered
    if not _discovered:
        _discovered = True
        package = importlib.import_module("sso._linkages")
        for module in pkgutil.iter_modules(package.__path__):
            importlib.import_module(f"sso._linkages.{module.name}")
    return dict(_REGISTRY)


def linkage_of_kind(kind: str) -> Linkage:
    """The linkage whose case kind is ``kind``; KeyError if none."""
    return linkages()[kind]


def linkage_of(mechanism: Mechanism | str) -> Linkage:
    """The entry of a mechanism instance, or of a type name from a result document."""
    name = mechanism if isinstance(mechanism, str) else type(mechanism).__name__
    for linkage in linkages().values():
        if linkage.type_name == name:
            return linkage
    raise KeyError(f"no registered linkage of type {name!r}")
