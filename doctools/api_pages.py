"""The API reference pages: one page for every name in ``sso.__all__``.

Each page holds a mkdocstrings directive for the object where it is defined (the
package re-exports its names lazily, so the static loader is pointed at the
defining module), and the index groups the names by kind. ``missing_docstrings``
is the check the build and the tests share: a public name without a docstring of
its own fails both.
"""

from __future__ import annotations

import inspect
from dataclasses import dataclass
from typing import Any

import sso

API_FOLDER = "reference/api"


@dataclass(frozen=True)
class PublicName:
    """One name of ``sso.__all__`` and where its documentation lives.

    Attributes
    ----------
    name : str
        The name as ``sso.<name>``.
    target : str
        Dotted path of the defining object, for mkdocstrings.
    kind : str
        ``"function"``, ``"class"``, ``"warning"`` or ``"data"``.
    """

    name: str
    target: str
    kind: str

    @property
    def page(self) -> str:
        """Path of the page inside the docs folder."""
        return f"{API_FOLDER}/{self.name.strip('_') or self.name}.md"


def _data_module(name: str) -> str:
    """Module that assigns the data name ``name`` (a constant such as ``SOLVERS``)."""
    if name == "__version__":
        return "sso"
    exports: dict[str, Any] = getattr(sso, "_EXPORTS", {})
    where = exports.get(name)
    if isinstance(where, tuple):
        return str(where[0])
    if isinstance(where, str):
        return where
    raise LookupError(f"sso.{name}: cannot tell which module defines it")


def public_names() -> list[PublicName]:
    """Every name of ``sso.__all__`` with its defining object, in ``__all__`` order."""
    names = []
    for name in sso.__all__:
        value = getattr(sso, name)
        if inspect.isclass(value):
            kind = "warning" if issubclass(value, Warning) else "class"
            target = f"{value.__module__}.{value.__qualname__}"
        elif inspect.isfunction(value):
            kind = "function"
            target = f"{value.__module__}.{value.__qualname__}"
        else:
            kind = "data"
            target = f"{_data_module(name)}.{name}"
        names.append(PublicName(name, target, kind))
    return names


def missing_docstrings() -> list[str]:
    """Public names (and public methods of public classes) without a docstring of their own."""
    missing = []
    for public in public_names():
        value = getattr(sso, public.name)
        if public.kind == "data":
            continue  # documented by the attribute docstring beside its assignment
        if not (value.__doc__ or "").strip():
            missing.append(f"sso.{public.name}")
        if public.kind != "class":
            continue
        for attribute, member in vars(value).items():
            if attribute.startswith("_"):
                continue
            function = member.fget if isinstance(member, property) else member
            if isinstance(function, staticmethod | classmethod):
                function = function.__func__
            if inspect.isfunction(function) and not (function.__doc__ or "").strip():
                missing.append(f"sso.{public.name}.{attribute}")
    return missing


KIND_HEADINGS = {
    "function": "Functions",
    "class": "Classes (results and models)",
    "warning": "Warnings",
    "data": "Constants",
}


def page(public: PublicName) -> str:
    """The Markdown page of one public name."""
    return "\n".join([
        f"# sso.{public.name}",
        "",
        f"Defined in `{public.target.rsplit('.', 1)[0]}`; import it as `sso.{public.name}`.",
        "",
        f"::: {public.target}",
        "    options:",
        "      show_root_heading: false",
        "      show_root_toc_entry: false",
        "",
    ])


def index_page() -> str:
    """The API reference index: every public name, grouped by kind, one line each."""
    names = public_names()
    parts = [
        "# API reference",
        "",
        "Every public name of the `sso` package (`sso.__all__`), generated from the",
        "docstrings at each build (numpy docstring style). Import the package and use",
        "the names from it: `import sso; sso.optimise(...)`. Modules not listed here",
        "are internal and may change without notice.",
        "",
    ]
    for kind, heading in KIND_HEADINGS.items():
        members = [public for public in names if public.kind == kind]
        if not members:
            continue
        parts += [f"## {heading}", "", "| name | summary |", "| --- | --- |"]
        for public in members:
            link = public.page.removeprefix(API_FOLDER + "/")
            parts.append(f"| [`sso.{public.name}`]({link}) | {_summary(public)} |")
        parts.append("")
    return "\n".join(parts)


def _summary(public: PublicName) -> str:
    if public.kind == "data":
        return f"constant: `{getattr(sso, public.name)!r}`"
    doc = inspect.getdoc(getattr(sso, public.name)) or ""
    first = doc.strip().split("\n\n")[0].replace("\n", " ")
    return first.replace("|", "\\|")
