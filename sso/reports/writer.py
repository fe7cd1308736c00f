"""Render the report files of a result document, and read ``result.json`` back.

Everything is rendered in memory; :func:`sso.reports.kinds.write_report` writes
the files as one new report folder.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from sso.cases.column import COLUMN_KIND
from sso.cases.mechanism import MECHANISM_KINDS
from sso.record import RecordError, read_json_object
from sso.reports.documents import render_documents
from sso.run.document import SCHEMA_VERSION
from sso.validation import shown

RESULT_FILE = "result.json"
MECHANISM_REQUIRED_KEYS = ("schema_version", "kind", "mode", "case", "case_file", "length_unit",
                           "crank_speed_rad_s", "crank_accel_rad_s2", "linkages", "tables",
                           "extremes", "success", "verdict", "warnings", "versions")
COLUMN_REQUIRED_KEYS = ("schema_version", "kind", "mode", "case", "case_file", "geometry",
                        "cancel", "assemblies", "excitation", "recommended", "success",
                        "verdict", "warnings", "versions")


class ResultFileError(ValueError):
    """A result file cannot be read or is not a result document this version knows."""


def render(document: Mapping[str, Any], formats: Sequence[str]) -> dict[str, bytes]:
    """Contents of every requested file, keyed by file name (nothing is written).

    Parameters
    ----------
    document : mapping
        A result document of a mechanism or a column case
        (:mod:`sso.run.mechanism_document`, :mod:`sso.run.column_document`).
    formats : sequence of {"json", "csv", "md", "html", "png"}
        Files to render. Without ``"png"`` matplotlib is never imported and the
        reports carry no plots.
    """
    if document.get("kind") == COLUMN_KIND:
        return _render_column(document, formats)
    files: dict[str, bytes] = {}
    if "json" in formats:
        files[RESULT_FILE] = result_json(document).encode("utf-8")
    if "csv" in formats:
        from sso.reports.mechanism_report import table_files

        files.update({name: text.encode("utf-8") for name, text in table_files(document).items()})
    images: dict[str, bytes] = {}
    if "png" in formats:
        from sso.reports.mechanism_plots import render_mechanism_plots

        images = render_mechanism_plots(document)
        files.update(images)
    if "md" in formats or "html" in formats:
        from sso.reports.mechanism_report import mechanism_blocks

        blocks = mechanism_blocks(document, tuple(images))
        files.update(render_documents(blocks, images, formats))
    return files


def _render_column(document: Mapping[str, Any], formats: Sequence[str]) -> dict[str, bytes]:
    """The files of a 3D-column result (:mod:`sso.reports.column_report`)."""
    from sso.reports.column_report import EXCITATION_FILE, column_blocks, excitation_csv

    files: dict[str, bytes] = {}
    if "json" in formats:
        files[RESULT_FILE] = result_json(document).encode("utf-8")
    if "csv" in formats:
        files[EXCITATION_FILE] = excitation_csv(document).encode("utf-8")
    images: dict[str, bytes] = {}
    if "png" in formats:
        from sso.reports.column_plots import render_column_plots

        images = render_column_plots(document)
        files.update(images)
    if "md" in formats or "html" in formats:
        blocks = column_blocks(document, tuple(images))
        files.update(render_documents(blocks, images, formats))
    return files


def result_json(document: Mapping[str, Any]) -> str:
    """The document as strict JSON (non-finite numbers become null)."""
    return json.dumps(_finite(document), indent=2, allow_nan=False) + "\n"


def read_result(path: str | Path) -> dict[str, Any]:
    """Read a ``result.json`` written by :func:`write_report`.

    Raises
    ------
    ResultFileError
        If the file is unreadable, not JSON, from another schema version, or
        lacks a key the reports need.
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
    if kind != COLUMN_KIND and kind not in MECHANISM_KINDS:
        raise ResultFileError(f"{path}: kind = {shown(kind)} is no result document this sso "
                              "reads (a shaft series' result.json is a saved result now: write "
                              "it again with sso run or sso evaluate)")
    required = COLUMN_REQUIRED_KEYS if kind == COLUMN_KIND else MECHANISM_REQUIRED_KEYS
    missing = [key for key in required if key not in document]
    if missing:
        raise ResultFileError(f"{path}: result document lacks {', '.join(missing)}")
    return document


def _finite(value: Any) -> Any:
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {key: _finite(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(item) for item in value]
    return value
