"""Old module paths of v0.1, kept working for one release with a DeprecationWarning.

v0.2 moved the modules into one folder per idea (see ``docs/architecture.md``).
``import sso`` installs :class:`MovedModuleFinder`, which answers an old path such as
``sso.series`` with a thin module that forwards every name to its new home and warns
once, naming that home.
"""

from __future__ import annotations

import importlib.abc
import importlib.machinery
import sys
import types
import warnings
from collections.abc import Sequence
from importlib import import_module
from typing import Any

# Old module path -> new module path; None marks a former package (its modules moved).
MOVED: dict[str, str | None] = {
    "sso.series": "sso.shafts.series",
    "sso.evaluation": "sso.shafts.evaluation",
    "sso.optimisation": "sso.shafts.optimise",
    "sso.mechanisms": "sso.linkages.mechanisms",
    "sso.mechanism_table": "sso.linkages.table",
    "sso.design": None,
    "sso.design.objective": "sso.shafts.objective",
    "sso.design.quadrature": "sso.shafts.quadrature",
    "sso.design.options": "sso.shafts.options",
    "sso.design.starts": "sso.solvers.starts",
    "sso.design.nlp": "sso.solvers.nlp",
    "sso.design.fourbar_swing": "sso.linkages.fourbar_swing",
    "sso.io": None,
    "sso.io.atomic": "sso.files",
    "sso.io.case": "sso.cases.schema",
    "sso.io.mechanism_case": "sso.cases.mechanism",
    "sso.io.document": "sso.run.document",
    "sso.io.mechanism_document": "sso.run.mechanism_document",
    "sso.io.report": "sso.reports.writer",
    "sso.io.curves": "sso.reports.curves",
    "sso.io.html": "sso.reports.html",
    "sso.io.markdown": "sso.reports.markdown",
    "sso.io.mechanism_plots": "sso.reports.mechanism_plots",
    "sso.io.mechanism_report": "sso.reports.mechanism_report",
    "sso.io.plots": "sso.reports.plots",
    "sso.io.speeds": "sso.reports.speeds",
    "sso.io.summary": "sso.reports.summary",
    "sso.batch.command": "sso.cli.batch_commands",
    "sso.batch.tolerance": "sso.batch.tolerance_study",
}
# Names that changed with their module: old path -> {old name: new name}.
RENAMED = {"sso.batch.tolerance": {"tolerance": "tolerance_study"}}
# Names that left the module the old path now points to: old path -> {name: module}.
SPLIT = {"sso.io.case": {name: "sso.cases.shaft_series" for name in (
    "Case", "SHAFT_SERIES_KEYS", "TOLERANCE_ARGUMENTS", "option_value")}}


class MovedModuleFinder(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds and loads the old module paths listed in :data:`MOVED`."""

    def find_spec(self, fullname: str, path: Sequence[str] | None = None,
                  target: types.ModuleType | None = None) -> importlib.machinery.ModuleSpec | None:
        if fullname not in MOVED:
            return None
        return importlib.machinery.ModuleSpec(fullname, self,
                                              is_package=MOVED[fullname] is None)

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> types.ModuleType:
        new_name = MOVED[spec.name]
        module = types.ModuleType(spec.name)
        if new_name is None:
            module.__path__ = []
            return module
        _warn(f"{spec.name} is deprecated and will be removed in the next release; "
              f"import from {new_name} (or the names exported by sso)")
        target = import_module(new_name)
        renamed = RENAMED.get(spec.name, {})
        split = SPLIT.get(spec.name, {})

        def forward(name: str) -> Any:
            if name in split:
                return getattr(import_module(split[name]), name)
            return getattr(target, renamed.get(name, name))

        # Through the module's namespace: ModuleType declares neither attribute (PEP 562
        # looks ``__getattr__`` up there).
        namespace = vars(module)
        namespace["__getattr__"] = forward
        namespace["__all__"] = list(getattr(target, "__all__", [name for name in vars(target)
                                                                if not name.startswith("_")]))
        return module

    def exec_module(self, module: types.ModuleType) -> None:
        """Nothing to run: the module forwards to its new home."""


def _warn(message: str) -> None:
    # Blame the import line: the first frame outside this file. ``warnings`` itself
    # skips the import machinery's frames, so they are not counted.
    frame: types.FrameType | None = sys._getframe(0)
    level = 1
    while frame is not None and (frame.f_code.co_filename.startswith("<frozen")
                                 or frame.f_code.co_filename == __file__):
        if not frame.f_code.co_filename.startswith("<frozen"):
            level += 1
        frame = frame.f_back
    warnings.warn(message, DeprecationWarning, stacklevel=level)


def install() -> None:
    """Put the finder first on ``sys.meta_path``, once.

    First, so that no other finder (an editable install of an older checkout, say)
    answers an old path; it answers nothing but the paths in :data:`MOVED`.
    """
    if not any(isinstance(finder, MovedModuleFinder) for finder in sys.meta_path):
        sys.meta_path.insert(0, MovedModuleFinder())
