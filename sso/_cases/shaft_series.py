"""The shaft-series case kind: keys, checks and :class:`Case`, registered with the schema.

The default kind of a case file (``kind = "shaft_series"`` or no ``kind``): a series
of Hooke joints to evaluate or optimise, and optionally a reference design and a
Monte Carlo tolerance study (``[tolerance]``).
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any

from sso._cases.schema import (
    REQUIRED,
    Bounds,
    Key,
    SavedCase,
    _quoted,
    bounds_list,
    choice,
    choice_list,
    number,
    number_list,
    register_case_kind,
    text,
    whole_number,
)
from sso._kinematics.hooke import MODELS
from sso._limits import (
    BETA_LIMIT_DEG,
    CROSS_CHECK_SOLVERS,
    DEFAULT_BETA_BOUNDS_DEG,
    DEFAULT_INPUT_SPEED_RPM,
    DEFAULT_KKT_TOLERANCE,
    DEFAULT_MAX_ITERATIONS,
    DEFAULT_OBJECTIVE_ATOL,
    DEFAULT_OBJECTIVE_RTOL,
    DEFAULT_OPTION,
    DEFAULT_PHASE_BOUNDS_DEG,
    DEFAULT_QUADRATURE_ATOL,
    DEFAULT_QUADRATURE_RTOL,
    DEFAULT_SEED,
    DEFAULT_SHAFT_SOLVER_TOL,
    DEFAULT_STARTS,
    MAX_INPUT_SPEED_RPM,
    MAX_ITERATIONS,
    MAX_JOINTS,
    MAX_STARTS,
    SOLVERS,
)
from sso._record import register_record
from sso._shafts.options import OPTION_NAMES, build_problem, parse_option, warn_moved_starts
from sso._shafts.series import ShaftSeries
from sso._validation import shown

KIND = "shaft_series"


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


@register_record
@dataclass(frozen=True)
class Case(SavedCase):
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
    solver_tol : float
        The solvers' stopping tolerance.
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
        Keyword arguments of :func:`sso.tolerance_study` from the ``[tolerance]`` table
        (only the keys given), or None without one.
    units_confirmed : tuple of str
        The keys of ``[units] confirm``: values meant as given, though they look like
        another unit (:mod:`sso._cases.units`).
    """

    kind: str
    name: str
    description: str
    model: str
    option: int
    input_speed_rpm: float
    beta_deg: tuple[float, ...]
    phase_deg: tuple[float, ...]
    beta_bounds_deg: Bounds
    phase_bounds_deg: Bounds
    solvers: tuple[str, ...]
    starts: int
    solver_tol: float
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
    units_confirmed: tuple[str, ...] = ()

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
            "solver_tol": self.solver_tol,
            "max_iterations": self.max_iterations,
            "seed": self.seed,
            "quadrature_rtol": self.quadrature_rtol,
            "quadrature_atol": self.quadrature_atol,
            "objective_rtol": self.objective_rtol,
            "objective_atol": self.objective_atol,
            "kkt_tolerance": self.kkt_tolerance,
        }

    def with_overrides(self, solvers: tuple[str, ...] | None = None,
                       formats: tuple[str, ...] | None = None) -> Case:
        """A copy with the solvers and/or report formats replaced (command-line options).

        Raises
        ------
        ValueError
            If ``solvers`` breaks the ``solver.solvers`` key or names ``"lm"`` for the
            paper model (the message names the key, the value and what is allowed).
        """
        if solvers is not None:
            solvers = checked_solvers(SHAFT_SERIES_KEYS, solvers)
            check_solvers_for_model(solvers, self.model)
        return replace(self, solvers=self.solvers if solvers is None else solvers,
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
                       "solver_tol": self.solver_tol, "max_iterations": self.max_iterations,
                       "seed": self.seed},
            "quadrature": {"rtol": self.quadrature_rtol, "atol": self.quadrature_atol},
            "crosscheck": {"objective_rtol": self.objective_rtol,
                           "objective_atol": self.objective_atol,
                           "kkt_tolerance": self.kkt_tolerance},
            "output": {"formats": list(self.formats)},
        }
        if self.reference_beta_deg is not None and self.reference_phase_deg is not None:
            document["reference"] = {"label": self.reference_label,
                                     "beta_deg": list(self.reference_beta_deg),
                                     "phase_deg": list(self.reference_phase_deg)}
        if self.units_confirmed:
            document["units"] = {"confirm": list(self.units_confirmed)}
        if self.tolerance_study is not None:
            document["tolerance"] = {name: _plain_list(self.tolerance_study[argument])
                                     for name, argument in TOLERANCE_ARGUMENTS.items()
                                     if argument in self.tolerance_study}
        return document


def _bounds_to_lists(bounds: Bounds) -> list[Any]:
    """JSON-ready ``[lower, upper]``, or one such list per item."""
    if bounds and isinstance(bounds[0], tuple):
        return [list(pair) for pair in bounds]
    return list(bounds)


def _default_phases(design_table: str) -> Callable[[dict[str, Any], str], tuple[float, ...]]:
    def default(values: dict[str, Any], path: str) -> tuple[float, ...]:
        beta = values.get(f"{design_table}.beta_deg") or ()
        return (90.0,) * max(len(beta) - 1, 0)

    return default


def check_solvers_for_model(solvers: tuple[str, ...], model: str) -> None:
    """Refuse ``"lm"`` outside the exact model (the paper model has no residual form).

    Raises
    ------
    ValueError
        Naming ``solver.solvers``, its value and the solvers ``model`` allows.
    """
    if "lm" in solvers and model != "exact":
        raise ValueError(f"solver.solvers = {shown(list(solvers))} includes 'lm', the "
                         "least-squares solver of the exact model's closed form; "
                         f"model = {shown(model)} allows {_quoted(CROSS_CHECK_SOLVERS)}")


_BETA_RANGE = "each in [0, 90) deg"
SHAFT_SERIES_KEYS: tuple[Key, ...] = (
    Key("", "model", choice(MODELS), "exact", "", "'exact' or 'paper'"),
    Key("", "option", option_value, DEFAULT_OPTION, "",
        "1 or 'phase', 2 or 'angle', 3 or 'both'"),
    Key("", "input_speed_rpm", number(0.0, MAX_INPUT_SPEED_RPM, "rpm", lower_open=True),
        DEFAULT_INPUT_SPEED_RPM, "rpm", f"(0, {MAX_INPUT_SPEED_RPM:g}]"),
    Key("design", "beta_deg", number_list(0.0, BETA_LIMIT_DEG, "deg", upper_open=True), REQUIRED,
        "deg", f"1-{MAX_JOINTS} entries (one per joint), {_BETA_RANGE}"),
    Key("design", "phase_deg", number_list(-360.0, 360.0, "deg", min_length=0),
        _default_phases("design"),
        "deg", "n-1 entries (n accepted: the paper's inert last phase), each in [-360, 360]"),
    Key("bounds", "beta_deg", bounds_list(0.0, BETA_LIMIT_DEG, "deg", upper_open=True),
        DEFAULT_BETA_BOUNDS_DEG, "deg", "[lower, upper] or one pair per joint, within [0, 90)"),
    Key("bounds", "phase_deg", bounds_list(-360.0, 360.0, "deg"), DEFAULT_PHASE_BOUNDS_DEG, "deg",
        "[lower, upper] or one pair per phase, within [-360, 360]"),
    Key("solver", "solvers", choice_list(SOLVERS), CROSS_CHECK_SOLVERS, "",
        f"non-empty list of {_quoted(SOLVERS)}; 'lm' with model = 'exact' only"),
    Key("solver", "starts", whole_number(1, MAX_STARTS), DEFAULT_STARTS, "",
        f"[1, {MAX_STARTS}]"),
    Key("solver", "solver_tol", number(0.0, 1.0, lower_open=True, upper_open=True),
        DEFAULT_SHAFT_SOLVER_TOL, "",
        "(0, 1)"),
    Key("solver", "max_iterations", whole_number(1, MAX_ITERATIONS), DEFAULT_MAX_ITERATIONS, "",
        f"[1, {MAX_ITERATIONS}]"),
    Key("solver", "seed", whole_number(0, 2**63 - 1), DEFAULT_SEED, "", "[0, 2^63 - 1]"),
    Key("quadrature", "rtol", number(0.0, 1.0, lower_open=True, upper_open=True),
        DEFAULT_QUADRATURE_RTOL, "", "(0, 1)"),
    Key("quadrature", "atol", number(0.0, float("inf"), upper_open=True),
        DEFAULT_QUADRATURE_ATOL, "", "[0, inf)"),
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
    # [tolerance]: a Monte Carlo study of the design (sso.tolerance_study, sso tolerance);
    # None means "not given": sso.tolerance_study's own default applies.
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


def checked_solvers(keys: tuple[Key, ...], solvers: tuple[str, ...]) -> tuple[str, ...]:
    """``solvers`` checked by the ``solver.solvers`` key among ``keys`` (an override).

    Raises
    ------
    ValueError
        Naming ``solver.solvers``, the bad entry and the allowed names.
    """
    key = next(key for key in keys if key.label == "solver.solvers")
    checked: tuple[str, ...] = key.parse(key.label, list(solvers))
    return checked


def solver_keys(defaults: dict[str, Any]) -> tuple[Key, ...]:
    """The ``[solver]`` keys for a kind whose problems have no residual form.

    As the shaft series' keys, with ``defaults`` replacing theirs by key name, and
    ``solver.solvers`` limited to :data:`sso._limits.CROSS_CHECK_SOLVERS` (no ``"lm"``).
    """
    keys = []
    for key in SHAFT_SERIES_KEYS:
        if key.table != "solver":
            continue
        key = replace(key, default=defaults.get(key.name, key.default))
        if key.name == "solvers":
            key = replace(key, parse=choice_list(CROSS_CHECK_SOLVERS),
                          allowed=f"non-empty list of {_quoted(CROSS_CHECK_SOLVERS)}")
        keys.append(key)
    return tuple(keys)


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
        solver_tol=values["solver.solver_tol"],
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
        units_confirmed=values["units.confirm"],
    )


# [tolerance] keys and the sso.tolerance_study arguments they give.
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
    check_solvers_for_model(values["solver.solvers"], values["model"])
    _series_or_error("design", values["design.beta_deg"], values["design.phase_deg"],
                     values["model"])
    if "reference.beta_deg" in values:
        if len(values["reference.beta_deg"]) != joints:
            raise ValueError(f"reference.beta_deg has {len(values['reference.beta_deg'])} "
                             f"entries; design.beta_deg has {joints} joints")
        _series_or_error("reference", values["reference.beta_deg"],
                         values["reference.phase_deg"], values["model"])
    try:
        problem = build_problem(values["design.beta_deg"],
                                values["design.phase_deg"][: joints - 1], values["model"],
                                values["option"], values["bounds.beta_deg"],
                                values["bounds.phase_deg"])
    except ValueError as error:
        raise ValueError(str(error).replace("beta_bounds_deg", "bounds.beta_deg")
                         .replace("phase_bounds_deg", "bounds.phase_deg")) from None
    warn_moved_starts(problem)


def _series_or_error(table: str, beta_deg: tuple[float, ...], phase_deg: tuple[float, ...],
                     model: str) -> None:
    try:
        ShaftSeries(beta_deg, phase_deg, model)
    except ValueError as error:
        raise ValueError(re.sub(r"\b(beta_deg|phase_deg)\b", rf"{table}.\1", str(error),
                                count=1)) from None


register_case_kind(KIND, SHAFT_SERIES_KEYS, _build_shaft_series, frozenset({"reference"}))
