"""sso._limits: every physical limit and default is defined there once, and used from there.

Reference values: the module's own docstrings (what each constant means) and the
v0.1 defaults the README documents (25 rpm, 8 starts, 500 iterations, tolerance
1e-12 for a shaft series and 1e-10 for the four-bar design, the (40, 120) deg band).
"""

from __future__ import annotations

import ast
import inspect
import math
import textwrap
from importlib import import_module
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import sso
from sso import _limits as limits
from sso._cases.schema import COMMON_KEYS
from sso._cases.shaft_series import SHAFT_SERIES_KEYS
from sso._column.dispatch import COLUMN_OPTIMISER_KEYWORDS, _column_optimiser
from sso._kinematics.hooke import speed_ratio
from sso._linkages.fourbar_swing import design_fourbar
from sso._shafts.optimise import optimise

PACKAGE = Path(__file__).resolve().parents[1] / "sso"

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
    tree = ast.parse((PACKAGE / "_limits.py").read_text(encoding="utf-8"))
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


def public_functions() -> list[tuple[str, Any]]:
    """Every function of the public API: those in ``sso.__all__``, the public methods of
    its classes, and the optimisers ``sso.optimise`` sends each problem to."""
    found: list[tuple[str, Any]] = []
    for name in sso.__all__:
        value = getattr(sso, name)
        if inspect.isfunction(value):
            found.append((name, value))
        elif inspect.isclass(value):
            for attribute, member in vars(value).items():
                function = member.__func__ if isinstance(member, (classmethod, staticmethod)) \
                    else member
                if inspect.isfunction(function) and not attribute.startswith("_"):
                    found.append((f"{name}.{attribute}", function))
    found += [(f"{optimiser.__module__}.{optimiser.__name__}", optimiser)
              for optimiser in map(_column_optimiser, (*COLUMN_OPTIMISER_KEYWORDS, None))]
    optimisers = [("sso._column.positions", "optimise_positions"),
                  ("sso._linkages.fourbar_swing", "design_fourbar"),
                  ("sso._shafts.optimise", "optimise")]
    found += [(f"{module}.{name}", getattr(import_module(module), name))
              for module, name in optimisers]
    return found


def literal_defaults(function: Any) -> list[str]:
    """Parameters of ``function`` whose default is a number or a tuple written in place,
    or a name that is not a constant of :mod:`sso._limits`."""
    node = ast.parse(textwrap.dedent(inspect.getsource(function))).body[0]
    assert isinstance(node, ast.FunctionDef)
    arguments = node.args
    positional = arguments.posonlyargs + arguments.args
    pairs = [*zip(positional[len(positional) - len(arguments.defaults):], arguments.defaults,
                  strict=True),
             *((argument, default) for argument, default
               in zip(arguments.kwonlyargs, arguments.kw_defaults, strict=True)
               if default is not None)]
    constants = {id(value) for name, value in vars(limits).items() if name.isupper()}
    found = []
    for argument, default in pairs:
        if isinstance(default, ast.Constant) and (default.value is None
                                                  or isinstance(default.value, (bool, str))):
            continue  # no default, a switch, or a choice by name
        if isinstance(default, ast.Tuple) and not default.elts:
            continue  # nothing given
        if isinstance(default, (ast.Name, ast.Attribute)) and id(
                eval(ast.unparse(default), function.__globals__)) in constants:  # noqa: S307
            continue
        found.append(f"{argument.arg} = {ast.unparse(default)}")
    return found


def test_every_public_default_is_a_constant_of_the_limits():
    functions = public_functions()
    assert len(functions) > 45  # the walk sees the API (Record methods are inherited)
    written_in_place = {name: found for name, function in functions
                        if (found := literal_defaults(function))}
    assert written_in_place == {}, "define each default in sso/_limits.py and name it there"


def test_the_default_check_can_fail():
    def hard_coded(starts: int = 8, solvers: tuple[str, ...] = ("ipopt",),
                   seed: int = limits.DEFAULT_SEED, model: str = "exact") -> None:
        pass

    assert literal_defaults(hard_coded) == ["starts = 8", "solvers = ('ipopt',)"]


def test_the_iteration_cap_is_written_once():
    found = set()
    for path in sorted(PACKAGE.rglob("*.py")):
        if path.name == "_limits.py":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if (
                isinstance(node, ast.Constant)
                and type(node.value) is int
                and node.value == limits.MAX_ITERATIONS
            ):
                found.add(path.relative_to(PACKAGE.parent).as_posix())
    assert found == set()
