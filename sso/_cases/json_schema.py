"""A JSON Schema of the case files, generated from the case-file schema itself.

Editors use it to check and complete case files as they are typed (see the README,
"Case files"). It is built from the :class:`~sso._cases.schema.Key` declarations of
every registered kind, so it cannot hold a second copy of the keys: names, tables,
types, ranges, list lengths, choices, defaults and which keys are required all come
from the engine. The engine (:func:`sso._cases.schema.load_case`) stays the primary
check: only it names lines, suggests the nearest key, and checks keys against each
other (phase counts, the crank-angle grid, that a linkage assembles).

A key's parser is a closure made by one of the engine's factories (``number``,
``whole_number``, ``choice``, ...); its range is read from the closure's variables.
The few parsers written as named functions (:data:`NAMED_PARSERS`) are translated
here from the constants they check against. A parser this module does not know
yields a schema that accepts any value, with the key's ``allowed`` text as its
description (:func:`opaque_keys` lists such keys).

Regenerate the shipped file with::

    python -m sso._cases.json_schema --output sso/_cases/case.schema.json

The schema declares draft 2020-12 but uses only keywords that mean the same in
draft 7 (no ``prefixItems``, no ``$ref`` beside other keywords), so validators and
editors that implement draft 7 only read it the same way.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable, Sequence
from importlib import resources
from typing import Any

from sso._cases.column_points import MAX_POINTS
from sso._cases.column_robust import MAX_POSITIONS
from sso._cases.driveline import MAX_POSITIONS as DRIVELINE_MAX_POSITIONS
from sso._cases.driveline import MEASUREMENT_PARSERS
from sso._cases.schema import (
    COMMON_KEYS,
    DEFAULT_KIND,
    NAME_PATTERN,
    REQUIRED,
    Key,
    case_kinds,
)
from sso._column.splines import MAX_TEETH
from sso._files import write_text_atomic
from sso._limits import INPUT_MAGNITUDE_RANGE
from sso._shafts.options import OPTION_NAMES

DRAFT = "https://json-schema.org/draft/2020-12/schema"
SHIPPED_NAME = "case.schema.json"
KIND_KEY = "kind"

JsonSchema = dict[str, Any]


def case_json_schema() -> JsonSchema:
    """The JSON Schema (draft 2020-12) of a case file of every registered kind.

    Returns
    -------
    dict
        The schema; ``kind`` picks the per-kind schema under ``$defs`` (a file
        without ``kind`` is a ``shaft_series`` case).
    """
    kinds = ordered_kinds()
    definitions = {kind: _kind_schema(kind) for kind in kinds}
    branches = []
    for kind in kinds:
        condition: JsonSchema = {"properties": {KIND_KEY: {"enum": [kind]}}}
        if kind != DEFAULT_KIND:
            condition["required"] = [KIND_KEY]
        branches.append({"if": condition, "then": {"$ref": f"#/$defs/{kind}"}})
    return {
        "$schema": DRAFT,
        "title": "sso case file",
        "description": "One design or analysis problem for the sso command (sso run CASE.toml). "
        "Generated from sso._cases.schema; sso validate gives line numbers "
        "and checks the keys against each other.",
        "type": "object",
        "properties": {KIND_KEY: _kind_key_schema(kinds)},
        "allOf": branches,
        "$defs": definitions,
    }


def ordered_kinds() -> list[str]:
    """Registered kinds, the default first, then alphabetical (independent of import order)."""
    return [DEFAULT_KIND, *sorted(kind for kind in case_kinds() if kind != DEFAULT_KIND)]


def opaque_keys(kind: str) -> list[str]:
    """Labels of the keys of ``kind`` whose parser this module cannot translate."""
    return [
        key.label
        for key in COMMON_KEYS + case_kinds()[kind].keys
        if key.label != KIND_KEY and _value_schema(key.parse) is None
    ]


def shipped_schema_text() -> str:
    """The schema file shipped in the package, as text."""
    return resources.files("sso._cases").joinpath(SHIPPED_NAME).read_text(encoding="utf-8")


def schema_text() -> str:
    """The schema as the shipped file holds it: indented JSON ending in a newline."""
    return json.dumps(case_json_schema(), indent=2, ensure_ascii=False) + "\n"


# ---------------------------------------------------------------- one kind


def _kind_key_schema(kinds: Sequence[str]) -> JsonSchema:
    result: JsonSchema = {
        "type": "string",
        "enum": list(kinds),
        "description": "what the file describes: a registered kind of case",
    }
    kind_key = next(key for key in COMMON_KEYS if key.label == KIND_KEY)
    if kind_key.default in kinds:
        result["default"] = kind_key.default
    return result


def _kind_schema(kind: str) -> JsonSchema:
    case_kind = case_kinds()[kind]
    keys = COMMON_KEYS + case_kind.keys
    top: JsonSchema = {
        "type": "object",
        "properties": {},
        "additionalProperties": False,
        "required": [],
    }
    tables: dict[str, JsonSchema] = {}
    for key in keys:
        if key.table:
            holder = tables.setdefault(
                key.table,
                {
                    "type": "object",
                    "properties": {},
                    "additionalProperties": False,
                    "required": [],
                },
            )
        else:
            holder = top
        holder["properties"][key.name] = (
            _kind_key_schema([kind]) if key.label == KIND_KEY else _key_schema(key)
        )
        if key.default is REQUIRED:
            holder["required"].append(key.name)
    for name, table in tables.items():
        top["properties"][name] = table
        if table["required"] and name not in case_kind.optional_tables:
            top["required"].append(name)
    for holder in (top, *tables.values()):
        if not holder["required"]:
            del holder["required"]
    return top


def _key_schema(key: Key) -> JsonSchema:
    described = f"{key.allowed} ({key.unit})" if key.unit else key.allowed
    value = _value_schema(key.parse)
    result: JsonSchema = dict(value) if value is not None else {}
    result["description"] = described
    if key.default is not REQUIRED and key.default is not None and not callable(key.default):
        result["default"] = _plain(key.default)
    return result


def _plain(value: Any) -> Any:
    if isinstance(value, tuple):
        return [_plain(item) for item in value]
    return value


# ---------------------------------------------------------------- parsers


def _closure(parse: Callable[..., Any]) -> dict[str, Any]:
    """The variables a factory's parser closes over (its declared range, choices, ...)."""
    cells = parse.__closure__ or ()
    return {
        name: cell.cell_contents
        for name, cell in zip(parse.__code__.co_freevars, cells, strict=True)
    }


def _factory(parse: Callable[..., Any]) -> str:
    """``number`` for a parser made by a factory ``number`` of a module of
    :mod:`sso._cases`; "" for any other parser."""
    module, qualified = str(getattr(parse, "__module__", "")), _qualified_name(parse)
    if not module.startswith("sso._cases.") or ".<locals>." not in qualified:
        return ""
    return qualified.split(".<locals>.")[0]


def _qualified_name(parse: Callable[..., Any]) -> str:
    return str(getattr(parse, "__qualname__", ""))


def _number(lower: float, upper: float, lower_open: bool, upper_open: bool) -> JsonSchema:
    """A number in the interval that is also 0 or of a magnitude in INPUT_MAGNITUDE_RANGE
    (the engine's :func:`sso._cases.schema.number` checks both)."""
    smallest, largest = INPUT_MAGNITUDE_RANGE
    result: JsonSchema = {"type": "number"}
    if lower > -largest:
        result["exclusiveMinimum" if lower_open else "minimum"] = lower
    else:
        result["minimum"] = -largest
    if upper < largest:
        result["exclusiveMaximum" if upper_open else "maximum"] = upper
    else:
        result["maximum"] = largest
    if lower < smallest and upper > -smallest:  # the interval reaches the tiny magnitudes
        result["not"] = {"allOf": [{"exclusiveMinimum": -smallest},
                                   {"exclusiveMaximum": smallest}, {"not": {"const": 0}}]}
    return result


def _pair(item: JsonSchema) -> JsonSchema:
    return {"type": "array", "items": item, "minItems": 2, "maxItems": 2}


# Parsers written as named functions, by module and name: what each accepts, built from
# the constants they check against.
# "mean" or a percentile "pNN" with 50 <= NN < 100 (sso._column.robust_phasing.LOWEST_PERCENTILE).
ROBUST_OBJECTIVE_PATTERN = r"^(mean|p[5-9][0-9](\.[0-9]+)?)$"

NAMED_PARSERS: dict[str, Callable[[], JsonSchema]] = {
    "sso._cases.schema.case_name": lambda: {
        "type": "string",
        "pattern": f"^{NAME_PATTERN.pattern}$",
    },
    "sso._cases.shaft_series.option_value": lambda: {
        "anyOf": [
            {"type": "integer", "enum": list(OPTION_NAMES)},
            {"type": "string", "enum": list(OPTION_NAMES.values())},
        ]
    },
    "sso._cases.mechanism.length_pair": lambda: _pair({"type": "number", "exclusiveMinimum": 0.0}),
    "sso._cases.mechanism.angle_pair": lambda: _pair(
        {"type": "number", "exclusiveMinimum": 0.0, "exclusiveMaximum": 180.0}
    ),
    "sso._cases.column_points.point_list": lambda: {
        "type": "array",
        "items": {"type": "array", "items": {"type": "number"}, "minItems": 3, "maxItems": 3},
        "minItems": 1,
        "maxItems": MAX_POINTS,
    },
    "sso._cases.column.teeth_list": lambda: {
        "type": "array",
        "items": {"type": "integer", "minimum": 1, "maximum": MAX_TEETH},
        "minItems": 1,
    },
    "sso._cases.units.confirmed_labels": lambda: {
        "type": "array",
        "items": {"type": "string"},
        "uniqueItems": True,
    },
    "sso._cases.column._rpm_range": lambda: _pair({"type": "number", "exclusiveMinimum": 0.0}),
    "sso._cases.column.yield_fraction": lambda: _number(0.0, 1.0, True, False),
    "sso._cases.column_robust.positions_table": lambda: {
        "type": "object",
        "minProperties": 2,
        "maxProperties": MAX_POSITIONS,
        "additionalProperties": NAMED_PARSERS["sso._cases.column_points.point_list"](),
    },
    "sso._cases.column_robust.position_weights": lambda: {
        "type": "object",
        "minProperties": 1,
        "additionalProperties": {"type": "number", "minimum": 0.0},
    },
    "sso._cases.column_robust.robust_objective": lambda: {
        "type": "string",
        "pattern": ROBUST_OBJECTIVE_PATTERN,
    },
    "sso._cases.driveline.bearing_pair": lambda: _pair(
        {"type": "number", "minimum": 0.0, "maximum": 1e5}),
    "sso._cases.driveline.positions_of_points": lambda: {
        "type": "object",
        "minProperties": 1,
        "maxProperties": DRIVELINE_MAX_POSITIONS,
        "additionalProperties": NAMED_PARSERS["sso._cases.column_points.point_list"](),
    },
    "sso._cases.driveline.positions_of_measurements": lambda: {
        "type": "object",
        "minProperties": 1,
        "maxProperties": DRIVELINE_MAX_POSITIONS,
        "additionalProperties": {
            "type": "object",
            "minProperties": 1,
            "properties": {name: _value_schema(parse)
                           for name, parse in MEASUREMENT_PARSERS.items()},
            "additionalProperties": False,
        },
    },
}


def _value_schema(parse: Callable[..., Any]) -> JsonSchema | None:
    """Schema of the values ``parse`` accepts, or None if its kind of parser is unknown."""
    named = NAMED_PARSERS.get(f"{getattr(parse, '__module__', '')}.{_qualified_name(parse)}")
    if named is not None:
        return named()
    try:
        return _factory_schema(_factory(parse), _closure(parse))
    except KeyError:  # a factory whose closure no longer holds the names read here
        return None


def _factory_schema(factory: str, values: dict[str, Any]) -> JsonSchema | None:
    """Schema of a parser made by ``sso._cases.schema.<factory>`` closing over ``values``."""
    if factory == "number":
        return _number(values["lower"], values["upper"], values["lower_open"], values["upper_open"])
    if factory == "whole_number":
        return {
            "type": "integer",
            "minimum": values["lower"],
            "maximum": values["upper"],
        }
    if factory == "choice":
        return {"type": "string", "enum": list(values["allowed"])}
    if factory == "text":
        return {"type": "string", "maxLength": values["max_length"]}
    if factory == "choice_list":
        return {
            "type": "array",
            "items": {"type": "string", "enum": list(values["allowed"])},
            "minItems": 1,
            "uniqueItems": True,
        }
    if factory == "number_list":
        item = _value_schema(values["item"])
        if item is None:
            return None
        return {
            "type": "array",
            "items": item,
            "minItems": values["min_length"],
            "maxItems": values["max_length"],
        }
    if factory == "bounds_list":
        pair = _pair(_number(values["lower"], values["upper"], False, values["upper_open"]))
        return {"anyOf": [pair, {"type": "array", "items": pair, "minItems": 1}]}
    if factory == "_one_or_list":
        items = _value_schema(values["items"])
        if items is None:
            return None
        return {"anyOf": [items["items"], items]}
    return None


# ---------------------------------------------------------------- command


def main(arguments: Sequence[str] | None = None) -> int:
    """Print the schema, or write it atomically with ``--output PATH``; returns 0."""
    parser = argparse.ArgumentParser(
        prog="python -m sso._cases.json_schema",
        description="Print the JSON Schema of sso case files (generated from sso._cases.schema).",
    )
    parser.add_argument(
        "--output",
        metavar="PATH",
        help="write the schema to PATH atomically instead of printing it",
    )
    options = parser.parse_args(arguments)
    text = schema_text()
    if options.output:
        write_text_atomic(options.output, text)
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
