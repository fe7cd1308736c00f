"""The package's imports point one way: down the layer order, and never in a circle.

Every module under ``sso/`` is parsed with :mod:`ast` (nothing is imported), and
every import in it counts: at module level, inside functions, and under
``TYPE_CHECKING``. A circle through any of them is a circle in the design.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "sso"

# Lowest first. A module may import its own part (file or folder) and any part on a
# lower layer; parts on one layer do not import each other. ``sso/__init__.py`` (the
# lazy public facade, with ``__version__``) stands outside the order.
LAYERS: tuple[tuple[str, ...], ...] = (
    ("limits", "distribution", "warning_origin", "interrupts"),
    ("validation", "files", "display", "progress"),
    ("kinematics", "folder_lock", "resources"),
    ("record",),
    ("solvers",),
    ("shafts", "linkages"),
    ("column",),
    ("driveline",),
    ("cases",),
    ("run",),
    ("reports",),
    ("studies",),
    ("cli",),
    ("__main__",),
)
LAYER_OF = {part: index for index, parts in enumerate(LAYERS) for part in parts}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def modules() -> dict[str, Path]:
    return {module_name(path): path for path in sorted(PACKAGE.rglob("*.py"))}


def imported_modules(name: str, path: Path, known: set[str]) -> set[str]:
    """Modules of sso that ``name`` imports (``from a import b`` counts ``a.b`` if a module)."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join([*anchor, base] if base else anchor)
            targets = [f"{base}.{alias.name}" if f"{base}.{alias.name}" in known else base
                       for alias in node.names]
        else:
            continue
        found.update(target for target in targets if target in known and target != name)
    return found


def import_graph() -> dict[str, set[str]]:
    found = modules()
    known = set(found)
    return {name: imported_modules(name, path, known) for name, path in found.items()}


def part(name: str) -> str | None:
    """``sso._shafts.series`` -> ``shafts``; ``sso._limits`` -> ``limits``; ``sso`` -> None."""
    pieces = name.split(".")
    if len(pieces) < 2:
        return None
    return pieces[1] if pieces[1].startswith("__") else pieces[1].removeprefix("_")


def test_every_part_has_a_layer():
    parts = {part(name) for name in modules()} - {None}
    assert parts == set(LAYER_OF), "put each new module or folder on a layer in LAYERS"


def test_imports_point_down():
    upward = []
    for name, targets in import_graph().items():
        source = part(name)
        if source is None:
            continue
        for target in targets:
            destination = part(target)
            if destination is None or destination == source:
                continue
            if LAYER_OF[destination] >= LAYER_OF[source]:
                upward.append(f"{name} -> {target}")
    assert upward == []


def test_no_module_imports_the_public_facade():
    """``import sso`` or ``from sso import X`` inside the package is an import of the top:
    it hides which module (and layer) a name comes from. Import the defining module."""
    importers = sorted(name for name, targets in import_graph().items()
                       if name != "sso" and "sso" in targets)
    assert importers == []


def test_no_import_cycle():
    graph = import_graph()
    state: dict[str, int] = {}
    stack: list[str] = []
    cycles = []

    def visit(node: str) -> None:
        state[node] = 1
        stack.append(node)
        for target in sorted(graph[node]):
            if state.get(target) == 1:
                cycles.append(" -> ".join([*stack[stack.index(target):], target]))
            elif target not in state:
                visit(target)
        stack.pop()
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node)
    assert cycles == []


def test_the_walk_sees_imports():
    """The checks above would pass on an empty graph; this one would not."""
    graph = import_graph()
    assert "sso._shafts.series" in graph["sso._shafts.optimise"]
    assert "sso._shafts.series" in graph["sso._studies.results"]  # a module-level import
    assert "sso._shafts.evaluation" in graph["sso._shafts.series"]  # inside a method
    assert "sso._cli.app" in graph["sso._cli"]
    assert len(graph) > 50


def test_the_walk_sees_the_facade_imported_anywhere(tmp_path):
    known = set(modules())
    for index, source in enumerate(("import sso\n",
                                    "def f():\n    from sso import ShaftSeries\n")):
        probe = tmp_path / f"probe_{index}.py"
        probe.write_text(source, encoding="utf-8")
        assert imported_modules("sso._column.probe", probe, known) == {"sso"}


def test_importing_sso_installs_no_import_hook():
    """No finder answers old module paths: ``import sso`` leaves ``sys.meta_path`` as is."""
    probe = ("import sys; before = list(sys.meta_path); import sso; "
             "print(len(before), len(sys.meta_path), sys.meta_path == before)")
    shown = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                           check=True, cwd=PACKAGE.parent).stdout.split()
    assert shown[2] == "True", shown
    assert int(shown[0]) > 0  # the interpreter's own finders were seen


def test_only_public_interfaces_of_python_and_scipy():
    # Issue 33: CPython's private _signal module and scipy's legacy fmin_slsqp are not
    # used; the public signal module and scipy.optimize.minimize are (records skipping
    # their constructors: tests/test_record.py).
    private_modules = {"_signal", "_thread", "_posixsubprocess"}
    found = []
    for name, path in modules().items():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                found += [(name, alias.name) for alias in node.names
                          if alias.name in private_modules]
            elif isinstance(node, ast.ImportFrom) and node.module in private_modules:
                found.append((name, node.module))
            elif isinstance(node, ast.Attribute) and node.attr == "fmin_slsqp":
                found.append((name, "fmin_slsqp"))
            elif isinstance(node, ast.alias) and node.name == "fmin_slsqp":
                found.append((name, "fmin_slsqp"))
    assert found == []
    assert len(modules()) > 100  # the walk saw the package
