"""``sso.write_report``: one way to write the report of any result, by a registry of kinds.

A report kind renders one kind of result into the contents of its report files
(nothing is written while rendering); :func:`write_report` then swaps them in as
the whole report folder (:func:`sso._files.replace_folder`). The command line calls
the same function, so a report written from Python is the one ``sso`` writes.

Kinds of this layer and below are registered here: ``"optimisation"``
(:class:`sso.OptimisationResult`), ``"shaft_series_run"`` (a shaft-series case run,
:class:`sso._run.shaft_series.ShaftSeriesRun`), ``"column_run"`` (a column case run,
:class:`sso.ColumnRun`), ``"mechanism_run"`` (a mechanism case run,
:class:`sso._run.mechanism_run.MechanismRun`),
``"fourbar_design"`` (:class:`sso.FourBarDesignResult`), ``"mechanism_table"`` (a
:class:`sso.MechanismTable`, what a mechanism's ``analyse`` returns) and
``"record"`` (every other result: its summary). The studies
above this layer register their own (``"sweep"``, ``"tolerance"`` in
:mod:`sso._studies.report`) when their result module is imported, so any result that
exists has its kind registered. A result names its kind in its ``report_kind``
class attribute.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from sso._files import FileContents, replace_folder
from sso._folder_lock import folder_lock
from sso._limits import OUTPUT_FORMATS
from sso._record import Record

Renderer = Callable[[Any, tuple[str, ...]], Mapping[str, FileContents]]

RESULT_FILE = "result.json"
"""The saved result in every report folder; :meth:`sso._record.Record.from_dict` reads it."""
RECORD_KIND = "record"
"""The report kind of a result without one of its own: its summary and its record."""


@dataclass(frozen=True)
class ReportKind:
    """How one kind of result becomes report files.

    Attributes
    ----------
    name : str
        The kind, as results name it in ``report_kind``.
    render : callable
        ``render(result, formats) -> {file name: bytes or StreamedFile}``.
    folder : str
        What its report folder holds, as the folder's manifest names it
        (:func:`sso._files.replace_folder`): :data:`CASE_REPORT` for every kind of
        one case, ``"sweep"``, ``"tolerance study"``. A folder holding one is never
        replaced by another.
    """

    name: str
    render: Renderer
    folder: str


REPORT_KINDS: dict[str, ReportKind] = {}
CASE_REPORT = "case report"
"""The folder of one case's report, whichever result it was written from."""


def register_report_kind(name: str, render: Renderer, folder: str) -> None:
    """Add (or replace) the report kind ``name``, whose folders hold a ``folder``."""
    REPORT_KINDS[name] = ReportKind(name, render, folder)


def report_kind_of(result: Any) -> ReportKind:
    """The report kind of ``result``.

    A result that names no kind of its own is reported by the kind ``"record"``:
    its summary as Markdown and HTML, and its saved form.

    Raises
    ------
    TypeError
        If ``result`` is no result sso can report.
    """
    name = getattr(result, "report_kind", RECORD_KIND) if isinstance(result, Record) else None
    if not isinstance(name, str) or name not in REPORT_KINDS:
        raise TypeError("result must be an sso result (an object sso.optimise, "
                        f"sso.sweep or another sso function returns), not "
                        f"{type(result).__name__}")
    return REPORT_KINDS[name]


def validate_formats(formats: Any) -> tuple[str, ...]:
    """``formats`` as a tuple of known format names (None: every format).

    Raises
    ------
    ValueError
        Naming the unknown format and the allowed ones.
    """
    if formats is None:
        return OUTPUT_FORMATS
    if isinstance(formats, str):
        formats = (formats,)
    chosen = tuple(dict.fromkeys(formats))
    unknown = [name for name in chosen if name not in OUTPUT_FORMATS]
    if unknown or not chosen:
        raise ValueError(f"formats = {list(chosen)!r}: each must be one of "
                         f"{', '.join(OUTPUT_FORMATS)} (at least one)")
    return chosen


def render_report(result: Any,
                  formats: Sequence[str] | None = None) -> dict[str, FileContents]:
    """Contents of the report files of ``result`` (nothing is written; a large table is
    a :class:`sso._files.StreamedFile`, made as it is written)."""
    kind = report_kind_of(result)
    chosen = validate_formats(formats)
    files = dict(kind.render(result, chosen))
    if "json" in chosen:  # the saved result comes first
        files = {RESULT_FILE: record_json(result).encode("utf-8"),
                 **{name: data for name, data in files.items() if name != RESULT_FILE}}
    return files


def record_json(result: Record) -> str:
    """The saved form of ``result`` (what ``result.json`` holds), strict JSON."""
    return json.dumps(result.to_dict(), indent=2, allow_nan=False) + "\n"


def write_report(result: Any, folder: str | Path, formats: Sequence[str] | None = None,
                 adopt: tuple[str, ...] = ()) -> list[Path]:
    """Write the report of a result into ``folder``, as the ``sso`` command does.

    Parameters
    ----------
    result : sso result
        Any result of ``sso.__all__`` (what :func:`sso.optimise`, :func:`sso.sweep`
        and the other functions return), or a case run's (:class:`sso.ColumnRun`, a
        saved ``result.json`` read back with ``from_dict``).
    folder : str or pathlib.Path
        The report folder. It is written afresh: the new files go into a
        temporary folder beside it, which replaces it only when complete, so
        nothing of an earlier report survives beside the new one and a failure
        leaves the earlier report whole. It must be new, empty, or hold only
        files sso wrote there for the same kind of result (its ``sso-files.json``
        lists them); sso replaces nothing else.
    formats : sequence of {"json", "csv", "md", "html", "png"}, optional
        Files to write (default: all). Without ``"png"`` matplotlib is never
        imported.
    adopt : tuple of str
        Files in ``folder`` to treat as sso's although its manifest does not list
        them (the ``result.json`` a report is written again from).

    Returns
    -------
    list of pathlib.Path
        The files written.

    Raises
    ------
    TypeError
        If ``result`` is not a result sso can report.
    ValueError
        For an unknown format, or a ``folder`` that holds files sso did not write
        or another kind of result (see :func:`sso._files.replace_folder`).
    sso._folder_lock.FolderLockedError
        (a ValueError) If another process is writing ``folder``.
    """
    if not isinstance(folder, (str, Path)):
        raise TypeError(f"folder must be a str or pathlib.Path, not {type(folder).__name__}")
    kind = report_kind_of(result)
    files = render_report(result, formats)
    with folder_lock(folder, f"write a {kind.folder}"):
        return replace_folder(folder, files, kind.folder, adopt)


def _render_optimisation(result: Any, formats: tuple[str, ...]) -> dict[str, bytes]:
    from sso._reports.shaft_report import optimisation_files

    return optimisation_files(result, formats)


def _render_shaft_series_run(run: Any, formats: tuple[str, ...]) -> dict[str, bytes]:
    from sso._reports.shaft_report import run_files

    return run_files(run, formats)


def _render_column_run(run: Any, formats: tuple[str, ...]) -> dict[str, bytes]:
    from sso._reports.column_report import column_files

    return column_files(run, formats)


def _render_fourbar_design(result: Any, formats: tuple[str, ...]) -> dict[str, bytes]:
    from sso._reports.mechanism_report import design_files

    return design_files(result, formats)


def _render_mechanism_run(run: Any, formats: tuple[str, ...]) -> dict[str, bytes]:
    from sso._reports.mechanism_report import mechanism_files

    return mechanism_files(run, formats)


def _render_mechanism_table(table: Any, formats: tuple[str, ...]) -> dict[str, bytes]:
    from sso._reports.mechanism_report import table_report

    return table_report(table, formats)


def _render_record(result: Any, formats: tuple[str, ...]) -> dict[str, bytes]:
    from sso._reports.record_report import render_record

    return render_record(result, formats)


register_report_kind("optimisation", _render_optimisation, CASE_REPORT)
register_report_kind("shaft_series_run", _render_shaft_series_run, CASE_REPORT)
register_report_kind("column_run", _render_column_run, CASE_REPORT)
register_report_kind("fourbar_design", _render_fourbar_design, CASE_REPORT)
register_report_kind("mechanism_run", _render_mechanism_run, CASE_REPORT)
register_report_kind("mechanism_table", _render_mechanism_table, CASE_REPORT)
register_report_kind(RECORD_KIND, _render_record, CASE_REPORT)


def _render_driveline(result: Any, formats: tuple[str, ...]) -> dict[str, bytes]:
    from sso._reports.driveline_report import render_driveline_result

    return render_driveline_result(result, formats)


def _render_driveline_run(run: Any, formats: tuple[str, ...]) -> dict[str, bytes]:
    from sso._reports.driveline_report import render_driveline_run

    return render_driveline_run(run, formats)


register_report_kind("driveline", _render_driveline, CASE_REPORT)
register_report_kind("driveline_run", _render_driveline_run, CASE_REPORT)
