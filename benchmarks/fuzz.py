"""Fuzz the input files and count exit codes; a traceback is a defect.

``python -m benchmarks.fuzz [--cases N] [--results N] [--sweeps N] [--seed S]`` mutates
the shipped case files (``cases/**/*.toml``), ``result.json`` files written from them
(case runs of every kind and tolerance studies: fields replaced by other types, huge
numbers and deep nesting, text cut anywhere) and the ``sweep.csv`` of a finished
sweep (cells, lines and bytes damaged: ``mutate_sweep_csv`` of tests/fuzzing.py),
runs each through the ``sso`` command in this process (``run_sso`` of
tests/fuzzing.py: ``validate``, then ``evaluate`` for case files that validate;
``report`` for result files; ``sweep --resume`` for sweep files) and prints the
counts by exit code. A run "tracebacks" when an exception escapes ``main`` or its
output contains ``Traceback``. It also checks that no report lands outside
``--out``. Defaults: 10,000 case files, 2,000 result files, 2,000 sweep files (the
target: 0 tracebacks).
"""

from __future__ import annotations

import argparse
import collections
import contextlib
import json
import random
import shutil
import sys
import tempfile
import time
import tomllib
from collections.abc import Callable
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
from fuzzing import (  # noqa: E402  (the tests' helpers, shared)
    mutate_sweep_csv,
    run_sso,
    toml_document,
)

PARENT = "." * 2  # spelt out, a parent folder reads as a path leaving the repository
NASTY_TEXT = (
    "[]", "{}", "[[]]", "[" * 3000 + "]" * 3000, "9" * 5000, "9" * 400, "-" + "9" * 400,
    "1e308", "-1e308", "5e-324", "nan", "inf", "-inf", "0", "-0.0", "-1", "1e-300",
    "true", '""', '"' + PARENT + '/' + PARENT + '/escape"', '"' + PARENT + '"', '"."',
    '"\\u0000"', "1979-05-27T07:32:00Z",
    "07:32:00", '"' + "x" * 20000 + '"', "[1, 2, 3, 4, 5, 6, 7, 8, 9, 10]", "[[0, 90], [0, 90]]",
    "[89.99, 89.99, 89.99]", "89.9999999", "2", "3", "64", "65", "100000000", "1e9",
    '"exact"', '"paper"', '"fourbar"', '"slider_crank"', '"quick_return"', '"fourbar_design"',
    '["ipopt"]', '["json", "png"]', "{ a = 1 }",
)
SHALLOW_TEXT = tuple(text for text in NASTY_TEXT if not text.startswith("[[["))
NASTY_JSON: tuple[Any, ...] = (
    None, True, 0, -1, 1e308, -1e308, 5e-324, "", "x", PARENT, f"{PARENT}/{PARENT}/escape",
    [], {}, [[]],
    10**400, 10**5000, [1, 2], {"a": 1}, float("nan"), 1e9, "exact", "png",
)


def mutate_toml(rng: random.Random, text: str) -> str:
    """One random mutation of a TOML file: of its text, or of its parsed values."""
    lines = text.splitlines()
    choice = rng.random()
    if choice < 0.35:
        assignments = [index for index, line in enumerate(lines) if "=" in line]
        if assignments:
            index = rng.choice(assignments)
            key = lines[index].split("=", 1)[0]
            lines[index] = f"{key}= {rng.choice(NASTY_TEXT)}"
        return "\n".join(lines) + "\n"
    if choice < 0.45 and lines:
        index = rng.randrange(len(lines))
        operation = rng.choice(("delete", "duplicate", "truncate"))
        if operation == "delete":
            del lines[index]
        elif operation == "duplicate":
            lines.insert(index, lines[index])
        else:
            lines[index] = lines[index][: rng.randrange(len(lines[index]) + 1)]
        return "\n".join(lines) + "\n"
    if choice < 0.5:
        data = bytearray(text.encode("utf-8"))
        for _ in range(rng.randint(1, 5)):
            if data:
                data[rng.randrange(len(data))] = rng.randrange(256)
        return data.decode("utf-8", errors="replace")
    document = tomllib.loads(text)
    with unlimited_integers():
        for _ in range(rng.randint(1, 3)):
            # deep nesting goes in by text only (the fuzzer's own parser would recurse)
            _mutate_tree(rng, document,
                         lambda: tomllib.loads(f"v = {rng.choice(SHALLOW_TEXT)}")["v"])
        return toml_document(document)


@contextlib.contextmanager
def unlimited_integers() -> Any:
    """Let the fuzzer itself parse and print integers of any length (sso runs without)."""
    limit = sys.get_int_max_str_digits()
    sys.set_int_max_str_digits(0)
    try:
        yield
    finally:
        sys.set_int_max_str_digits(limit)


def _mutate_tree(rng: random.Random, tree: Any, nasty: Callable[[], Any]) -> None:
    """Replace, delete or add one entry somewhere in a tree of dicts and lists."""
    path = [tree]
    node = tree
    while isinstance(node, (dict, list)) and node and rng.random() < 0.7:
        key = rng.choice(list(node)) if isinstance(node, dict) else rng.randrange(len(node))
        if not isinstance(node[key], (dict, list)):
            break
        node = node[key]
        path.append(node)
    if isinstance(node, dict):
        operation = rng.random()
        if node and operation < 0.6:
            node[rng.choice(list(node))] = nasty()
        elif node and operation < 0.8:
            del node[rng.choice(list(node))]
        else:
            node[rng.choice(("extra", "kind", "name", "value"))] = nasty()
    elif isinstance(node, list) and node:
        node[rng.randrange(len(node))] = nasty()


def mutate_json(rng: random.Random, text: str) -> str:
    """One random mutation of a result file: of its text, or of its parsed values."""
    if rng.random() < 0.1:
        return text[:rng.randrange(len(text) + 1)]  # a file cut short
    if rng.random() < 0.25:
        data = list(text)
        for _ in range(rng.randint(1, 5)):
            position = rng.randrange(len(data))
            data[position:position + rng.randint(0, 40)] = rng.choice(
                ["", "[", "{", '"', "9" * 5000, "[" * 5000, "NaN", "-", "\\u0000", "1e999"])
        return "".join(data)
    document = json.loads(text)
    with unlimited_integers():
        for _ in range(rng.randint(1, 4)):
            _mutate_tree(rng, document, lambda: json.loads(json.dumps(rng.choice(NASTY_JSON))))
        return json.dumps(document)


def seed_results(work: Path) -> list[str]:
    """result.json texts written by ``sso evaluate`` and ``sso run`` from the shipped cases."""
    texts = []
    for case in sorted(ROOT.glob("cases/**/*.toml")):
        out = work / "seed"
        run_sso(["evaluate", str(case), "--formats", "json", "--quiet", "--out", str(out)])
        texts.extend(path.read_text() for path in out.glob("*/result.json"))
        shutil.rmtree(out, ignore_errors=True)
    run_sso(["run", str(ROOT / "cases/steering_column.toml"), "--formats", "json",
                       "--quiet", "--out", str(work / "seed")])
    for case in ("paper_option1_exact.toml", "paper_option1_paper.toml",
                 "column_truck_three_joints.toml"):
        run_sso(["tolerance", str(ROOT / "cases" / case), "--samples", "200", "--workers", "1",
                 "--no-plots", "--quiet", "--out", str(work / "tolerance")])
    texts.extend(path.read_text() for path in (work / "seed").glob("*/result.json"))
    texts.extend(path.read_text() for path in (work / "tolerance").glob("*/result.json"))
    return texts


SWEEP = """name = "fuzzed"
case = "{case}"
action = "evaluate"
[axes]
"design.beta_deg[1]" = {{ start = 10, stop = 25, num = 6 }}
"""


def seed_sweep(work: Path) -> Path:
    """The folder of a finished 6-point sweep (sweep.toml beside it, in ``work``)."""
    (work / "sweep.toml").write_text(
        SWEEP.format(case=ROOT / "cases" / "paper_option1_exact.toml"), encoding="utf-8")
    code, text = run_sso(["sweep", str(work / "sweep.toml"), "--workers", "1", "--no-plots",
                          "--quiet", "--out", str(work / "sweep")])
    assert code == 0, text
    return work / "sweep" / "fuzzed"


def fuzz_sweeps(rng: random.Random, work: Path, count: int, counts: collections.Counter[Any],
                examples: dict[str, str]) -> None:
    """``sso sweep --resume`` of ``count`` damaged copies of a finished sweep's folder."""
    finished = seed_sweep(work)
    text = (finished / "sweep.csv").read_text(encoding="utf-8")
    for index in range(count):
        folder = work / f"s{index}"
        copy = folder / "out" / "fuzzed"
        shutil.copytree(finished, copy)
        damaged = mutate_sweep_csv(rng, text)
        (copy / "sweep.csv").write_bytes(damaged.encode("utf-8"))
        code, output = run_sso(["sweep", str(work / "sweep.toml"), "--resume", "--workers",
                                "1", "--no-plots", "--quiet", "--out", str(folder / "out")])
        counts[code] += 1
        if code == "traceback":
            examples.setdefault(output[:80], damaged[:400] + "\n---\n" + output)
        shutil.rmtree(folder)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=10_000)
    parser.add_argument("--results", type=int, default=2_000)
    parser.add_argument("--sweeps", type=int, default=2_000)
    parser.add_argument("--seed", type=int, default=11)
    args = parser.parse_args()
    rng = random.Random(args.seed)
    sources = [path.read_text() for path in sorted(ROOT.glob("cases/**/*.toml"))]
    case_counts: collections.Counter[Any] = collections.Counter()
    report_counts: collections.Counter[Any] = collections.Counter()
    sweep_counts: collections.Counter[Any] = collections.Counter()
    escapes = 0
    examples: dict[str, str] = {}
    started = time.perf_counter()
    with tempfile.TemporaryDirectory() as temporary:
        work = Path(temporary)
        for index in range(args.cases):
            folder = work / f"c{index}"
            (folder / "out").mkdir(parents=True)
            name = rng.choice(("case.toml", "...toml", "..toml", ".toml", "a b.toml", "x.toml"))
            path = folder / name
            path.write_text(mutate_toml(rng, rng.choice(sources)), encoding="utf-8")
            code, text = run_sso(["validate", str(path)])
            if code == 0:
                code, text = run_sso(["evaluate", str(path), "--formats", "json,csv,md,html",
                                      "--quiet", "--out", str(folder / "out")])
            case_counts[code] += 1
            if code == "traceback":
                examples.setdefault(text[:80], path.read_text()[:400] + "\n---\n" + text)
            if {item.name for item in folder.iterdir()} - {"out", name}:
                escapes += 1
            shutil.rmtree(folder)
        results = seed_results(work)
        for index in range(args.results):
            folder = work / f"r{index}"
            (folder / "out").mkdir(parents=True)
            path = folder / "result.json"
            path.write_text(mutate_json(rng, rng.choice(results)), encoding="utf-8")
            code, text = run_sso(["report", str(path), "--no-plots", "--quiet",
                                  "--out", str(folder / "out")])
            report_counts[code] += 1
            if code == "traceback":
                examples.setdefault(text[:80], text)
            if {item.name for item in folder.iterdir()} - {"out", "result.json"}:
                escapes += 1
            shutil.rmtree(folder)
        fuzz_sweeps(rng, work, args.sweeps, sweep_counts, examples)
    print(f"{args.cases} fuzzed case files (validate, then evaluate): "
          f"{dict(sorted(case_counts.items(), key=str))}")
    print(f"{args.results} fuzzed result.json files (report): "
          f"{dict(sorted(report_counts.items(), key=str))}")
    print(f"{args.sweeps} damaged sweep.csv files (sweep --resume): "
          f"{dict(sorted(sweep_counts.items(), key=str))}")
    print(f"reports outside --out: {escapes}; {time.perf_counter() - started:.0f} s")
    print(f"kinds of traceback (by the first 80 characters of the output): {len(examples)}")
    for text in list(examples.values())[:20]:
        print("----- traceback example\n" + text)


if __name__ == "__main__":
    main()
