"""Saved results: which classes a ``result.json`` may name, reading one, and their schema.

Every public result class (a :class:`sso._record.Record` in ``sso.__all__``) and the
result of a case run can be saved; ``sso report`` reads a saved one back with the
``from_dict`` of the class its ``type`` names. The published JSON Schema of the saved form
(``sso/result.schema.json``) is generated from the same classes; regenerate it
with::

    python -m sso._cli.saved_results --output sso/result.schema.json
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from importlib import import_module, resources
from pathlib import Path
from typing import Any

from sso._files import write_text_atomic
from sso._record import RECORD_VERSION, Record, RecordError, json_schema, read_json_object
from sso._run.mechanism_run import MechanismRun
from sso._run.shaft_series import ShaftSeriesRun
from sso._validation import shown

SHIPPED_SCHEMA = "result.schema.json"


def result_classes() -> dict[str, type[Record]]:
    """Every public result class and the case runs' results, by name.

    Importing the modules that define them.
    """
    package = import_module("sso")
    classes: dict[str, type[Record]] = {"ShaftSeriesRun": ShaftSeriesRun,
                                        "MechanismRun": MechanismRun}
    for name in package.__all__:
        value = getattr(package, name)
        if isinstance(value, type) and issubclass(value, Record):
            classes[name] = value
    return classes


def read_saved_result(path: str | Path) -> Record:
    """The result saved in ``path`` (a ``result.json``), equal to the one saved, its
    figures computed again from its designs (:func:`sso._reports.figure_checks.check_figures`;
    a sweep's rows: :func:`sso._studies.saved_rows.check_saved_rows`).

    Raises
    ------
    RecordError
        If the file is unreadable, not JSON, names no public result type, or a
        field is missing, unknown, of the wrong type or out of range, or a figure is
        not that of the design it belongs to (named).
    """
    from sso._reports.figure_checks import check_figures
    from sso._studies.results import SweepResult
    from sso._studies.saved_rows import check_saved_rows

    saved = read_json_object(path)
    if "type" not in saved and "schema_version" in saved:
        raise RecordError(f"{path}: a result document of an earlier sso (schema_version = "
                          f"{shown(saved['schema_version'])}): this sso reads saved results "
                          f'("type" and "version" {RECORD_VERSION}) only; write it again with '
                          "sso run or sso evaluate of its case")
    classes = result_classes()
    kind = saved.get("type")
    if not isinstance(kind, str) or kind not in classes:
        raise RecordError(f"{path}: type = {shown(kind)}; allowed: "
                          f"{', '.join(sorted(classes))}")
    try:
        result = classes[kind].from_dict(saved)
        check_figures(result)
        if isinstance(result, SweepResult):
            check_saved_rows(result)
    except RecordError as error:
        raise RecordError(f"{path}: {error}") from None
    except RecursionError:
        raise RecordError(f"{path}: objects are nested too deeply to read") from None
    return result


def result_schema() -> dict[str, Any]:
    """The JSON Schema of a saved result of every public result class."""
    return json_schema(tuple(result_classes().values()))


def shipped_schema() -> dict[str, Any]:
    """The JSON Schema shipped with the package (``sso/result.schema.json``)."""
    text = resources.files("sso").joinpath(SHIPPED_SCHEMA).read_text(encoding="utf-8")
    schema: dict[str, Any] = json.loads(text)
    return schema


def main(argv: Sequence[str] | None = None) -> int:
    """Write the result schema (``--output FILE``) or print it."""
    parser = argparse.ArgumentParser(description="Write the JSON Schema of sso's result.json.")
    parser.add_argument("--output", metavar="FILE", help="write here instead of stdout")
    args = parser.parse_args(argv)
    text = json.dumps(result_schema(), indent=2) + "\n"
    if args.output is None:
        sys.stdout.write(text)
    else:
        write_text_atomic(args.output, text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
