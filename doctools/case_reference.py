"""The case-file reference page, generated from the case schema.

Every key of every registered kind comes from :func:`sso._cases.schema.schema`
(its table, name, unit, default and allowed values); the JSON type of each key comes
from the JSON Schema that :mod:`sso._cases.json_schema` generates from that same
schema. Nothing here lists a key by hand, so a key added to the engine appears on
the page at the next build.
"""

from __future__ import annotations

import json
from typing import Any

from sso._cases import schema as case_schema
from sso._cases.json_schema import case_json_schema, ordered_kinds

KIND_TITLES = {
    "shaft_series": "Shaft series (`kind = \"shaft_series\"`, the default)",
    "column": "Steering column from hardpoints (`kind = \"column\"`)",
    "fourbar": "Four-bar analysis (`kind = \"fourbar\"`)",
    "fourbar_design": "Four-bar design (`kind = \"fourbar_design\"`)",
    "quick_return": "Quick-return analysis (`kind = \"quick_return\"`)",
    "slider_crank": "Slider-crank analysis (`kind = \"slider_crank\"`)",
}


def key_labels(kind: str) -> list[str]:
    """Dotted labels of every key a case of ``kind`` accepts, in schema order."""
    return [key.label for key in case_schema.schema(kind)]


def json_schema_labels(kind: str, document: dict[str, Any] | None = None) -> list[str]:
    """Dotted labels of the keys the JSON Schema of ``kind`` declares (deprecated ones left out)."""
    document = case_json_schema() if document is None else document
    labels = []
    for name, entry in document["$defs"][kind]["properties"].items():
        if entry.get("type") == "object" and "properties" in entry:
            labels.extend(f"{name}.{inner}" for inner, value in entry["properties"].items()
                          if not value.get("deprecated"))
        else:
            labels.append(name)
    return labels


def _json_entry(document: dict[str, Any], kind: str, label: str) -> dict[str, Any]:
    properties = document["$defs"][kind]["properties"]
    if "." in label:
        table, name = label.split(".", 1)
        entry: dict[str, Any] = properties[table]["properties"][name]
        return entry
    top: dict[str, Any] = properties[label]
    return top


def json_type(entry: dict[str, Any]) -> str:
    """A short type name of one JSON Schema entry: ``number``, ``list of number``, ..."""
    if "anyOf" in entry:
        return " or ".join(dict.fromkeys(json_type(option) for option in entry["anyOf"]))
    kind = entry.get("type")
    if kind == "array":
        items = entry.get("items")
        return f"list of {json_type(items)}" if isinstance(items, dict) else "list"
    if kind == "object":
        return "table"
    if kind is None:
        return "any" if "enum" not in entry else "one of the choices"
    return str(kind)


def default_text(default: Any) -> str:
    """How a key's default reads in the table."""
    if default is case_schema.REQUIRED:
        return "**required**"
    if default is None:
        return "none (optional)"
    if callable(default):
        return "from other keys (see allowed)"
    if isinstance(default, tuple):
        default = list(default)
    return f"`{json.dumps(default)}`"


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def kind_table(kind: str, document: dict[str, Any]) -> str:
    """The Markdown table of every key of ``kind``."""
    lines = ["| key | type | unit | default | allowed |", "| --- | --- | --- | --- | --- |"]
    for key in case_schema.schema(kind):
        entry = _json_entry(document, kind, key.label)
        lines.append("| " + " | ".join([
            f"`{key.label}`", _cell(json_type(entry)), _cell(key.unit or "-"),
            _cell(default_text(key.default)), _cell(key.allowed)]) + " |")
    return "\n".join(lines)


def page() -> str:
    """The whole case-file reference page, Markdown."""
    document = case_json_schema()
    parts = [
        "# Case-file reference",
        "",
        "This page is generated from the case schema (`sso/_cases/schema.py`) each time the",
        "site is built, with each key's type taken from the JSON Schema generated from the",
        "same declarations (`sso/_cases/case.schema.json`). A test checks that every key of",
        "the schema appears here and in the JSON Schema, and no other.",
        "",
        "A case file is TOML. `kind` selects the table below; a file without `kind` is a",
        "shaft series. A key `table.name` is written `name = ...` under `[table]`.",
        "An unknown key is refused with the nearest valid key suggested; a value out of",
        "range is refused naming the key, the value, the allowed range and the line",
        "(`sso validate CASE.toml` checks a file without solving it).",
        "",
    ]
    for kind in ordered_kinds():
        parts += [f"## {KIND_TITLES.get(kind, f'`kind = {kind!r}`')}", "",
                  f"<a id=\"kind-{kind}\"></a>", "", kind_table(kind, document), ""]
    parts += [
        "## Editor support",
        "",
        "The package ships the JSON Schema of every kind, `sso/_cases/case.schema.json`",
        "(regenerate it with `python -m sso._cases.json_schema --output",
        "sso/_cases/case.schema.json`; a test fails when it drifts). Taplo and the editors",
        "that run it check a case file against it when the file's first line is the",
        "comment `#:schema PATH`. `sso validate` stays the full check: line numbers,",
        "\"did you mean\" and the checks between keys.",
        "",
    ]
    return "\n".join(parts)
