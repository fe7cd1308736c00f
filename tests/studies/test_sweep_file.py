"""Sweep files as read: defaults, the base case path, and refusals naming file and key.

Expected values: the layout and defaults documented in sso/_studies/sweep_file.py's
docstring (name from the file name, action "optimise", mode "product").
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from sso._studies.sweep_file import load_sweep

MINIMAL = 'case = "base.toml"\n[axes]\noption = [2, 3]\n'


def write(folder: Path, text: str, name: str = "start-map.toml") -> Path:
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def test_defaults_and_the_base_case_relative_to_the_sweep_file(tmp_path):
    spec = load_sweep(write(tmp_path, MINIMAL))
    assert spec.name == "start-map"
    assert spec.base == tmp_path / "base.toml"
    assert spec.axes == {"option": [2, 3]}
    assert (spec.action, spec.mode, spec.chunk_size) == ("optimise", "product", None)


def test_everything_given_and_an_inline_case_table(tmp_path):
    spec = load_sweep(
        write(
            tmp_path,
            (
                'name = "map_1"\naction = "evaluate"\nmode = "listed"\nchunk_size = 10\n'
                "[case.design]\nbeta_deg = [30.0, 40.0]\n"
                '[axes]\n"design.beta_deg[0]" = { start = 10, stop = 40, num = 7 }\n'
            ),
        )
    )
    assert (spec.name, spec.action, spec.mode, spec.chunk_size) == (
        "map_1",
        "evaluate",
        "listed",
        10,
    )
    assert spec.base == {"design": {"beta_deg": [30.0, 40.0]}}
    assert spec.axes == {"design.beta_deg[0]": {"start": 10, "stop": 40, "num": 7}}


@pytest.mark.parametrize(
    "text, message",
    [
        (
            "acton = 'x'\n" + MINIMAL,
            "unknown key acton; did you mean action? Keys: name, case",
        ),
        ("name = '../x'\n" + MINIMAL, "name = '../x' must be 1 to 100 letters"),
        ("case = 3\n[axes]\noption = [2]\n", "case = 3 must be a case file path"),
        ('case = "base.toml"\n', "[axes] is missing or empty"),
        ('case = "base.toml"\n[axes]\n', "[axes] is missing or empty"),
        ("action = 'solve'\n" + MINIMAL, "action = 'solve' is not one of"),
        ("case = \n", "not a valid TOML sweep file"),
    ],
)
def test_refusals_name_the_file_and_the_key(tmp_path, text, message):
    path = write(tmp_path, text)
    with pytest.raises(ValueError) as caught:
        load_sweep(path)
    # the file first, then the line where one is known (a TOML syntax error has one)
    assert re.match(rf"{re.escape(str(path))}(, line \d+)?: ", str(caught.value))
    assert message in str(caught.value)


def test_missing_file(tmp_path):
    with pytest.raises(ValueError, match="cannot read the sweep file: No such file"):
        load_sweep(tmp_path / "absent.toml")
