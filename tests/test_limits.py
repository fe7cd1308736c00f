"""sso.limits: every physical limit and default is defined there once, and used from there.

Reference values: the module's own docstrings (what each constant means) and the
v0.1 defaults the README documents (25 rpm, 8 starts, 500 iterations, tolerance
1e-12 for a shaft series and 1e-10 for the four-bar design, the (40, 120) deg band).
"""

from __future__ import annotations

import ast
import inspect
import math
from pathlib import Path

import numpy as np
import pytest

from sso import limits
from sso.cases.schema import COMMON_KEYS
from sso.cases.shaft_series import SHAFT_SERIES_KEYS
from sso.kinematics.hooke import speed_ratio
from sso.linkages.fourbar_swing import design_fourbar
from sso.shafts.optimise import optimise

PACKAGE = Path(__file__).resolve().parents[1] / "sso"

# Each public default's parameter name and the constant it must take its default from.
DEFAULT_OF_PARAMETER = {
    "input_speed_rpm": "DEFAULT_INPUT_SPEED_RPM",
    "starts": "DEFAULT_STARTS",
    "max_iterations": "DEFAULT_MAX_ITERATIONS",
    "transmission_angle_bounds_deg": "TRANSMISSION_BAND_DEG",
}

# Functions that still write a default as a literal instead of naming the constant.
# They belong to work in progress elsewhere; delete each line when its module imports
# the constant, so this list only shrinks.
LITERAL_DEFAULTS_STILL_ALLOWED = {
    ("sso/column/feel.py", "optimise_on_centre", "starts"),
    ("sso/column/joint_positions.py", "optimise_joint_centres", "starts"),
    # The batched least-squares solver's own iteration default (200), not the design one.
    ("sso/solvers/least_squares.py", "batch_least_squares", "max_iterations"),
}


def test_documented_values():
    assert limits.BETA_LIMIT_DEG == 90.0
    assert limits.DEFAULT_INPUT_SPEED_RPM == 25.0
    assert (limits.DEFAULT_STARTS, limits.MAX_STARTS) == (8, 10_000)
    assert (limits.DEFAULT_MAX_ITERATIONS, limits.MAX_ITERATIONS) == (500, 1_000_000)
    assert limits.DEFAULT_SHAFT_SOLVER_TOL == 1e-12
    assert limits.DEFAULT_FOURBAR_SOLVER_TOL == 1e-10
    assert limits.TRANSMISSION_BAND_DEG == (40.0, 120.0)
    assert limits.OUTPUT_FORMATS == ("json", "csv", "md", "html", "png")


def test_defaults_lie_inside_their_limits():
    assert 1 <= limits.DEFAULT_STARTS <= limits.MAX_STARTS
    assert 1 <= limits.DEFAULT_MAX_ITERATIONS <= limits.MAX_ITERATIONS
    assert 0.0 < limits.DEFAULT_SHAFT_SOLVER_TOL < limits.DEFAULT_FOURBAR_SOLVER_TOL < 1.0
    lower, upper = limits.TRANSMISSION_BAND_DEG
    assert 0.0 < lower < 90.0 < upper < 180.0  # a band around the ideal 90 deg
    assert len(set(limits.OUTPUT_FORMATS)) == len(limits.OUTPUT_FORMATS)


def test_a_joint_at_the_beta_limit_locks():
    """Why 90 deg is excluded: the one-joint law w_out / w_in = cos b / (1 - sin^2 b sin^2 t)
    (the Hooke joint's textbook speed ratio) is 0 at b = 90 deg wherever cos t != 0:
    the output stops."""
    theta = np.radians([30.0, 60.0, 135.0, 300.0])
    ratio = speed_ratio(np, np.cos(theta), np.sin(theta), [math.radians(limits.BETA_LIMIT_DEG)], [])
    assert np.max(np.abs(ratio)) < 1e-15
    below = speed_ratio(np, np.cos(theta), np.sin(theta), [math.radians(89.0)], [])
    assert np.min(below) > 0.0


def test_module_imports_nothing_from_sso():
    tree = ast.parse((PACKAGE / "limits.py").read_text(encoding="utf-8"))
    imports = [node for node in ast.walk(tree) if isinstance(node, (ast.Import, ast.ImportFrom))]
    assert imports == []


@pytest.mark.parametrize(
    "function, parameter, constant",
    [
        (optimise, "input_speed_rpm", "DEFAULT_INPUT_SPEED_RPM"),
        (optimise, "starts", "DEFAULT_STARTS"),
        (optimise, "max_iterations", "DEFAULT_MAX_ITERATIONS"),
        (optimise, "solver_tol", "DEFAULT_SHAFT_SOLVER_TOL"),
        (design_fourbar, "starts", "DEFAULT_STARTS"),
        (design_fourbar, "max_iterations", "DEFAULT_MAX_ITERATIONS"),
        (design_fourbar, "solver_tol", "DEFAULT_FOURBAR_SOLVER_TOL"),
        (design_fourbar, "transmission_angle_bounds_deg", "TRANSMISSION_BAND_DEG"),
    ],
)
def test_public_api_defaults_are_the_limits(function, parameter, constant):
    assert inspect.signature(function).parameters[parameter].default == getattr(limits, constant)


def test_case_file_defaults_are_the_limits():
    default = {key.label: key.default for key in COMMON_KEYS + SHAFT_SERIES_KEYS}
    assert default["input_speed_rpm"] == limits.DEFAULT_INPUT_SPEED_RPM
    assert default["solver.starts"] == limits.DEFAULT_STARTS
    assert default["solver.max_iterations"] == limits.DEFAULT_MAX_ITERATIONS
    assert default["solver.solver_tol"] == limits.DEFAULT_SHAFT_SOLVER_TOL
    assert default["output.formats"] == limits.OUTPUT_FORMATS


def _literal_defaults() -> set[tuple[str, str, str]]:
    """(module, function, parameter) whose default for a known parameter is a literal."""
    found = set()
    for path in sorted(PACKAGE.rglob("*.py")):
        if path.name == "limits.py":
            continue
        name = path.relative_to(PACKAGE.parent).as_posix()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            arguments = node.args
            positional = arguments.posonlyargs + arguments.args
            pairs = list(
                zip(
                    positional[len(positional) - len(arguments.defaults) :],
                    arguments.defaults,
                    strict=True,
                )
            )
            pairs += [
                (argument, default)
                for argument, default in zip(
                    arguments.kwonlyargs, arguments.kw_defaults, strict=True
                )
                if default is not None
            ]
            for argument, default in pairs:
                literal = isinstance(default, (ast.Constant, ast.Tuple)) and not (
                    isinstance(default, ast.Constant) and default.value is None
                )
                if argument.arg in DEFAULT_OF_PARAMETER and literal:
                    found.add((name, node.name, argument.arg))
    return found


def test_defaults_are_named_not_written_as_literals():
    found = _literal_defaults()
    assert found - LITERAL_DEFAULTS_STILL_ALLOWED == set(), "import the default from sso.limits"
    assert LITERAL_DEFAULTS_STILL_ALLOWED - found == set(), "fixed: delete it from the list"


def test_the_iteration_cap_is_written_once():
    found = set()
    for path in sorted(PACKAGE.rglob("*.py")):
        if path.name == "limits.py":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if (
                isinstance(node, ast.Constant)
                and type(node.value) is int
                and node.value == limits.MAX_ITERATIONS
            ):
                found.add(path.relative_to(PACKAGE.parent).as_posix())
    assert found == set()
