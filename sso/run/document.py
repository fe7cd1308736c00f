"""The result document: what ``result.json`` holds, built by calling the public API.

A document is a plain JSON-ready dictionary. It carries the case as read (after
defaults), every design compared (initial, optimum, reference) with its
evaluation, every solver's answer, the cross-check, the quadrature used, the
warnings and the package versions, so every report format can be rendered again
from the file alone (:mod:`sso.reports.writer`).

Layout (``schema_version`` 1)::

    schema_version, kind, mode ("optimise" | "evaluate"), created_utc,
    case, case_file, model, option, option_name, input_speed_rpm,
    designs: {initial, optimum?, reference?} -> {label, beta_deg, phase_deg, evaluation},
    start, bounds, solutions, runs, crosscheck, local_minima, quadrature,
    success, verdict, warnings, versions
"""

from __future__ import annotations

import importlib.metadata
import importlib.util
import platform
import re
import warnings
from datetime import UTC, datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any

from sso.cases.shaft_series import Case
from sso.distribution import installed_version
from sso.shafts.options import OPTION_NAMES

if TYPE_CHECKING:
    from sso.shafts.optimise import OptimisationResult
    from sso.solvers.result import DesignResult

SCHEMA_VERSION = 1
DESIGN_ROLES = ("initial", "optimum", "reference")
VERSIONED_PACKAGES = ("casadi", "scipy", "numpy", "matplotlib")


def optimise_case(case: Case) -> dict[str, Any]:
    """Optimise a case with :func:`sso.optimise` and return its result document.

    Solver failures and disagreements are recorded (``success`` false, ``verdict``
    says why), never raised. Warnings are recorded in ``warnings``, not emitted.

    Raises
    ------
    ValueError
        If the case's values are rejected by :func:`sso.optimise`.
    """
    from sso.shafts.optimise import optimise

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = optimise(case.series(), case.option, **case.optimise_options())
    document = optimisation_document(result, case)
    document["warnings"] = _unique(document["warnings"]
                                   + [str(warning.message) for warning in caught])
    return document


def optimisation_document(result: OptimisationResult, case: Case | None = None) -> dict[str, Any]:
    """The result document of an optimisation, as ``sso run`` writes it.

    Parameters
    ----------
    result : sso.OptimisationResult
    case : sso.cases.schema.Case, optional
        The case it solved. Without one (a result made in Python) the document's
        case is built from what the result records: its design, option, model,
        bounds, solvers and starts; settings the result does not record (solver
        tolerance, iteration limit, seed) appear at their defaults.
    """
    if case is None:
        case = case_of_result(result)
    document = _common(case, "optimise")
    document["designs"] = {
        "initial": _design("initial design (as given)", result.initial_series, result.initial),
        "optimum": _design(f"optimum ({result.best.solver})", result.best.series,
                           result.optimum),
    }
    _add_reference(document, case)
    outcome = result._document_dict()
    document.update({
        "start": outcome["start_series"],
        "bounds": {"beta_deg": outcome["beta_bounds_deg"],
                   "phase_deg": outcome["phase_bounds_deg"]},
        "solutions": outcome["solutions"],
        "runs": outcome["runs"],
        "crosscheck": outcome["crosscheck"],
        "local_minima": outcome["local_minima"],
        "starts": outcome["starts"],
        "quadrature": {"samples": result.samples, "error_estimate": result.quadrature_error,
                       "rtol": case.quadrature_rtol, "atol": case.quadrature_atol},
        "success": result.success,
        "verdict": _verdict(result),
    })
    document["warnings"] = _unique(document["warnings"] + list(result.warnings))
    return document


def case_of_result(result: OptimisationResult) -> Case:
    """A case holding what an optimisation result records of its problem."""
    from sso.cases.schema import parse_case

    case: Case = parse_case({
        "name": "optimisation",
        "description": "An optimisation made with sso.optimise in Python.",
        "model": result.model,
        "option": result.option,
        "input_speed_rpm": result.input_speed_rpm,
        "design": {"beta_deg": list(result.initial_series.beta_deg),
                   "phase_deg": list(result.initial_series.phase_deg)},
        "bounds": {"beta_deg": [list(pair) for pair in result.beta_bounds_deg],
                   "phase_deg": [list(pair) for pair in result.phase_bounds_deg]},
        "solver": {"solvers": list(result.solutions), "starts": result.starts},
    }, "<sso.optimise>")
    return case


def evaluate_case(case: Case) -> dict[str, Any]:
    """Evaluate the case's design as given (and its reference); no optimisation.

    Builds no NLP and imports no CasADi.
    """
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        series = case.series()
        evaluation = series.evaluate(case.input_speed_rpm, quadrature_rtol=case.quadrature_rtol,
                                     quadrature_atol=case.quadrature_atol)
        document = _common(case, "evaluate")
        document["designs"] = {"initial": _design("design (as given)", series, evaluation)}
        _add_reference(document, case)
    document["warnings"] = _unique(document["warnings"]
                                   + [str(warning.message) for warning in caught])
    document.update({
        "quadrature": {"samples": evaluation.samples,
                       "error_estimate": evaluation.quadrature_error,
                       "rtol": case.quadrature_rtol, "atol": case.quadrature_atol},
        "success": True,
        "verdict": "evaluated as given; no optimisation",
    })
    return document


def package_versions() -> dict[str, str]:
    """Versions of Python, sso, CasADi, its bundled IPOPT, SciPy, NumPy and matplotlib.

    Read from the installed distributions' metadata, so nothing is imported.
    """
    versions = {"python": platform.python_version(), "sso": installed_version()}
    for package in VERSIONED_PACKAGES:
        try:
            versions[package] = importlib.metadata.version(package)
        except importlib.metadata.PackageNotFoundError:
            versions[package] = "not installed"
    versions["ipopt"] = bundled_ipopt_version()
    return versions


def bundled_ipopt_version() -> str:
    """Version of the IPOPT library bundled with CasADi, read from its files.

    CasADi ships IPOPT's ``IpoptConfig.h`` (``#define IPOPT_VERSION "x.y.z"``) and
    ``libipopt.so.x.y.z``; neither needs CasADi to be imported.
    """
    spec = importlib.util.find_spec("casadi")
    if spec is None or not spec.submodule_search_locations:
        return "unknown: casadi is not installed"
    folder = Path(list(spec.submodule_search_locations)[0])
    header = folder / "include" / "coin-or" / "IpoptConfig.h"
    if header.is_file():
        found = re.search(r'#define\s+IPOPT_VERSION\s+"([^"]+)"',
                          header.read_text(errors="replace"))
        if found:
            return found.group(1)
    for library in sorted(folder.glob("libipopt*")):
        found = re.search(r"(\d+\.\d+\.\d+)", library.name)
        if found:
            return found.group(1)
    return "unknown: no IPOPT version found in casadi's files"


def document_header(case: Any, mode: str) -> dict[str, Any]:
    """The keys every result document opens with, for a case of any kind.

    Parameters
    ----------
    case : a checked case
        Anything with ``kind``, ``source`` and ``to_dict()``.
    mode : str
        ``"optimise"``, ``"evaluate"`` or ``"analyse"``.

    Returns
    -------
    dict
        ``schema_version``, ``kind``, ``mode``, ``created_utc``, ``case``, ``case_file``.
    """
    return {
        "schema_version": SCHEMA_VERSION,
        "kind": case.kind,
        "mode": mode,
        "created_utc": datetime.now(UTC).isoformat(timespec="seconds"),
        "case": case.to_dict(),
        "case_file": case.source,
    }


def _common(case: Case, mode: str) -> dict[str, Any]:
    return {
        **document_header(case, mode),
        "model": case.model,
        "option": case.option,
        "option_name": OPTION_NAMES[case.option],
        "input_speed_rpm": case.input_speed_rpm,
        "warnings": list(case.warnings),
        "versions": package_versions(),
    }


def _design(label: str, series: Any, evaluation: Any) -> dict[str, Any]:
    return {"label": label, "beta_deg": list(series.beta_deg),
            "phase_deg": list(series.phase_deg), "evaluation": evaluation.to_dict()}


def _add_reference(document: dict[str, Any], case: Case) -> None:
    reference = case.reference_series()
    if reference is not None:
        evaluation = reference.evaluate(case.input_speed_rpm,
                                        quadrature_rtol=case.quadrature_rtol,
                                        quadrature_atol=case.quadrature_atol)
        document["designs"]["reference"] = _design(case.reference_label, reference, evaluation)


UNRELIABLE_VERDICT = "optimum unreliable"
"""How the verdict of a run whose optimum's quadrature did not converge begins."""


def _verdict(result: DesignResult) -> str:
    if not result.best.success:
        return f"solver failed: {result.best.solver}: {result.best.message}"
    # a shaft series' optimum says whether its quadrature converged; a four-bar's has none
    if not getattr(getattr(result, "optimum", None), "quadrature_converged", True):
        return (f"{UNRELIABLE_VERDICT}: operating angles this close to 90 deg put peaks in "
                "the speed ratio that the residual-error quadrature cannot resolve")
    if result.crosscheck is None:
        return f"solved by {result.best.solver} alone (no cross-check): {result.best.message}"
    return result.crosscheck.message


def _unique(texts: list[str]) -> list[str]:
    return list(dict.fromkeys(texts))

