"""The published JSON Schema of case files: generated, shipped, and in step with the engine.

The engine (``sso._cases.schema``) is the reference: every verdict of the JSON Schema
is compared with the engine's own verdict on the same value, never with a copy of
the ranges written here.
"""

from __future__ import annotations

import json
import tomllib
from pathlib import Path
from typing import Any

import jsonschema
import pytest

from sso._cases import json_schema
from sso._cases.schema import COMMON_KEYS, CaseError, Key, case_kinds, parse_case

ROOT = Path(__file__).resolve().parents[2]
SHIPPED_CASES = sorted((ROOT / "cases").glob("*.toml")) + sorted(
    (ROOT / "cases" / "mechanisms").glob("*.toml")
)
VALIDATORS = (jsonschema.Draft202012Validator, jsonschema.Draft7Validator)
KNOWN_KINDS = (
    "shaft_series",
    "column",
    "driveline",
    "fourbar",
    "slider_crank",
    "quick_return",
    "fourbar_design",
)


@pytest.fixture(scope="module")
def schema() -> dict[str, Any]:
    return json.loads(json_schema.shipped_schema_text())


def test_shipped_file_equals_a_fresh_generation():
    # If this fails, regenerate:
    #   python -m sso._cases.json_schema --output sso/_cases/case.schema.json
    assert json_schema.shipped_schema_text() == json_schema.schema_text()
    on_disk = (ROOT / "sso" / "_cases" / json_schema.SHIPPED_NAME).read_text(encoding="utf-8")
    assert on_disk == json_schema.schema_text()


def test_the_command_writes_the_same_text(tmp_path, capsys):
    target = tmp_path / "case.schema.json"
    assert json_schema.main(["--output", str(target)]) == 0
    assert target.read_text(encoding="utf-8") == json_schema.schema_text()
    assert [path.name for path in tmp_path.iterdir()] == ["case.schema.json"]
    assert json_schema.main([]) == 0
    assert capsys.readouterr().out == json_schema.schema_text()


@pytest.mark.parametrize("validator", VALIDATORS, ids=lambda item: item.__name__)
def test_schema_is_valid_under_its_draft_and_under_draft_7(schema, validator):
    validator.check_schema(schema)
    assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"


def test_every_registered_kind_and_key_is_in_the_schema(schema):
    assert schema["properties"]["kind"]["enum"] == json_schema.ordered_kinds()
    assert set(KNOWN_KINDS) <= set(case_kinds())
    for kind, case_kind in case_kinds().items():
        definition = schema["$defs"][kind]
        for key in COMMON_KEYS + case_kind.keys:
            holder = definition["properties"][key.table] if key.table else definition
            assert key.name in holder["properties"], f"{kind}: {key.label}"


@pytest.mark.parametrize("kind", KNOWN_KINDS)
def test_every_key_of_the_shipped_kinds_has_a_typed_schema(kind):
    assert json_schema.opaque_keys(kind) == []


@pytest.mark.parametrize("path", SHIPPED_CASES, ids=lambda path: path.name)
@pytest.mark.parametrize("validator", VALIDATORS, ids=lambda item: item.__name__)
def test_every_shipped_case_validates(schema, validator, path):
    document = tomllib.loads(path.read_text(encoding="utf-8"))
    errors = [error.message for error in validator(schema).iter_errors(document)]
    assert errors == []


def test_there_are_shipped_cases_of_every_kind():
    kinds = {
        tomllib.loads(path.read_text(encoding="utf-8")).get("kind", "shaft_series")
        for path in SHIPPED_CASES
    }
    assert kinds == set(KNOWN_KINDS)
    assert len(SHIPPED_CASES) >= 17


SHAFT_CASE = {"design": {"beta_deg": [30.0, 40.0, 40.0], "phase_deg": [90.0, 90.0]}}
FOURBAR_CASE = {
    "kind": "fourbar",
    "linkage": {"ground": 7.0, "crank": 3.0, "coupler": 8.0, "rocker": 5.0},
}

# (what is broken, the case, where in the document the JSON Schema should point)
BROKEN = [
    ("misspelt key", {**SHAFT_CASE, "solver": {"strats": 4}}, ["solver"]),
    (
        "beta at the 90 deg limit",
        {"design": {"beta_deg": [30.0, 90.0]}},
        ["design", "beta_deg", 1],
    ),
    ("no starts", {**SHAFT_CASE, "solver": {"starts": 0}}, ["solver", "starts"]),
    ("unknown model", {**SHAFT_CASE, "model": "fast"}, ["model"]),
    ("unknown table", {**SHAFT_CASE, "solvers": {"starts": 4}}, []),
    ("required table missing", {"model": "exact"}, []),
    ("option out of range", {**SHAFT_CASE, "option": 4}, ["option"]),
    (
        "format named twice",
        {**SHAFT_CASE, "output": {"formats": ["json", "json"]}},
        ["output", "formats"],
    ),
    ("name with a slash", {**SHAFT_CASE, "name": "../escape"}, ["name"]),
    (
        "text for a number",
        {**SHAFT_CASE, "input_speed_rpm": "fast"},
        ["input_speed_rpm"],
    ),
    (
        "$schema key (the engine refuses it)",
        {**SHAFT_CASE, "$schema": "case.schema.json"},
        [],
    ),
    ("unknown kind", {**SHAFT_CASE, "kind": "gearbox"}, ["kind"]),
    (
        "negative crank",
        {**FOURBAR_CASE, "linkage": {**FOURBAR_CASE["linkage"], "crank": -3.0}},
        ["linkage", "crank"],
    ),
    ("shaft-series key in a four-bar case", {**FOURBAR_CASE, "model": "exact"}, []),
    ("four-bar without its linkage", {"kind": "fourbar"}, []),
]


@pytest.mark.parametrize("what, document, where", BROKEN, ids=[item[0] for item in BROKEN])
def test_broken_cases_are_rejected_by_the_schema_and_by_the_engine(schema, what, document, where):
    with pytest.raises(CaseError):
        parse_case(document, "broken.toml")
    for validator in VALIDATORS:
        errors = list(validator(schema).iter_errors(document))
        assert errors, f"{validator.__name__} accepted: {what}"
        deepest = max(errors, key=lambda error: len(error.absolute_path))
        leaves = [leaf for error in errors for leaf in _leaf_errors(error)]
        assert any(list(leaf.absolute_path) == where for leaf in leaves + [deepest]), (
            what,
            [list(leaf.absolute_path) for leaf in leaves],
        )


def _leaf_errors(error: jsonschema.ValidationError) -> list[jsonschema.ValidationError]:
    if not error.context:
        return [error]
    return [leaf for child in error.context for leaf in _leaf_errors(child)]


def test_the_good_cases_of_the_broken_list_are_accepted(schema):
    for document in (SHAFT_CASE, FOURBAR_CASE):
        parse_case(document, "good.toml")
        for validator in VALIDATORS:
            assert list(validator(schema).iter_errors(document)) == []


# Values tried on every key; the engine's parser and the key's JSON Schema must agree
# on each (cross-key checks such as lower <= upper are the engine's alone).
PROBES: list[Any] = [
    0,
    1,
    2,
    3,
    4,
    64,
    100,
    10_000,
    10_001,
    1_000_000,
    1_000_001,
    2**63 - 1,
    2**63,
    -1,
    0.0,
    0.5,
    1.0,
    45.0,
    89.999,
    90.0,
    179.0,
    180.0,
    360.0,
    360.5,
    -360.0,
    -360.5,
    3600.0,
    3600.5,
    -3600.5,
    1e300,
    -1e300,
    1e-20,
    True,
    None,
    "",
    "exact",
    "paper",
    "phase",
    "both",
    "ipopt",
    "slsqp",
    "json",
    "png",
    "pdf",
    "open",
    "crossed",
    "mark",
    "normal",
    "uniform",
    "mm",
    "a" * 21,
    "a" * 201,
    "ok_name-1.0",
    "-bad",
    "a" * 100,
    "a" * 101,
    [],
    [30.0],
    [0.0, 40.0],
    [10.0, 10.0],
    [0.0, 90.0],
    [-360.0, 360.0],
    [0.5, 179.5],
    [[0.0, 40.0], [10.0, 20.0]],
    [[0.0, 90.0]],
    [1.0] * 64,
    [1.0] * 65,
    [5.0] * 100,
    [5.0] * 101,
    ["json"],
    ["json", "json"],
    ["ipopt", "slsqp"],
    ["pdf"],
    [50.0, 101.0],
    [0.5, 0.0],
    [0.5, 0.0, 1.0],
    ["a"],
    [True],
]


def _engine_accepts(key: Key, value: Any) -> bool:
    try:
        key.parse(key.label, value)
    except ValueError:
        return False
    return True


def _key_schema(schema: dict[str, Any], kind: str, key: Key) -> dict[str, Any]:
    definition = schema["$defs"][kind]
    holder = definition["properties"][key.table] if key.table else definition
    return holder["properties"][key.name]


def _is_integer_schema(subschema: dict[str, Any]) -> bool:
    return '"integer"' in json.dumps(subschema)


@pytest.mark.parametrize("kind", KNOWN_KINDS)
def test_each_key_schema_agrees_with_the_engine_parser(schema, kind):
    disagreements = []
    checked = 0
    for key in COMMON_KEYS + case_kinds()[kind].keys:
        if key.label == "kind":
            continue
        subschema = _key_schema(schema, kind, key)
        validator = jsonschema.Draft202012Validator(subschema)
        for value in PROBES:
            engine = _engine_accepts(key, value)
            published = validator.is_valid(value)
            checked += 1
            if engine == published:
                continue
            # JSON Schema counts 1.0 as an integer (draft 6 on); TOML and the engine do not.
            if _is_integer_schema(subschema) and _has_integral_float(value):
                continue
            if _inverted_pairs(value):
                continue
            disagreements.append((key.label, value, engine, published))
    assert disagreements == []
    assert checked > 500


def _has_integral_float(value: Any) -> bool:
    if isinstance(value, list):
        return any(_has_integral_float(item) for item in value)
    return isinstance(value, float) and value.is_integer()


def _inverted_pairs(value: Any) -> bool:
    """A [lower, upper] pair with lower > upper: only the engine refuses it."""
    pairs = value if value and isinstance(value, list) and isinstance(value[0], list) else [value]
    return any(
        isinstance(pair, list)
        and len(pair) == 2
        and all(isinstance(item, float) for item in pair)
        and pair[0] > pair[1]
        for pair in pairs
    )


def test_schema_ships_as_package_data_and_taplo_config_points_at_it():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    assert "_cases/case.schema.json" in project["tool"]["setuptools"]["package-data"]["sso"]
    assert "jsonschema>=4.18" in project["project"]["optional-dependencies"]["test"]
    taplo = tomllib.loads((ROOT / ".taplo.toml").read_text(encoding="utf-8"))
    (rule,) = taplo["rule"]
    assert rule["include"] == ["cases/**/*.toml"]
    assert (ROOT / rule["schema"]["path"]).resolve() == (
        ROOT / "sso" / "_cases" / json_schema.SHIPPED_NAME
    )


def test_the_schema_accepts_lm_for_a_shaft_series_only(schema):
    lm_case = {**SHAFT_CASE, "solver": {"solvers": ["lm"]}}
    parse_case(lm_case, "lm.toml")
    column = {"kind": "column", "hardpoints": {"points_mm": [
        [-950.0, 360.0, 780.0], [-717.9, 296.7, 569.0], [-614.1, 263.4, 333.0],
        [-599.9, 285.3, 215.8]]}, "solver": {"solvers": ["lm"]}}
    with pytest.raises(CaseError, match="solver.solvers"):
        parse_case(column, "column.toml")
    for validator in VALIDATORS:
        assert list(validator(schema).iter_errors(lm_case)) == []
        assert list(validator(schema).iter_errors(column)) != []
    # "lm" with the paper model is a check between keys: the engine's alone.
    paper = {**lm_case, "model": "paper"}
    with pytest.raises(CaseError, match="model = 'paper' allows 'ipopt', 'slsqp'"):
        parse_case(paper, "paper.toml")
