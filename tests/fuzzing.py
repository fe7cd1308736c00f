"""Helpers of the fuzz tests (tests/test_fuzz_inputs.py) and of benchmarks/fuzz.py.

Runs the ``sso`` command in this process and tells a clean exit from a traceback,
and writes TOML (the standard library only reads it).
"""

from __future__ import annotations

import contextlib
import io
import json
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
