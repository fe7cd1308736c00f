"""A bounded fuzz of what sso reads back (issue 34): damaged ``sweep.csv`` files
resumed, and ``result.json`` files of case runs and tolerance studies cut short or
with a field of another type. Each input goes through the ``sso`` command in this
process; it must exit 0, 1 or 2 with no traceback, and nothing may land outside
``--out``. The long run is ``python -m benchmarks.fuzz`` (its counts and time are in
its docstring's target and the issue's report).
"""

from __future__ import annotations

import functools
import json
import random
import shutil
from pathlib import Path

import pytest
from fuzzing import NASTY_CELLS, mutate_sweep_csv, run_sso

ROOT = Path(__file__).resolve().parents[1]
INPUTS = 40  # per test; seeded, so every run tries the same inputs
SWEEP = """name = "fuzzed"
case = "{case}"
action = "evaluate"
[axes]
"design.beta_deg[1]" = {{ start = 10, stop = 25, num = 6 }}
"""
# Every nasty cell, the one longer than the csv module's field limit (131,072
# characters, refused with exit 2: issue 34 item 7) included.
CELLS = NASTY_CELLS
TYPES = (None, True, -1, 1e308, "", "x", [], {}, [[[]]], {"type": "ShaftSeries"})


def _clean(code, text, folder: Path, allowed: set[str]) -> None:
    assert code in (0, 1, 2), text
    assert "Traceback" not in text
    assert {item.name for item in folder.iterdir()} <= allowed


def test_damaged_sweep_files_resume_or_are_refused(tmp_path):
    (tmp_path / "sweep.toml").write_text(
        SWEEP.format(case=ROOT / "cases" / "paper_option1_exact.toml"), encoding="utf-8")
    code, text = run_sso(["sweep", str(tmp_path / "sweep.toml"), "--workers", "1",
                          "--no-plots", "--quiet", "--out", str(tmp_path / "finished")])
    assert code == 0, text
    finished = tmp_path / "finished" / "fuzzed"
    original = (finished / "sweep.csv").read_text(encoding="utf-8")
    rng = random.Random(34)
    codes = []
    for index in range(INPUTS):
        folder = tmp_path / f"s{index}"
        shutil.copytree(finished, folder / "out" / "fuzzed")
        damaged = mutate_sweep_csv(rng, original, CELLS)
        (folder / "out" / "fuzzed" / "sweep.csv").write_bytes(damaged.encode("utf-8"))
        code, text = run_sso(["sweep", str(tmp_path / "sweep.toml"), "--resume", "--workers",
                              "1", "--no-plots", "--quiet", "--out", str(folder / "out")])
        _clean(code, text, folder, {"out"})
        codes.append(code)
        if code == 2 and damaged.endswith("\n"):  # refused: the file is left as it was
            # (a last line without its end is an append cut short, which sso drops)
            assert (folder / "out" / "fuzzed" / "sweep.csv").read_bytes() == damaged.encode()
        shutil.rmtree(folder)
    assert codes.count(2) >= INPUTS // 4 and codes.count(0) >= 1, codes


@functools.lru_cache(maxsize=1)
def _results() -> tuple[str, ...]:
    import tempfile

    with tempfile.TemporaryDirectory() as temporary:
        folder = Path(temporary)
        for command in (["run", str(ROOT / "cases" / "column_car_intermediate_shaft.toml")],
                        ["evaluate", str(ROOT / "cases" / "paper_option1_paper.toml")],
                        ["tolerance", str(ROOT / "cases" / "paper_option1_exact.toml"),
                         "--samples", "200", "--workers", "1", "--no-plots"]):
            code, text = run_sso([*command, "--quiet", "--out", str(folder / command[0])])
            assert code == 0, text
        return tuple(path.read_text() for path in sorted(folder.glob("*/*/result.json")))


@pytest.mark.parametrize("kind", range(3))
def test_result_files_cut_short_or_retyped_are_refused(tmp_path, kind):
    text = _results()[kind]
    rng = random.Random(kind)
    for index in range(INPUTS // 2):
        if index % 2:
            mutated = text[:rng.randrange(len(text))]
        else:
            document = json.loads(text)
            node = document
            while True:
                key = rng.choice(list(node))
                if not isinstance(node[key], dict) or rng.random() < 0.3:
                    break
                node = node[key]
            node[key] = rng.choice(TYPES)
            mutated = json.dumps(document)
        folder = tmp_path / f"r{index}"
        (folder / "out").mkdir(parents=True)
        (folder / "result.json").write_text(mutated, encoding="utf-8")
        code, output = run_sso(["report", str(folder / "result.json"), "--no-plots", "--quiet",
                                "--out", str(folder / "out")])
        _clean(code, output, folder, {"out", "result.json"})
