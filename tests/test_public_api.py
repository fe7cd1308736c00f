"""The public API: ``sso.__all__``, one name per idea, each name documented.

docs/architecture.md ("Public API") declares it; this module keeps the declaration
and the package in step.
"""

from __future__ import annotations

import ast
import inspect
from pathlib import Path

import pytest

import sso

PACKAGE = Path(__file__).resolve().parents[1] / "sso"

# Names that are values, not functions or classes: the module that documents each
# with a string right after its assignment.
VALUE_DOCUMENTED_IN = {"SOLVERS": ("_limits.py", "SOLVERS"),
                       "__version__": ("_distribution.py", "VERSION")}


def attribute_docstring(module_file: str, name: str) -> str | None:
    """The string literal right after ``name = ...`` at the top of a module, if any."""
    body = ast.parse((PACKAGE / module_file).read_text(encoding="utf-8")).body
    for statement, following in zip(body, body[1:], strict=False):
        targets = (statement.targets if isinstance(statement, ast.Assign)
                   else [statement.target] if isinstance(statement, ast.AnnAssign) else [])
        if any(isinstance(target, ast.Name) and target.id == name for target in targets):
            if (isinstance(following, ast.Expr) and isinstance(following.value, ast.Constant)
                    and isinstance(following.value.value, str)):
                return following.value.value
            return None
    return None


def own_docstring(value: object) -> str | None:
    """The docstring written for ``value`` itself: not inherited, not generated."""
    written = vars(value).get("__doc__") if inspect.isclass(value) else value.__doc__
    if not written:
        return None
    name = getattr(value, "__name__", "")
    if inspect.isclass(value) and written.startswith(f"{name}("):
        return None  # the signature a dataclass writes when nobody wrote a docstring
    return written


@pytest.mark.parametrize("name", sso.__all__)
def test_every_public_name_has_a_docstring(name):
    value = getattr(sso, name)
    if name in VALUE_DOCUMENTED_IN:
        written = attribute_docstring(*VALUE_DOCUMENTED_IN[name])
    else:
        assert inspect.isclass(value) or inspect.isfunction(value), (
            f"{name}: document it in VALUE_DOCUMENTED_IN or export a function or class")
        written = own_docstring(value)
    assert written is not None and len(written.split()) >= 4, f"sso.{name} has no docstring"


def test_the_docstring_check_can_fail():
    class Undocumented:
        pass

    def undocumented() -> None:
        pass

    assert own_docstring(Undocumented) is None and own_docstring(undocumented) is None
    assert attribute_docstring("_limits.py", "NO_SUCH_NAME") is None
    assert "solver" in attribute_docstring("_limits.py", "SOLVERS")


def test_no_two_public_names_for_one_thing():
    by_identity: dict[int, list[str]] = {}
    for name in sso.__all__:
        by_identity.setdefault(id(getattr(sso, name)), []).append(name)
    assert [names for names in by_identity.values() if len(names) > 1] == []


def test_one_optimiser_entry_point():
    """``sso.optimise`` dispatches every design problem; ``optimise_batch`` stays
    public for the reason docs/architecture.md gives (many starts in, every start's
    optimum out); no other public name optimises."""
    optimisers = {name for name in sso.__all__
                  if inspect.isfunction(getattr(sso, name))
                  and any(word in name for word in ("optimise", "design", "best"))}
    assert optimisers == {"optimise", "optimise_batch"}


def test_the_architecture_page_declares_exactly_the_public_names():
    page = (PACKAGE.parent / "docs" / "architecture.md").read_text(encoding="utf-8")
    section = page.split("## Public API", 1)[1].split("### ", 1)[0]
    table = [line for line in section.splitlines() if line.startswith("| ")][1:]
    declared = {name for line in table for name in line.split("|")[2].replace("`", "")
                .replace("(", ",").replace(")", ",").split(",")}
    declared = {name.strip() for name in declared} - {"", "every problem", "see below"}
    assert declared == set(sso.__all__) - {"__version__"}
