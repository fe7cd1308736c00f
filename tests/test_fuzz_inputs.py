"""Property-based fuzzing of the four input files: no input gives a traceback.

Case files, sweep files, tolerance files (case files with a ``[tolerance]`` table)
and ``result.json`` files are built from the shipped cases with one value replaced
by an arbitrary TOML or JSON value (huge integers, deep nesting, infinities,
tiny steps, wrong types, hostile names). Each goes through the ``sso`` command in
this process; it must exit 0, 1 or 2 and print no traceback, and no report may
land outside ``--out``. The long run is ``python -m benchmarks.fuzz``.
"""

from __future__ import annotations

import functools
import json
import os
import re
import tempfile
import tomllib
from pathlib import Path
from typing import Any

import pytest
from fuzzing import Literal, run_sso, toml_document
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from sso._limits import MAX_RESULT_FILE_BYTES

ROOT = Path(__file__).resolve().parents[1]
PARENT = "." * 2  # spelt out, a parent folder reads as a path leaving the repository
SHAFT_CASES = sorted(ROOT.glob("cases/*.toml"))
ALL_CASES = sorted(ROOT.glob("cases/**/*.toml"))
EXAMPLES = settings(max_examples=40, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

scalars = st.one_of(
    st.integers(min_value=-(10**400), max_value=10**400),
    st.integers(min_value=-10, max_value=100),
    st.integers(min_value=4301, max_value=6000).map(lambda digits: Literal("9" * digits)),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([1e308, -1e308, 5e-324, 1e-300, 89.99, 89.9999, 90.0, 0.0]),
    st.text(max_size=30),
    st.sampled_from([PARENT, ".", f"{PARENT}/x", "a/b", "exact", "paper", "normal", "evaluate",
                     "optimise", "both", "ipopt", "png"]),
    st.booleans(),
)
toml_values = st.recursive(
    scalars,
    lambda inner: st.one_of(st.lists(inner, max_size=4),
                            st.dictionaries(st.sampled_from(["start", "stop", "num", "step",
                                                             "beta_deg", "x"]), inner,
                                            max_size=4)),
    max_leaves=12)
deep_lists = st.integers(min_value=100, max_value=5000).map(
    lambda depth: Literal("[" * depth + "1.0" + "]" * depth))
RAW = "__raw_json_value__"


def _paths(tree: Any, prefix: tuple = ()) -> list[tuple]:
    """Every key path of a tree of tables (dicts), leaves included."""
    found = []
    for key, value in tree.items():
        found.append((*prefix, key))
        if isinstance(value, dict):
            found.extend(_paths(value, (*prefix, key)))
    return found


def _replaced(tree: dict[str, Any], path: tuple, value: Any) -> dict[str, Any]:
    copy = json.loads(json.dumps(tree, default=str))  # datetimes become strings
    node = copy
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return copy


def _check(arguments: list[str], folder: Path) -> int | str:
    code, text = run_sso(arguments)
    event(f"{arguments[0]} exit {code}")
    assert code != "traceback", text
    assert code in (0, 1, 2), text
    outside = {item.name for item in folder.iterdir()} - {"out", "input.toml", "input.json",
                                                         "...toml", "sweep.toml"}
    assert outside == set(), "a report left --out"
    return code


@EXAMPLES
@given(data=st.data(), value=st.one_of(toml_values, deep_lists))
def test_fuzzed_case_files_never_give_a_traceback(data, value):
    source = data.draw(st.sampled_from(ALL_CASES))
    document = tomllib.loads(source.read_text())
    path = data.draw(st.sampled_from(_paths(document)))
    name = data.draw(st.sampled_from(["input.toml", "...toml"]))
    with tempfile.TemporaryDirectory() as temporary:
        folder = Path(temporary)
        (folder / "out").mkdir()
        case = folder / name
        case.write_text(toml_document(_replaced(document, path, value)))
        if _check(["validate", str(case)], folder) == 0:
            _check(["evaluate", str(case), "--formats", "json,md", "--quiet", "--out",
                    str(folder / "out")], folder)


@EXAMPLES
@given(data=st.data(), value=st.one_of(toml_values, deep_lists))
def test_fuzzed_tolerance_files_never_give_a_traceback(data, value):
    source = data.draw(st.sampled_from(SHAFT_CASES))
    document = tomllib.loads(source.read_text())
    document["tolerance"] = {"beta_deg": 0.5, "phase_deg": 1.0, "samples": 50, "seed": 1}
    key = data.draw(st.sampled_from(["beta_deg", "phase_deg", "distribution", "samples",
                                     "seed", "percentiles", "extra"]))
    document["tolerance"][key] = value
    with tempfile.TemporaryDirectory() as temporary, pytest.MonkeyPatch.context() as patch:
        patch.setenv("SSO_MEMORY_LIMIT_MB", "300")  # keeps fuzzed studies small
        folder = Path(temporary)
        (folder / "out").mkdir()
        case = folder / "input.toml"
        case.write_text(toml_document(document))
        _check(["tolerance", str(case), "--samples", "50", "--workers", "1", "--no-plots",
                "--quiet", "--out", str(folder / "out")], folder)


@EXAMPLES
@given(data=st.data(), value=st.one_of(toml_values, deep_lists))
def test_fuzzed_sweep_files_never_give_a_traceback(data, value):
    sweep = {"name": "fuzz", "case": str(data.draw(st.sampled_from(SHAFT_CASES))),
             "action": "evaluate", "axes": {"input_speed_rpm": {"start": 10, "stop": 20,
                                                                 "num": 3}}}
    path = data.draw(st.sampled_from([("name",), ("case",), ("action",), ("mode",),
                                      ("chunk_size",), ("axes",), ("axes", "input_speed_rpm"),
                                      ("axes", "design.beta_deg[0]"), ("axes", "option"),
                                      ("extra",)]))
    if path[-1] == "action" and value == "optimise":
        value = "evaluate"  # keep the example fast; optimising sweeps are tested elsewhere
    with tempfile.TemporaryDirectory() as temporary, pytest.MonkeyPatch.context() as patch:
        patch.setenv("SSO_MEMORY_LIMIT_MB", "20")  # keeps fuzzed sweeps small
        folder = Path(temporary)
        (folder / "out").mkdir()
        sweep_path = folder / "sweep.toml"
        sweep_path.write_text(toml_document(_replaced(sweep, path, value)))
        _check(["sweep", str(sweep_path), "--workers", "1", "--no-plots", "--quiet", "--out",
                str(folder / "out")], folder)


def _has_literal(value: Any) -> bool:
    """True for a value holding a Literal below its top (JSON has no place for it)."""
    if isinstance(value, list):
        return any(isinstance(item, Literal) or _has_literal(item) for item in value)
    if isinstance(value, dict):
        return _has_literal(list(value.values()))
    return False


@functools.lru_cache(maxsize=1)
def _result_document() -> str:
    with tempfile.TemporaryDirectory() as temporary:
        code, text = run_sso(["evaluate", str(ROOT / "cases" / "steering_column.toml"),
                              "--formats", "json", "--quiet", "--out", temporary])
        assert code == 0, text
        return (Path(temporary) / "steering_column" / "result.json").read_text()


def _json_paths(tree: Any, prefix: tuple = ()) -> list[tuple]:
    found = []
    items = tree.items() if isinstance(tree, dict) else enumerate(tree)
    for key, value in items:
        found.append((*prefix, key))
        if isinstance(value, (dict, list)) and len(prefix) < 4:
            found.extend(_json_paths(value, (*prefix, key)))
    return found


@EXAMPLES
@given(data=st.data(), value=st.one_of(toml_values.filter(lambda value: not _has_literal(value)),
                                       deep_lists, st.none()))
def test_fuzzed_result_files_never_give_a_traceback(data, value):
    document = json.loads(_result_document())
    path = data.draw(st.sampled_from(_json_paths(document)))
    node = document
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = RAW if isinstance(value, Literal) else value
    text = json.dumps(document)
    if isinstance(value, Literal):
        text = text.replace(json.dumps(RAW), value)
    with tempfile.TemporaryDirectory() as temporary:
        folder = Path(temporary)
        (folder / "out").mkdir()
        result = folder / "input.json"
        result.write_text(text)
        _check(["report", str(result), "--no-plots", "--quiet", "--out", str(folder / "out")],
               folder)


@pytest.mark.parametrize("special", ["fifo", "folder", "device", "large"])
def test_special_and_large_files_are_refused_unread(tmp_path, special):
    # a FIFO would block the read forever; /dev/zero would fill memory
    if special == "fifo":
        path = tmp_path / "case.toml"
        os.mkfifo(path)
    elif special == "folder":
        path = tmp_path / "case.toml"
        path.mkdir()
    elif special == "device":
        path = Path("/dev/zero")
    else:
        path = tmp_path / "case.toml"
        path.write_text("# padding\n" * 100_001)  # 1,100,011 bytes > 1 MB
        # past the 100 MB of a saved result too (sparse: no disk is used)
        os.truncate(path, MAX_RESULT_FILE_BYTES + 1)
    for command in (["validate", str(path)], ["report", str(path)],
                    ["sweep", str(path)], ["tolerance", str(path)]):
        code, text = run_sso(command)
        assert code == 2, text
        assert "Traceback" not in text
        assert ("not a regular file" in text or "folder" in text
                or re.search(r"it has \d+ bytes; at most \d+ are read", text)), text
