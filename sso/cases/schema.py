"""Case files: one TOML file describes one design problem.

A case file is data only (``tomllib``; nothing in it is executed). Reading one
checks every key against the schema of its ``kind``:

* a TOML syntax error names the line;
* an unknown key or table is refused with the nearest valid key suggested;
* a wrong type or an out-of-range value names the key, the value and the allowed
  range (and the line where the key sits).

Adding a kind
-------------
The schema is a table of :class:`Key` entries per kind, registered in
:data:`CASE_KINDS` with a function that builds the kind's case object from the
checked values. A new kind (a planar mechanism, say) registers its own keys and
builder with :func:`register_case_kind`; a new table shared by every kind (a sweep,
say) adds its keys to :data:`COMMON_KEYS`.
"""

from __future__ import annotations

import difflib
import re
import tomllib
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Callable, Mapping

from sso.kinematics.hooke import MODELS
from sso.limits import (
    BETA_LIMIT_DEG,
    DEFAULT_INPUT_SPEED_RPM,
    DEFAULT_MAX_ITERATIONS,
    DEFAULT_SHAFT_SOLVER_TOL,
    DEFAULT_STARTS,
    INPUT_MAGNITUDE_RANGE,
    MAX_INPUT_SPEED_RPM,
    MAX_ITERATIONS,
    MAX_STARTS,
    OUTPUT_FORMATS,
)
from sso.shafts.options import OPTION_NAMES, build_problem, parse_option
from sso.shafts.quadrature import DEFAULT_ATOL, DEFAULT_RTOL
from sso.shafts.series import ShaftSeries
from sso.solvers.crosscheck import (
    DEFAULT_KKT_TOLERANCE,
    DEFAULT_OBJECTIVE_ATOL,
    DEFAULT_OBJECTIVE_RTOL,
)
from sso.solvers.starts import DEFAULT_SEED
from sso.files import read_input_bytes
from sso.validation import finite_float, per_item_bounds, shown

DEFAULT_KIND = "shaft_series"
SOLVER_NAMES = ("ipopt", "slsqp")
NAME_PATTERN = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,99}")
MAX_JOINTS = 64

MAX_TEXT_LENGTH = 10_000


class CaseError(ValueError):
    """A case file cannot be read or breaks the schema.

    Attributes
    ----------
    path : str
        The case file.
    line : int or None
        Line of the offending key, when it could be found.
    reason : str
        What is wrong, naming the key, the value and the allowed range.
    """

    def __init__(self, path: str, reason: str, line: int | None = None) -> None:
        self.path = path
        self.line = line
        self.reason = reason
        where = f"{path}, line {line}" if line is not None else path
        super().__init__(f"{where}: {reason}")


@dataclass(frozen=True)
class Key:
    """One key of the case-file schema.

    Attributes
    ----------
    table : str
        TOML table holding the key (``""`` for the top level).
    name : str
        Key name inside the table.
    parse : callable
        ``parse(label, value)`` returns the checked value or raises ValueError
        naming ``label``, the value and the allowed range.
    default : any
        Value when the key is absent; :data:`REQUIRED` if it must be given, or a
        callable ``default(values, path)`` for defaults that depend on other keys.
    unit : str
        Unit of the value (``""`` if none).
    allowed : str
        Allowed values in words, for errors and the README.
    """

    table: str
    name: str
    parse: Callable[[str, Any], Any]
    default: Any
    unit: str
    allowed: str

    @property
    def label(self) -> str:
        """Dotted name as a user writes it: ``solver.starts``."""
        return f"{self.table}.{self.name}" if self.table else self.name


REQUIRED = object()


@dataclass(frozen=True)
class CaseKind:
    """Schema and builder of one ``kind`` of case.

    Attributes
    ----------
    keys : tuple of Key
        The kind's own keys (the common keys are added to every kind).
    optional_tables : frozenset of str
        Tables that may be left out even though they hold required keys.
    build : callable
        ``build(values, path)`` checks the keys against each other and returns the
        case object from the checked values keyed by dotted label; it raises
        ValueError naming the keys.
    """

    keys: tuple[Key, ...]
    optional_tables: frozenset[str]
    build: Callable[[dict[str, Any], str], Any]


# ---------------------------------------------------------------- value parsers

def _describe_range(lower: float, upper: float, lower_open: bool = False,
                    upper_open: bool = False, unit: str = "") -> str:
    left = "(" if lower_open else "["
    right = ")" if upper_open else "]"
    text = f"{left}{lower:g}, {upper:g}{right}"
    return f"{text} {unit}" if unit else text


def number(lower: float, upper: float, unit: str = "", lower_open: bool = False,
           upper_open: bool = False) -> Callable[[str, Any], float]:
    """Parser of one real number inside an interval.

    Whatever the interval, the number must be 0 or have a magnitude inside
    :data:`sso.limits.INPUT_MAGNITUDE_RANGE`, so that squares, products and
    ratios computed from it cannot overflow.
    """
    allowed = _describe_range(lower, upper, lower_open, upper_open, unit)
    smallest, largest = INPUT_MAGNITUDE_RANGE

    def parse(label: str, value: Any) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError(f"{label} = {shown(value)} must be a number in {allowed}")
        result = finite_float(label, value)
        too_low = result <= lower if lower_open else result < lower
        too_high = result >= upper if upper_open else result > upper
        if too_low or too_high:
            raise ValueError(f"{label} = {result:g} is outside the allowed range {allowed}")
        if result != 0.0 and not smallest <= abs(result) <= largest:
            raise ValueError(f"{label} = {result:g} is outside the allowed range {allowed}: "
                             f"a number must be 0 or of magnitude {smallest:g} to {largest:g}")
        return result

    return parse


def whole_number(lower: int, upper: int) -> Callable[[str, Any], int]:
    """Parser of one integer inside ``[lower, upper]``."""

    def parse(label: str, value: Any) -> int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ValueError(f"{label} = {shown(value)} must be a whole number in [{lower}, {upper}]")
        if not lower <= value <= upper:
            raise ValueError(f"{label} = {value} is outside the allowed range [{lower}, {upper}]")
        return value

    return parse


def choice(allowed: tuple[str, ...]) -> Callable[[str, Any], str]:
    """Parser of one string out of ``allowed``."""

    def parse(label: str, value: Any) -> str:
        if value not in allowed:
            raise ValueError(f"{label} = {shown(value)} is not one of {_quoted(allowed)}")
        return value

    return parse


def text(max_length: int = MAX_TEXT_LENGTH) -> Callable[[str, Any], str]:
    """Parser of free text (stored as given; escaped wherever it is rendered)."""

    def parse(label: str, value: Any) -> str:
        if not isinstance(value, str):
            raise ValueError(f"{label} = {shown(value)} must be a string of at most {max_length} characters")
        if len(value) > max_length:
            raise ValueError(f"{label} has {len(value)} characters; at most {max_length} are allowed")
        return value

    return parse


def choice_list(allowed: tuple[str, ...]) -> Callable[[str, Any], tuple[str, ...]]:
    """Parser of a non-empty list of distinct strings out of ``allowed``."""

    def parse(label: str, value: Any) -> tuple[str, ...]:
        if not isinstance(value, list) or not value:
            raise ValueError(f"{label} = {shown(value)} must be a non-empty list of {_quoted(allowed)}")
        for index, item in enumerate(value):
            if item not in allowed:
                raise ValueError(f"{label}[{index}] = {shown(item)} is not one of {_quoted(allowed)}")
        if len(set(value)) != len(value):
            raise ValueError(f"{label} = {shown(value)} names an entry twice")
        return tuple(value)

    return parse


def number_list(lower: float, upper: float, unit: str, upper_open: bool = False,
                max_length: int = MAX_JOINTS,
                min_length: int = 1) -> Callable[[str, Any], tuple[float, ...]]:
    """Parser of a list of ``min_length..max_length`` numbers, each inside an interval."""
    item = number(lower, upper, unit, upper_open=upper_open)

    def parse(label: str, value: Any) -> tuple[float, ...]:
        if not isinstance(value, list) or not min_length <= len(value) <= max_length:
            raise ValueError(f"{label} = {shown(value)} must be a list of {min_length} to "
                             f"{max_length} numbers, "
                             f"each in {_describe_range(lower, upper, False, upper_open, unit)}")
        return tuple(item(f"{label}[{index}]", entry) for index, entry in enumerate(value))

    return parse


def bounds_list(lower: float, upper: float, unit: str,
                upper_open: bool = False) -> Callable[[str, Any], tuple]:
    """Parser of one ``[lower, upper]`` pair or a list of pairs (one per item)."""
    allowed = _describe_range(lower, upper, False, upper_open, unit)

    def parse(label: str, value: Any) -> tuple:
        if _is_pair(value):
            return tuple(per_item_bounds(label, value, 1, lower, upper, unit, upper_open)[0])
        if isinstance(value, list) and value and all(_is_pair(pair) for pair in value):
            return per_item_bounds(label, value, len(value), lower, upper, unit, upper_open)
        raise ValueError(f"{label} = {shown(value)} must be one [lower, upper] pair or a list of "
                         f"pairs, each bound in {allowed}")

    return parse


def _one_or_list(lower: float, upper: float, unit: str) -> Callable[[str, Any], tuple[float, ...]]:
    """Parser of one number or a list of numbers, each inside ``[lower, upper]``."""
    items = number_list(lower, upper, unit)

    def parse(label: str, value: Any) -> tuple[float, ...]:
        return items(label, value if isinstance(value, list) else [value])

    return parse


def option_value(label: str, value: Any) -> int:
    """Parser of the design option: 1, 2, 3 or its name."""
    try:
        return parse_option(value)
    except ValueError:
        raise ValueError(f"{label} = {shown(value)} is not one of 1, 2, 3, "
                         f"{_quoted(tuple(OPTION_NAMES.values()))}") from None


def case_name(label: str, value: Any) -> str:
    """Parser of a case name: it names the report folder, so it must be a safe file name."""
    if not isinstance(value, str) or not NAME_PATTERN.fullmatch(value):
        raise ValueError(
            f"{label} = {shown(value)} must be 1 to 100 letters, digits, '.', '_' or '-', "
            "starting with a letter or digit (it names the report folder)"
        )
    return value


def _name_from_file(path: str) -> str:
    """The default case name, the file's stem, checked like a given name."""
    stem = Path(path).stem
    try:
        return case_name("name", stem)
    except ValueError as error:
        raise ValueError(f"{error}; the name comes from the file name: rename the file or "
                         "give name = \"...\"") from None


def _is_pair(value: Any) -> bool:
    return (isinstance(value, list) and len(value) == 2
            and all(isinstance(item, (int, float)) and not isinstance(item, bool) for item in value))


def _quoted(items: tuple[str, ...]) -> str:
    return ", ".join(repr(item) for item in items)


# ---------------------------------------------------------------- the schema

COMMON_KEYS: tuple[Key, ...] = (
    Key("", "kind", lambda label, value: value, DEFAULT_KIND, "",
        "a registered kind: 'shaft_series', 'fourbar', 'slider_crank', 'quick_return', "
        "'fourbar_design'"),
    Key("", "name", case_name, lambda values, path: _name_from_file(path), "",
        "1-100 of A-Z a-z 0-9 . _ -, starting with a letter or digit"),
    Key("", "description", text(), "", "", "free text"),
    Key("output", "formats", choice_list(OUTPUT_FORMATS), OUTPUT_FORMATS, "",
        "non-empty list of 'json', 'csv', 'md', 'html', 'png'"),
)


@dataclass(frozen=True)
class Case:
    """A shaft-series design problem as read from a case file, after defaults.

    Attributes
    ----------
    kind : str
        ``"shaft_series"``.
    name : str
        Case name; the report goes to ``<out>/<name>/``.
    description : str
        Free text (escaped wherever it is rendered).
    model : {"exact", "paper"}
        Chain model.
    option : int
        1 (phases), 2 (operating angles, phases at 90 deg) or 3 (both).
    input_speed_rpm : float
        Input shaft speed, rpm.
    beta_deg, phase_deg : tuple of float
        The design as given (deg): start of the free angles, value of the fixed ones.
    beta_bounds_deg, phase_bounds_deg : tuple
        One ``(lower, upper)`` pair for all, or one pair per joint / phase (deg).
    solvers : tuple of str
        Solvers to run.
    starts : int
        Starts per solver.
    tolerance : float
        Solver tolerance.
    max_iterations : int
        Iteration limit of each run.
    seed : int
        Seed of the space-filling starts.
    quadrature_rtol, quadrature_atol : float
        Tolerance of the residual-error quadrature.
    objective_rtol, objective_atol, kkt_tolerance : float
        Tolerances of the solvers' cross-check.
    reference_label : str
        Name of the reference design in reports.
    reference_beta_deg, reference_phase_deg : tuple of float or None
        A design to compare against (deg), or None.
    formats : tuple of str
        Report files to write.
    source : str
        Path of the case file.
    warnings : tuple of str
        Warnings raised while checking the design (a start moved onto its bounds,
        the paper's inert phase); not part of the case data.
    tolerance_study : dict or None
        Keyword arguments of :func:`sso.tolerance` from the ``[tolerance]`` table
        (only the keys given), or None without one.
    """

    kind: str
    name: str
    description: str
    model: str
    option: int
    input_speed_rpm: float
    beta_deg: tuple[float, ...]
    phase_deg: tuple[float, ...]
    beta_bounds_deg: tuple
    phase_bounds_deg: tuple
    solvers: tuple[str, ...]
    starts: int
    tolerance: float
    max_iterations: int
    seed: int
    quadrature_rtol: float
    quadrature_atol: float
    objective_rtol: float
    objective_atol: float
    kkt_tolerance: float
    reference_label: str
    reference_beta_deg: tuple[float, ...] | None
    reference_phase_deg: tuple[float, ...] | None
    formats: tuple[str, ...]
    source: str
    warnings: tuple[str, ...] = field(default=(), compare=False)
    tolerance_study: dict[str, Any] | None = None

    def series(self) -> ShaftSeries:
        """The design as given, as a :class:`sso.ShaftSeries`."""
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return ShaftSeries(self.beta_deg, self.phase_deg, self.model)

    def reference_series(self) -> ShaftSeries | None:
        """The reference design, or None when the case gives none."""
        if self.reference_beta_deg is None:
            return None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return ShaftSeries(self.reference_beta_deg, self.reference_phase_deg, self.model)

    def optimise_options(self) -> dict[str, Any]:
        """Keyword arguments of :func:`sso.optimise` for this case."""
        return {
            "beta_bounds_deg": self.beta_bounds_deg,
            "phase_bounds_deg": self.phase_bounds_deg,
            "solvers": self.solvers,
            "starts": self.starts,
            "input_speed_rpm": self.input_speed_rpm,
            "tolerance": self.tolerance,
            "max_iterations": self.max_iterations,
            "seed": self.seed,
            "quadrature_rtol": self.quadrature_rtol,
            "quadrature_atol": self.quadrature_atol,
            "objective_rtol": self.objective_rtol,
            "objective_atol": self.objective_atol,
            "kkt_tolerance": self.kkt_tolerance,
        }

    def with_overrides(self, solvers: tuple[str, ...] | None = None,
                       formats: tuple[str, ...] | None = None) -> "Case":
        """A copy with the solvers and/or report formats replaced (command-line options)."""
        return replace(self, solvers=self.solvers if solvers is None else tuple(solvers),
                       formats=self.formats if formats is None else tuple(formats))

    def to_dict(self) -> dict[str, Any]:
        """The case in the case-file layout, every default filled in.

        :func:`parse_case` reads this dictionary back into an equal case.
        """
        document: dict[str, Any] = {
            "kind": self.kind,
            "name": self.name,
            "description": self.description,
            "model": self.model,
            "option": self.option,
            "input_speed_rpm": self.input_speed_rpm,
            "design": {"beta_deg": list(self.beta_deg), "phase_deg": list(self.phase_deg)},
            "bounds": {"beta_deg": _bounds_to_lists(self.beta_bounds_deg),
                       "phase_deg": _bounds_to_lists(self.phase_bounds_deg)},
            "solver": {"solvers": list(self.solvers), "starts": self.starts,
                       "tolerance": self.tolerance, "max_iterations": self.max_iterations,
                       "seed": self.seed},
            "quadrature": {"rtol": self.quadrature_rtol, "atol": self.quadrature_atol},
            "crosscheck": {"objective_rtol": self.objective_rtol,
                           "objective_atol": self.objective_atol,
                           "kkt_tolerance": self.kkt_tolerance},
            "output": {"formats": list(self.formats)},
        }
        if self.reference_beta_deg is not None:
            document["reference"] = {"label": self.reference_label,
                                     "beta_deg": list(self.reference_beta_deg),
                                     "phase_deg": list(self.reference_phase_deg)}
        if self.tolerance_study is not None:
            document["tolerance"] = {name: _plain_list(self.tolerance_study[argument])
                                     for name, argument in TOLERANCE_ARGUMENTS.items()
                                     if argument in self.tolerance_study}
        return document


def _bounds_to_lists(bounds: tuple) -> list:
    if bounds and isinstance(bounds[0], tuple):
        return [list(pair) for pair in bounds]
    return list(bounds)


def _default_phases(design_table: str) -> Callable[[dict[str, Any], str], tuple[float, ...]]:
    def default(values: dict[str, Any], path: str) -> tuple[float, ...]:
        beta = values.get(f"{design_table}.beta_deg") or ()
        return (90.0,) * max(len(beta) - 1, 0)

    return default


_BETA_RANGE = "each in [0, 90) deg"
SHAFT_SERIES_KEYS: tuple[Key, ...] = (
    Key("", "model", choice(MODELS), "exact", "", "'exact' or 'paper'"),
    Key("", "option", option_value, 3, "",
        "1 or 'phase', 2 or 'angle', 3 or 'both'"),
    Key("", "input_speed_rpm", number(0.0, MAX_INPUT_SPEED_RPM, "rpm", lower_open=True), DEFAULT_INPUT_SPEED_RPM, "rpm",
        "(0, inf)"),
    Key("design", "beta_deg", number_list(0.0, BETA_LIMIT_DEG, "deg", upper_open=True), REQUIRED,
        "deg", f"1-{MAX_JOINTS} entries (one per joint), {_BETA_RANGE}"),
    Key("design", "phase_deg", number_list(-360.0, 360.0, "deg", min_length=0),
        _default_phases("design"),
        "deg", "n-1 entries (n accepted: the paper's inert last phase), each in [-360, 360]"),
    Key("bounds", "beta_deg", bounds_list(0.0, BETA_LIMIT_DEG, "deg", upper_open=True), (0.0, 40.0),
        "deg", "[lower, upper] or one pair per joint, within [0, 90)"),
    Key("bounds", "phase_deg", bounds_list(-360.0, 360.0, "deg"), (0.0, 180.0), "deg",
        "[lower, upper] or one pair per phase, within [-360, 360]"),
    Key("solver", "solvers", choice_list(SOLVER_NAMES), SOLVER_NAMES, "",
        "non-empty list of 'ipopt', 'slsqp'"),
    Key("solver", "starts", whole_number(1, MAX_STARTS), DEFAULT_STARTS, "",
        f"[1, {MAX_STARTS}]"),
    Key("solver", "tolerance", number(0.0, 1.0, lower_open=True, upper_open=True),
        DEFAULT_SHAFT_SOLVER_TOL, "",
        "(0, 1)"),
    Key("solver", "max_iterations", whole_number(1, MAX_ITERATIONS), DEFAULT_MAX_ITERATIONS, "",
        f"[1, {MAX_ITERATIONS}]"),
    Key("solver", "seed", whole_number(0, 2**63 - 1), DEFAULT_SEED, "", "[0, 2^63 - 1]"),
    Key("quadrature", "rtol", number(0.0, 1.0, lower_open=True, upper_open=True), DEFAULT_RTOL,
        "", "(0, 1)"),
    Key("quadrature", "atol", number(0.0, float("inf"), upper_open=True), DEFAULT_ATOL, "",
        "[0, inf)"),
    Key("crosscheck", "objective_rtol", number(0.0, float("inf"), upper_open=True),
        DEFAULT_OBJECTIVE_RTOL, "", "[0, inf)"),
    Key("crosscheck", "objective_atol", number(0.0, float("inf"), upper_open=True),
        DEFAULT_OBJECTIVE_ATOL, "", "[0, inf)"),
    Key("crosscheck", "kkt_tolerance", number(0.0, float("inf"), lower_open=True,
                                              upper_open=True),
        DEFAULT_KKT_TOLERANCE, "1/rad", "(0, inf)"),
    Key("reference", "label", text(200), "reference", "", "free text, at most 200 characters"),
    Key("reference", "beta_deg", number_list(0.0, 90.0, "deg", upper_open=True), REQUIRED,
        "deg", f"as design.beta_deg (same joint count), {_BETA_RANGE}"),
    Key("reference", "phase_deg", number_list(-360.0, 360.0, "deg", min_length=0),
        _default_phases("reference"), "deg", "as design.phase_deg"),
    # [tolerance]: a Monte Carlo study of the design (sso.tolerance, sso tolerance);
    # None means "not given": sso.tolerance's own default applies.
    Key("tolerance", "beta_deg", _one_or_list(0.0, 45.0, "deg"), None, "deg",
        "standard deviation (normal) or half-width (uniform), one or one per joint, "
        "each in [0, 45] (default 0.5)"),
    Key("tolerance", "phase_deg", _one_or_list(0.0, 45.0, "deg"), None, "deg",
        "as tolerance.beta_deg, one or one per phase (default 1)"),
    Key("tolerance", "distribution", choice(("normal", "uniform")), None, "",
        "'normal' or 'uniform' (default 'normal')"),
    Key("tolerance", "samples", whole_number(1, 100_000_000), None, "",
        "[1, 100000000] (default 10000)"),
    Key("tolerance", "seed", whole_number(0, 2**63 - 1), None, "", "[0, 2^63 - 1] (default 0)"),
    Key("tolerance", "percentiles", number_list(0.0, 100.0, "%", max_length=100), None, "%",
        "1-100 entries, each in [0, 100] (default [5, 50, 95, 99])"),
)


def _build_shaft_series(values: dict[str, Any], path: str) -> Case:
    """Check the design keys against each other, then build the :class:`Case`."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        _check_shaft_series_design(values)
    has_reference = "reference.beta_deg" in values
    return Case(
        kind=values["kind"],
        name=values["name"],
        description=values["description"],
        model=values["model"],
        option=values["option"],
        input_speed_rpm=values["input_speed_rpm"],
        beta_deg=values["design.beta_deg"],
        phase_deg=values["design.phase_deg"],
        beta_bounds_deg=values["bounds.beta_deg"],
        phase_bounds_deg=values["bounds.phase_deg"],
        solvers=values["solver.solvers"],
        starts=values["solver.starts"],
        tolerance=values["solver.tolerance"],
        max_iterations=values["solver.max_iterations"],
        seed=values["solver.seed"],
        quadrature_rtol=values["quadrature.rtol"],
        quadrature_atol=values["quadrature.atol"],
        objective_rtol=values["crosscheck.objective_rtol"],
        objective_atol=values["crosscheck.objective_atol"],
        kkt_tolerance=values["crosscheck.kkt_tolerance"],
        reference_label=values["reference.label"],
        reference_beta_deg=values["reference.beta_deg"] if has_reference else None,
        reference_phase_deg=values["reference.phase_deg"] if has_reference else None,
        formats=values["output.formats"],
        source=path,
        tolerance_study=_tolerance_study(values),
        warnings=tuple(dict.fromkeys(str(warning.message) for warning in caught)),
    )


# [tolerance] keys and the sso.tolerance arguments they give.
TOLERANCE_ARGUMENTS = {"beta_deg": "beta_tolerance_deg", "phase_deg": "phase_tolerance_deg",
                       "distribution": "distribution", "samples": "samples", "seed": "seed",
                       "percentiles": "percentiles"}


def _tolerance_study(values: dict[str, Any]) -> dict[str, Any] | None:
    given = {argument: values[f"tolerance.{name}"] for name, argument in
             TOLERANCE_ARGUMENTS.items() if values.get(f"tolerance.{name}") is not None}
    return given or None


def _plain_list(value: Any) -> Any:
    return list(value) if isinstance(value, tuple) else value


def _check_shaft_series_design(values: dict[str, Any]) -> None:
    """Cross-key checks: phase counts, option against joint count, bound shapes.

    Uses the same constructors as :func:`sso.optimise`, so a case that passes
    here is accepted there (warnings are left to the caller to record).
    """
    joints = len(values["design.beta_deg"])
    _series_or_error("design", values["design.beta_deg"], values["design.phase_deg"],
                     values["model"])
    if "reference.beta_deg" in values:
        if len(values["reference.beta_deg"]) != joints:
            raise ValueError(f"reference.beta_deg has {len(values['reference.beta_deg'])} "
                             f"entries; design.beta_deg has {joints} joints")
        _series_or_error("reference", values["reference.beta_deg"],
                         values["reference.phase_deg"], values["model"])
    try:
        build_problem(values["design.beta_deg"], values["design.phase_deg"][: joints - 1],
                      values["model"], values["option"], values["bounds.beta_deg"],
                      values["bounds.phase_deg"])
    except ValueError as error:
        raise ValueError(str(error).replace("beta_bounds_deg", "bounds.beta_deg")
                         .replace("phase_bounds_deg", "bounds.phase_deg")) from None


def _series_or_error(table: str, beta_deg: tuple, phase_deg: tuple, model: str) -> None:
    try:
        ShaftSeries(beta_deg, phase_deg, model)
    except ValueError as error:
        raise ValueError(re.sub(r"\b(beta_deg|phase_deg)\b", rf"{table}.\1", str(error),
                                count=1)) from None


CASE_KINDS: dict[str, CaseKind] = {
    "shaft_series": CaseKind(SHAFT_SERIES_KEYS, frozenset({"reference"}),
                             _build_shaft_series),
}


def register_case_kind(kind: str, keys: tuple[Key, ...], build: Callable,
                       optional_tables: frozenset[str] = frozenset()) -> None:
    """Register a new kind of case: its own keys and the builder of its case object.

    Raises
    ------
    ValueError
        If the kind is already registered or a key repeats a common key.
    """
    if kind in CASE_KINDS:
        raise ValueError(f"case kind {shown(kind)} is already registered")
    common = {key.label for key in COMMON_KEYS}
    clashes = [key.label for key in keys if key.label in common]
    if clashes:
        raise ValueError(f"keys {clashes} of kind {shown(kind)} repeat common keys")
    CASE_KINDS[kind] = CaseKind(tuple(keys), frozenset(optional_tables), build)


def schema(kind: str = DEFAULT_KIND) -> tuple[Key, ...]:
    """Every key a case of ``kind`` accepts (common keys first)."""
    return COMMON_KEYS + CASE_KINDS[kind].keys


# ---------------------------------------------------------------- reading

def load_case(path: str | Path) -> Case:
    """Read and check one case file.

    Parameters
    ----------
    path : str or pathlib.Path
        The TOML file.

    Returns
    -------
    Case
        Every default filled in; warnings about the design in ``Case.warnings``.

    Raises
    ------
    CaseError
        If the file cannot be read, is not valid TOML, or breaks the schema; the
        message names the file, the line where known, the key, the value and the
        allowed range.
    """
    path_text = str(path)
    try:
        source = read_input_bytes(path).decode("utf-8")
    except ValueError as error:  # UnicodeDecodeError is one too
        reason = (f"not a UTF-8 text file (byte {error.start})"
                  if isinstance(error, UnicodeDecodeError) else f"cannot read the case file: {error}")
        raise CaseError(path_text, reason) from None
    return parse_case(parse_toml(source, path_text, CaseError), path_text, source)


def parse_toml(source: str, path: str, error_type: Callable[..., Exception]) -> dict[str, Any]:
    """Parse TOML text, raising ``error_type(path, reason, line)`` for anything tomllib
    refuses or cannot handle (syntax, integers of more than 4300 digits, nesting too
    deep for the parser)."""
    try:
        return tomllib.loads(source)
    except tomllib.TOMLDecodeError as error:
        raise error_type(path, f"TOML syntax error: {error}",
                         _line_of_decode_error(error, source)) from None
    except ValueError as error:  # int() of a number with more than 4300 digits
        raise error_type(path, f"a number cannot be read: {error}", None) from None
    except RecursionError:
        raise error_type(path, "arrays or tables are nested too deeply to read", None) from None


def parse_case(document: Mapping[str, Any], path: str = "<case>", source: str = "") -> Case:
    """Check a case given as a dictionary (a parsed file, or ``Case.to_dict()``).

    Parameters
    ----------
    document : mapping
        Tables and keys as in a case file.
    path : str
        Where the case came from (for messages and the default name).
    source : str
        The file's text, used to find the line of an offending key.

    Returns
    -------
    Case

    Raises
    ------
    CaseError
        If a key is unknown, has the wrong type or lies out of range.
    """
    kind_value = document.get("kind", DEFAULT_KIND)
    if not isinstance(kind_value, str) or kind_value not in CASE_KINDS:
        raise CaseError(path, f"kind = {shown(kind_value)} is not one of {_quoted(tuple(CASE_KINDS))}",
                        _line_of_key(source, "", "kind"))
    case_kind = CASE_KINDS[kind_value]
    keys = COMMON_KEYS + case_kind.keys
    _refuse_unknown_keys(document, keys, path, source)

    values: dict[str, Any] = {}
    for key in keys:
        table = document.get(key.table, {}) if key.table else document
        if key.name in table:
            try:
                values[key.label] = key.parse(key.label, table[key.name])
            except ValueError as error:
                raise CaseError(path, str(error), _line_of_key(source, key.table, key.name)) from None
            except (TypeError, ArithmeticError, RecursionError):
                raise CaseError(path, f"{key.label} = {shown(table[key.name])} is not "
                                f"allowed: give {key.allowed}",
                                _line_of_key(source, key.table, key.name)) from None
        elif key.default is REQUIRED:
            if key.table in case_kind.optional_tables and key.table not in document:
                continue
            raise CaseError(path, f"{key.label} is missing: give {key.allowed}")
    try:
        for key in keys:
            if key.label not in values and key.default is not REQUIRED:
                values[key.label] = (key.default(values, path) if callable(key.default)
                                     else key.default)
        return case_kind.build(values, path)
    except ValueError as error:
        raise CaseError(path, str(error), _line_of_first_label(source, str(error), keys)) from None
    except (TypeError, ArithmeticError, RecursionError) as error:
        raise CaseError(path, f"the values do not fit together ({type(error).__name__}: "
                        f"{shown(str(error))}); check the keys against the case-file "
                        "reference") from None


def _refuse_unknown_keys(document: Mapping[str, Any], keys: tuple[Key, ...], path: str,
                         source: str) -> None:
    tables = {key.table for key in keys if key.table}
    labels = [key.label for key in keys]
    for name, value in document.items():
        if name in tables:
            if not isinstance(value, dict):
                raise CaseError(path, f"{name} = {shown(value)} must be a table ([{name}])",
                                _line_of_key(source, "", name))
            known = [key.name for key in keys if key.table == name]
            for inner in value:
                if inner not in known:
                    raise CaseError(path, _unknown_message(f"{name}.{inner}", inner, known,
                                                           labels, name),
                                    _line_of_key(source, name, inner))
        elif not any(key.label == name for key in keys if not key.table):
            top_level = [key.name for key in keys if not key.table]
            if isinstance(value, dict):
                suggestion = difflib.get_close_matches(name, sorted(tables), n=1, cutoff=0.6)
                hint = f"; did you mean [{suggestion[0]}]?" if suggestion else ""
                raise CaseError(path, f"unknown table [{name}]{hint} Tables: "
                                f"{', '.join(sorted(tables))}", _line_of_table(source, name))
            raise CaseError(path, _unknown_message(name, name, top_level, labels, ""),
                            _line_of_key(source, "", name))


def _unknown_message(label: str, name: str, same_table: list[str], every_label: list[str],
                     table: str) -> str:
    close = difflib.get_close_matches(name, same_table, n=1, cutoff=0.6)
    if close:
        suggestion = f"{table}.{close[0]}" if table else close[0]
    else:
        elsewhere = [other for other in every_label if other.rsplit(".", 1)[-1] == name]
        close_labels = difflib.get_close_matches(label, every_label, n=1, cutoff=0.6)
        suggestion = (elsewhere or close_labels or [None])[0]
    hint = f"; did you mean {suggestion}?" if suggestion else ""
    return f"unknown key {label}{hint}"


def _line_of_decode_error(error: tomllib.TOMLDecodeError, source: str) -> int | None:
    found = re.search(r"at line (\d+)", str(error))
    if found:
        return int(found.group(1))
    return len(source.splitlines()) if "end of document" in str(error) else None


def _line_of_first_label(source: str, message: str, keys: tuple[Key, ...]) -> int | None:
    """Line of the key named first in ``message`` (for errors that involve several keys)."""
    positions = []
    for key in keys:
        found = re.search(rf"(?<![\w.]){re.escape(key.label)}(?![\w])", message)
        if found:
            positions.append((found.start(), key))
    if not positions:
        return None
    key = min(positions, key=lambda position: position[0])[1]
    return _line_of_key(source, key.table, key.name)


_TABLE_HEADER = re.compile(r"^\s*\[\s*([A-Za-z0-9_.-]+)\s*\]")


def _line_of_table(source: str, table: str) -> int | None:
    for number_of_line, line in enumerate(source.splitlines(), start=1):
        header = _TABLE_HEADER.match(line)
        if header and header.group(1) == table:
            return number_of_line
    return None


def _line_of_key(source: str, table: str, name: str) -> int | None:
    """Line of ``name = ...`` inside ``[table]`` (or ``table.name = ...`` at the top)."""
    current = ""
    assignment = re.compile(rf"^\s*{re.escape(name)}\s*=")
    dotted = re.compile(rf"^\s*{re.escape(table)}\s*\.\s*{re.escape(name)}\s*=") if table else None
    for number_of_line, line in enumerate(source.splitlines(), start=1):
        header = _TABLE_HEADER.match(line)
        if header:
            current = header.group(1)
        elif current == table and assignment.match(line):
            return number_of_line
        elif current == "" and dotted is not None and dotted.match(line):
            return number_of_line
    return None
