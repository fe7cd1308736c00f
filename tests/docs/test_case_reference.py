"""The case-file reference is generated from the case schema, and agrees with the JSON Schema."""

from __future__ import annotations

import json

import pytest

from doctools import case_reference
from sso._cases import schema as case_schema
from sso._cases.json_schema import ordered_kinds, shipped_schema_text

KINDS = ordered_kinds()


@pytest.mark.parametrize("kind", KINDS)
def test_every_key_of_the_schema_is_on_the_page_and_in_the_json_schema(kind):
    labels = case_reference.key_labels(kind)
    shipped = json.loads(shipped_schema_text())
    assert sorted(labels) == sorted(case_reference.json_schema_labels(kind, shipped))
    table = case_reference.kind_table(kind, shipped)
    rows = [line for line in table.split("\n")[2:]]
    assert [row.split(" | ")[0].removeprefix("| ").strip("`") for row in rows] == labels
    for key, row in zip(case_schema.schema(kind), rows, strict=True):
        cells = [cell.strip() for cell in row.strip("|").split(" | ")]
        assert cells[2] == (key.unit or "-")
        assert cells[4] == key.allowed.replace("|", "\\|")


def test_the_page_has_one_section_per_kind():
    page = case_reference.page()
    for kind in KINDS:
        assert f'<a id="kind-{kind}"></a>' in page


def test_defaults_read_as_written_in_a_case_file():
    assert case_reference.default_text(case_schema.REQUIRED) == "**required**"
    assert case_reference.default_text(("ipopt", "slsqp")) == '`["ipopt", "slsqp"]`'
    assert case_reference.default_text(1e-12) == "`1e-12`"
    assert case_reference.default_text(None) == "none (optional)"
