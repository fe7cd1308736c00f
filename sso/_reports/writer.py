"""Render the report files of a column's result document, and read its ``result.json`` back.

Everything is rendered in memory; :func:`sso._reports.kinds.write_report` writes
the files as one new report folder.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from sso._cases.column import COLUMN_KIND
from sso._record import RecordError, check_values, read_json_object
from sso._reports.documents import report_files
from sso._run.document import SCHEMA_VERSION
from sso._validation import shown

RESULT_FILE = "result.json"
COLUMN_REQUIRED_KEYS = ("schema_version", "kind", "mode", "case", "case_file", "geometry",
                        "cancel", "assemblies", "excitation", "recommended", "success",
                        "verdict", "warnings", "versions")


class ResultFileError(ValueError):
    """A result file cannot be read or is not a result document this version knows."""


def render(document: Mapping[str, Any], formats: Sequence[str]) -> dict[str, bytes]:
    """Contents of every requested file of a 3D-column result document, keyed by file
    name (nothing is written; :mod:`sso._reports.column_report`).

    Parameters
    ----------
    document : mapping
        A column case's result document (:mod:`sso._run.column_document`).
    formats : sequence of {"json", "csv", "md", "html", "png"}
        Files to render. Without ``"png"`` matplotlib is never imported and the
        reports carry no plots.
    """
    from sso._reports.column_plots import render_column_plots
    from sso._reports.column_report import EXCITATION_FILE, column_blocks, excitation_csv

    files = report_files(formats, lambda: {EXCITATION_FILE: excitation_csv(document)},
                         lambda: render_column_plots(document),
                         lambda images: column_blocks(document, images))
    if "json" in formats:  # the document first, as it was written
        files = {RESULT_FILE: result_json(document).encode("utf-8"), **files}
    return files


def result_json(document: Mapping[str, Any]) -> str:
    """The document as strict JSON (non-finite numbers become null)."""
    return json.dumps(_finite(document), indent=2, allow_nan=False) + "\n"


def read_result(path: str | Path) -> dict[str, Any]:
    """Read a ``result.json`` written by :func:`write_report`.

    Raises
    ------
    ResultFileError
        If the file is unreadable, not JSON, from another schema version, lacks a
        key the reports need, or holds a value out of its range (a residual error
        below 0, a succeeded solver's objective not finite; as a saved result is
        checked, :func:`sso._record.check_values`).
    """
    try:
        document = read_json_object(path)
    except RecordError as error:
        raise ResultFileError(str(error).replace("saved result", "result document")) from None
    version = document.get("schema_version")
    if type(version) is not type(SCHEMA_VERSION) or version != SCHEMA_VERSION:
        raise ResultFileError(f"{path}: schema_version = {shown(version)}; this sso reads "
                              f"schema_version {SCHEMA_VERSION}")
    kind = document.get("kind")
    if kind != COLUMN_KIND:
        raise ResultFileError(f"{path}: kind = {shown(kind)} is no result document this sso "
                              "reads (a shaft series' or a mechanism's result.json is a saved "
                              "result now: write it again with sso run or sso evaluate)")
    missing = [key for key in COLUMN_REQUIRED_KEYS if key not in document]
    if missing:
        raise ResultFileError(f"{path}: result document lacks {', '.join(missing)}")
    try:
        check_values(document)
    except RecordError as error:
        raise ResultFileError(f"{path}: {error}") from None
    return document


def _finite(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {key: _finite(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(item) for item in value]
    return value
