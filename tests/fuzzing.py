"""Helpers of the fuzz tests (tests/test_fuzz_inputs.py) and of benchmarks/fuzz.py.

Runs the ``sso`` command in this process and tells a clean exit from a traceback,
writes TOML (the standard library only reads it) and damages a ``sweep.csv`` as a
careless or hostile hand might (for ``--resume``).
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import random
import warnings
from typing import Any

from sso._cli.app import main as sso_main


def run_sso(arguments: list[str]) -> tuple[int | str, str]:
    """Exit code of ``sso ARGUMENTS`` run in this process (or ``"traceback"``), and its
    output. A run "tracebacks" when an exception escapes ``main`` or its output holds
    ``Traceback``."""
    output = io.StringIO()
    try:
        with contextlib.redirect_stdout(output), contextlib.redirect_stderr(output), \
                warnings.catch_warnings():
            warnings.simplefilter("ignore")
            code: int | str = sso_main(arguments)
    except SystemExit as stop:  # argparse's exit 2 on bad arguments
        code = stop.code if isinstance(stop.code, int) else 2
    except BaseException as error:  # noqa: BLE001 - the defect being counted
        return "traceback", f"{type(error).__name__}: {error}"[:300]
    text = output.getvalue()
    return ("traceback" if "Traceback" in text else code), text


class Literal(str):
    """Text written into a TOML or JSON file as it is: values Python cannot build or
    print easily (an integer of 5000 digits, arrays nested 5000 deep)."""


def toml_value(value: Any) -> str:
    """A TOML literal for a value tomllib can produce (inline tables for dicts)."""
    if isinstance(value, Literal):
        return str(value)
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(item) for item in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{json.dumps(str(key))} = {toml_value(item)}"
                               for key, item in value.items()) + "}"
    return value.isoformat() if hasattr(value, "isoformat") else json.dumps(str(value))


def toml_document(document: dict[str, Any]) -> str:
    """A TOML document: top-level values first, then one ``[table]`` per dict."""
    lines = [f"{json.dumps(str(key))} = {toml_value(value)}" for key, value in document.items()
             if not isinstance(value, dict)]
    for key, value in document.items():
        if isinstance(value, dict):
            lines.append(f"[{json.dumps(str(key))}]")
            lines.extend(f"{json.dumps(str(inner))} = {toml_value(item)}"
                         for inner, item in value.items())
    return "\n".join(lines) + "\n"


NASTY_CELLS = (
    "", "-5", "-0.0", "nan", "inf", "-inf", "1e999", "1e-400", "maybe", "True", "0x10", "1_0",
    "9" * 5000, "[" * 3000, "[1, 2", "[1, NaN]", "[[1, [2, [3]]]]", "[]", "{}", '"', "\x00",
    "ok", "failed", "lost", "true", "false", "0", "-1", "12345678901234567890", "x" * 300,
    "x" * 200_000,
)
"""Cell texts a damaged or hand-edited ``sweep.csv`` may hold."""


def mutate_sweep_csv(rng: random.Random, text: str,
                     cells: tuple[str, ...] = NASTY_CELLS) -> str:
    """One random damage to a ``sweep.csv``: a cell replaced (by one of ``cells``), a line
    deleted, duplicated, swapped or cut, the file truncated, bytes changed, a line
    appended."""
    lines = text.splitlines(keepends=True)
    choice = rng.random()
    if choice < 0.5 and len(lines) > 1:
        index = rng.randrange(len(lines))
        row = next(csv.reader([lines[index]]), [])
        if row:
            row[rng.randrange(len(row))] = rng.choice(cells)
        buffer = io.StringIO()
        csv.writer(buffer, lineterminator="\n").writerow(row)
        lines[index] = buffer.getvalue()
    elif choice < 0.65 and lines:
        index = rng.randrange(len(lines))
        operation = rng.choice(("delete", "duplicate", "swap", "cut"))
        if operation == "delete":
            del lines[index]
        elif operation == "duplicate":
            lines.insert(index, lines[index])
        elif operation == "swap":
            other = rng.randrange(len(lines))
            lines[index], lines[other] = lines[other], lines[index]
        else:
            lines[index] = lines[index][:rng.randrange(len(lines[index]) + 1)]
    elif choice < 0.75:
        return text[:rng.randrange(len(text) + 1)]
    elif choice < 0.9:
        data = list(text)
        for _ in range(rng.randint(1, 5)):
            if data:
                data[rng.randrange(len(data))] = rng.choice(',"\n\r\x00[]-9ex')
        return "".join(data)
    else:
        lines.append(rng.choice(("\n", ",,,\n", "garbage\n", lines[-1] if lines else "")))
    return "".join(lines)
