"""Reports of sweeps and tolerance studies, registered as the report kinds
``"sweep"`` and ``"tolerance"`` of :func:`sso.write_report`.

Each renderer turns a result into the contents of its report files (nothing is
written here): the data files (``sweep.csv`` and ``sweep.json``; ``tolerance.csv``
and ``tolerance.json``), ``report.md`` and ``report.html`` rendered from the same
blocks as every other report, and the plot. The results are read by their
attributes only, so this module does not import :mod:`sso._studies.results` (which
imports it, to register the kinds). matplotlib is imported only inside the
plotting functions (object-oriented ``Figure`` API, no pyplot state).

Data files: ``sweep.csv`` keeps every digit (a resumed sweep continues from it,
and its rows are the sweep's data, as ``result.json`` is a run's);
``tolerance.csv`` holds the samples to six significant digits and
``tolerance.json`` the summary at full precision.
"""

from __future__ import annotations

import io
import json
import math
import re
import textwrap
from collections.abc import Iterator, Sequence
from typing import Any

import numpy as np

from sso._display import format_number
from sso._files import FileContents, StreamedFile
from sso._limits import REPORT_DIGITS, ROUND_OFF_FLOOR
from sso._reports.documents import render_documents
from sso._reports.kinds import register_report_kind
from sso._reports.summary import Block, Heading, Image, Paragraph, Table
from sso._studies.axes import value_positions
from sso._studies.element_columns import gathered
from sso._studies.saved_rows import saved_columns
from sso._studies.table import CSV_NAME, MANIFEST_NAME, format_row, render_rows
from sso._validation import shown

REPORT_ROWS = 50
SWEEP_FOLDER = "sweep"
TOLERANCE_FOLDER = "tolerance study"
SWEEP_PLOT = "sweep_re.png"
SWEEP_FIGURES_PLOT = "sweep_figures.png"
TOLERANCE_PLOT = "tolerance_histogram.png"
TOLERANCE_CSV = "tolerance.csv"
TABLE_ROWS = 10_000
"""Rows of a study's table formatted at once while it is written (about 0.7 MB of text)."""
TOLERANCE_JSON = "tolerance.json"
PANEL_SIZE_IN = (3.6, 2.7)
SINGLE_SIZE_IN = (7.0, 4.5)
FIGURE_DPI = 120
MOST_PANELS = 16
MOST_TICK_LABELS = 8
MOST_DRAWN_POINTS = 20_000
"""Points a panel of a sweep's plot draws at most (a sample of a larger sweep)."""
FLOOR_LABEL = f"at or below {ROUND_OFF_FLOOR:g} (round-off), drawn at {ROUND_OFF_FLOOR:g}"
# (metric, label with unit) of a tolerance study's figures.
TOLERANCE_FIGURES = (
    ("residual_error", "residual error RE (dimensionless)"),
    ("fluctuation", "fluctuation, peak to peak / input speed (dimensionless)"),
    ("max_output_accel_rad_s2", "output acceleration, max |dw/dt| (rad/s^2)"),
)
# (sweep.csv column, report column with unit)
SWEEP_TABLE_COLUMNS = (
    ("status", "status"), ("residual_error", "RE (dimensionless)"),
    ("fluctuation", "fluctuation (dimensionless)"), ("success", "converged and agree"),
    ("crosscheck_agree", "solvers agree"), ("time_s", "time (s)"),
)
# The same for a sweep of a column case: its design and steering figures.
COLUMN_TABLE_COLUMNS = (
    ("status", "status"), ("residual_error", "RE (dimensionless)"),
    ("yoke_phase_deg", "yoke phasing (deg)"),
    ("speed_fluctuation_percent", "speed fluctuation, lock to lock (%)"),
    ("largest_transmission_error_deg", "largest |TE| (deg)"),
    ("success", "converged and agree"), ("time_s", "time (s)"),
)


def render_sweep(result: Any, formats: tuple[str, ...]) -> dict[str, FileContents]:
    """Report files of a :class:`sso.SweepResult`, keyed by file name."""
    files: dict[str, FileContents] = {}
    if "csv" in formats:
        table = getattr(result.rows, "table", None)  # a sweep's rows, held as columns
        header = list(table.header) if table is not None else saved_columns(result)
        files[CSV_NAME] = (render_rows(header, ()) + table.csv_text() if table is not None
                           else render_rows(header, [format_row(row, header)
                                                     for row in result.rows])).encode("utf-8")
    if "json" in formats and result.manifest:
        files[MANIFEST_NAME] = (json.dumps(result.manifest, indent=2) + "\n").encode("utf-8")
    images = {SWEEP_PLOT: _png(_sweep_figure(result))} if "png" in formats else {}
    if "png" in formats and _signed_columns(result):
        images[SWEEP_FIGURES_PLOT] = _png(_figures_figure(result))
    files.update(images)
    _add_documents(files, formats, _sweep_blocks(result, tuple(images)), images)
    return files


def render_tolerance(result: Any, formats: tuple[str, ...]) -> dict[str, FileContents]:
    """Report files of a :class:`sso.ToleranceResult`, keyed by file name; the samples'
    table streamed as it is written (:data:`TABLE_ROWS` rows at a time)."""
    files: dict[str, FileContents] = {}
    if "csv" in formats:
        files[TOLERANCE_CSV] = _tolerance_csv(result)
    if "json" in formats:
        summary = json.dumps(result._document_dict(), indent=2) + "\n"
        files[TOLERANCE_JSON] = summary.encode("utf-8")
    images = {TOLERANCE_PLOT: _png(_tolerance_figure(result))} if "png" in formats else {}
    files.update(images)
    _add_documents(files, formats, _tolerance_blocks(result, tuple(images)), images)
    return files


def _add_documents(files: dict[str, FileContents], formats: tuple[str, ...], blocks: list[Block],
                   images: dict[str, bytes]) -> None:
    files.update(render_documents(blocks, images, formats))


def _tolerance_csv(result: Any) -> StreamedFile:
    joints = result.design.n_joints
    header = ["sample", *(f"beta_deg[{k}]" for k in range(joints)),
              *(f"phase_deg[{k}]" for k in range(joints - 1)),
              "residual_error", "fluctuation", "max_output_accel_rad_s2"]
    return sample_table(header, (result.beta_deg, result.phase_deg, result.residual_error,
                                 result.fluctuation, result.max_output_accel_rad_s2))


def sample_table(header: Sequence[str], columns: Sequence[np.ndarray]) -> StreamedFile:
    """A study's table of samples (``tolerance.csv``): the sample index, then ``columns``
    (arrays of one value, or one row of values, per sample) to 6 significant digits,
    formatted :data:`TABLE_ROWS` rows at a time as the file is written."""

    def chunks() -> Iterator[bytes]:
        yield (",".join(["sample", *header[1:]]) + "\n").encode("utf-8")
        samples = len(columns[0])
        for start in range(0, samples, TABLE_ROWS):
            block = np.column_stack([column[start:start + TABLE_ROWS] for column in columns])
            lines = [",".join([str(index), *(f"{value:.{REPORT_DIGITS}g}" for value in row)])
                     for index, row in enumerate(block.tolist(), start)]
            yield ("\n".join(lines) + "\n").encode("utf-8")

    return StreamedFile(chunks)


def _sweep_blocks(result: Any, image_files: Sequence[str]) -> list[Block]:
    blocks: list[Block] = [
        Heading(1, "Sweep"),
        Paragraph(f"Action: {result.action}; mode: {result.mode}; {len(result.rows)} points. "
                  f"Every point, at full precision, is in {CSV_NAME}."),
        Table(("axis", "values", "first", "last"),
              tuple((axis.path, str(len(axis.values)), _cell(axis.values[0]),
                     _cell(axis.values[-1])) for axis in result.axes)),
        Heading(2, "Summary"), *[Paragraph(line.strip()) for line in result.summary().splitlines()
                                 if not line.strip().startswith("results:")],
    ]
    if image_files:
        blocks.append(Image(image_files[0], "Residual error of each point against each swept "
                            f"value (log scale); values {FLOOR_LABEL}."))
    if SWEEP_FIGURES_PLOT in image_files:
        blocks.append(Image(SWEEP_FIGURES_PLOT, "The steering figures of each point (speed-ratio "
                            "fluctuation, %; largest transmission error, deg) against the "
                            "swept value."))
    paths = [axis.path for axis in result.axes]
    shown = [result.rows[index] for index in result.lowest_re_order()[:REPORT_ROWS].tolist()]
    table = COLUMN_TABLE_COLUMNS if _kind(result) == "column" else SWEEP_TABLE_COLUMNS
    blocks += [Heading(2, f"Lowest residual error ({len(shown)} of {len(result.rows)} points)"),
               Table(("point", *paths, *(label for _, label in table)),
                     tuple((str(row["point"]), *(_cell(gathered(row, path)) for path in paths),
                            *(_cell(gathered(row, column)) for column, _ in table))
                           for row in shown))]
    failed = result.failed_points()
    if len(failed):
        listed = [result.rows[index] for index in failed[:REPORT_ROWS].tolist()]
        more = len(failed) - len(listed)
        blocks += [Heading(2, "Failed points"),
                   Table(("point", "error"), tuple((str(row["point"]), _cell(row["error"]))
                                                   for row in listed))]
        if more:
            blocks.append(Paragraph(f"... and {more} more failed points (every one is in "
                                    f"{CSV_NAME})."))
    return blocks


def _kind(result: Any) -> str:
    """The kind of the sweep's base case (``"shaft_series"`` or ``"column"``)."""
    kind: str = result.manifest.get("case", {}).get("kind", "shaft_series")
    return kind


def _tolerance_blocks(result: Any, image_files: Sequence[str]) -> list[Block]:
    spread = "standard deviation" if result.distribution == "normal" else "half-width"
    table = result.percentile_table()
    blocks: list[Block] = [
        Heading(1, "Tolerance study"),
        Paragraph(f"Design studied: {result.study_of}. Operating angles "
                  f"{_numbers(result.design.beta_deg)} deg, phases "
                  f"{_numbers(result.design.phase_deg)} deg, {result.design.model} model, "
                  f"{format_number(result.input_speed_rpm)} rpm."),
        Paragraph(f"Deviations: {result.distribution} ({spread}): operating angles "
                  f"{_numbers(result.beta_tolerance_deg)} deg, phases "
                  f"{_numbers(result.phase_tolerance_deg)} deg; {result.samples} samples, "
                  f"seed {result.seed}."),
        Paragraph(f"Samples with a perturbed operating angle below 0 deg: "
                  f"{result.reflected_samples}. They are reflected to |beta| (the same joint "
                  "bent the other way; the joint law depends on cos beta only). A tolerance "
                  "that could carry an angle to 90 deg, where the joint locks, is refused "
                  "before sampling."),
        Table(("figure", "nominal", *(f"p{q:g}" for q in result.percentiles)),
              tuple((label, format_number(getattr(result.nominal, metric)),
                     *(format_number(value) for value in table[metric].values()))
                    for metric, label in TOLERANCE_FIGURES)),
    ]
    if image_files:
        blocks.append(Image(image_files[0], "Histograms of the samples' figures; black: nominal, "
                            "red dotted: the percentiles above."))
    return blocks


def _sweep_figure(result: Any) -> Any:
    """One panel per swept axis; a two-axis product: one panel per value of the first axis.

    Read from the sweep's columns; each panel draws at most :data:`MOST_DRAWN_POINTS`
    points (evenly spread over the sweep; the line of the lowest RE at each value is
    drawn from every point).
    """
    ok = result.column("status") == "ok"
    errors = result.numbers("residual_error")
    positions = value_positions(result.axes, result.mode, result.numbers("point").astype(int))
    if result.mode == "product" and len(result.axes) == 2:
        outer, inner = 0, 1
        if _numeric(result.axes[0]) and not _numeric(result.axes[1]):
            outer, inner = 1, 0  # a numeric x axis reads better
        panels = [(f"{axis_label(result.axes[outer].path)} = {_cell(value)}", inner,
                   ok & (positions[outer] == number))
                  for number, value in enumerate(result.axes[outer].values[:MOST_PANELS])]
        possible = len(result.axes[outer].values)
    else:
        panels = [(f"against {axis_label(axis.path)}", number, ok)
                  for number, axis in enumerate(result.axes[:MOST_PANELS])]
        possible = len(result.axes)
    count = len(panels)
    columns_count = count if count <= 3 else 2 if count == 4 else 3 if count <= 9 else 4
    rows_count = math.ceil(count / columns_count)
    size = (SINGLE_SIZE_IN if count == 1 else
            (PANEL_SIZE_IN[0] * columns_count, PANEL_SIZE_IN[1] * rows_count + 0.6))
    figure = _figure(size)
    grid = figure.subplots(rows_count, columns_count, squeeze=False, sharey=True)
    for axes in grid.flat[count:]:
        axes.set_visible(False)
    thinned = False
    for axes, (title, number, selected) in zip(grid.flat, panels, strict=False):
        axis = result.axes[number]
        x = (result.numbers(axis.path) if _numeric(axis)
             else _category_positions(axis)[positions[number]].astype(float))
        thinned |= _sweep_panel(axes, axis, x[selected], errors[selected], title)
    failed = int(np.count_nonzero(~ok))
    omitted = f"; first {MOST_PANELS} of {possible} panels" if len(panels) < possible else ""
    sampled = (f"; at most {MOST_DRAWN_POINTS:,} points drawn a panel, evenly spread"
               if thinned else "")
    drawn = np.maximum(errors[ok & ~np.isnan(errors)], ROUND_OFF_FLOOR)
    top = max((drawn.max() if len(drawn) else 1.0) * 5, ROUND_OFF_FLOOR * 100)
    grid.flat[0].set_ylim(ROUND_OFF_FLOOR / 10, top)  # shared by every panel
    figure.suptitle(f"Residual error RE over the sweep ({result.action}, {len(result.rows)} "
                    f"points{f', {failed} failed not shown' if failed else ''}{omitted}"
                    f"{sampled})")
    legend: dict[str, Any] = {}
    for axes in grid.flat[:count]:
        for handle, label in zip(*axes.get_legend_handles_labels(), strict=True):
            legend.setdefault(label, handle)
    figure.legend(list(legend.values()), list(legend), loc="outside lower center",
                  ncols=min(len(legend), 2), fontsize="small")
    return figure


SIGNED_SWEEP_COLUMNS = (
    ("speed_fluctuation_percent", "speed-ratio fluctuation, lock to lock (%)"),
    ("largest_transmission_error_deg", "largest |transmission error|, lock to lock (deg)"),
)
"""The figures an engineer signs that a sweep's rows may hold (a column case's), with
their axis labels."""
UNIT_SUFFIXES = {"mm": "mm", "deg": "deg", "rpm": "rpm", "percent": "%", "s": "s",
                 "rad_s2": "rad/s^2"}
POINT_PATH = re.compile(r"(?:hardpoints\.)?(?:positions\.(\w+)\.)?points_mm\[(\d+)\]\[([012])\]$")


def axis_label(path: str) -> str:
    """A swept key in words with its unit: ``hardpoints.points_mm[2][2]`` reads
    ``P2 z (mm)``, ``design.beta_deg[0]`` ``beta_deg[0] (deg)`` (the key's last name,
    its unit suffix moved into brackets)."""
    point = POINT_PATH.search(path)
    if point is not None:
        position = f" at {point.group(1)}" if point.group(1) else ""
        return f"P{point.group(2)} {'xyz'[int(point.group(3))]}{position} (mm)"
    name = path.rsplit(".", 1)[-1]
    index = name.find("[")
    stem, indices = (name, "") if index < 0 else (name[:index], name[index:])
    for suffix, unit in sorted(UNIT_SUFFIXES.items(), key=lambda item: -len(item[0])):
        if stem.endswith(f"_{suffix}"):
            words = stem[:-len(suffix) - 1].replace("_", " ")
            return f"{words}{indices} ({unit})"
    return stem.replace("_", " ") + indices


def _signed_columns(result: Any) -> list[tuple[str, str]]:
    """The signed figures the sweep's rows hold a value of."""
    found = []
    for name, label in SIGNED_SWEEP_COLUMNS:
        try:
            values = result.numbers(name)
        except (KeyError, ValueError):
            continue
        if np.any(~np.isnan(values)):
            found.append((name, label))
    return found


def _figures_figure(result: Any) -> Any:
    """The signed figures (fluctuation %, transmission error deg) against the first
    numeric axis, one panel each; one line per value of the other axis of a two-axis
    product."""
    signed = _signed_columns(result)
    figure = _figure((PANEL_SIZE_IN[0] * len(signed) + 0.4, PANEL_SIZE_IN[1] + 1.2))
    grid = figure.subplots(1, len(signed), squeeze=False)[0]
    ok = result.column("status") == "ok"
    numeric = [number for number, axis in enumerate(result.axes) if _numeric(axis)]
    along = numeric[0] if numeric else 0
    axis = result.axes[along]
    x = (result.numbers(axis.path) if _numeric(axis)
         else _category_positions(axis)[value_positions(
             result.axes, result.mode, result.numbers("point").astype(int))[along]]
         .astype(float))
    groups: list[tuple[str, np.ndarray]] = [("", ok)]
    if result.mode == "product" and len(result.axes) == 2:
        other = 1 - along
        positions = value_positions(result.axes, result.mode,
                                    result.numbers("point").astype(int))[other]
        groups = [(f"{axis_label(result.axes[other].path)} = {_cell(value)}",
                   ok & (positions == number))
                  for number, value in enumerate(result.axes[other].values[:MOST_PANELS])]
    for panel, (name, label) in zip(grid, signed, strict=True):
        values = result.numbers(name)
        for group, selected in groups:
            order = np.argsort(x[selected], kind="stable")
            panel.plot(x[selected][order], values[selected][order], "o-", markersize=4,
                       linewidth=1.2, label=group or label)
        panel.set_xlabel(axis_label(axis.path))
        panel.set_ylabel(label, fontsize="small")
        panel.grid(True, alpha=0.3)
    if len(groups) > 1:
        legend: dict[str, Any] = {}
        for handle, text in zip(*grid[0].get_legend_handles_labels(), strict=True):
            legend.setdefault(text, handle)
        figure.legend(list(legend.values()), list(legend), loc="outside lower center",
                      ncols=min(len(legend), 2), fontsize="small")
    figure.suptitle(f"Steering figures over the sweep ({len(result.rows)} points; failed points "
                    "not shown)")
    return figure


def _category_positions(axis: Any) -> np.ndarray:
    """Where each value of a non-numeric axis is drawn: one place per distinct text."""
    places: dict[str, int] = {}
    return np.array([places.setdefault(str(value), len(places)) for value in axis.values],
                    dtype=int)


def _sweep_panel(axes: Any, axis: Any, x: np.ndarray, re_values: np.ndarray,
                 title: str) -> bool:
    """Draw one panel; True if it drew a sample of its points."""
    from matplotlib.ticker import MaxNLocator

    numeric = _numeric(axis)
    known = ~np.isnan(re_values)
    x, re_values = x[known], re_values[known]
    drawn = np.maximum(re_values, ROUND_OFF_FLOOR)
    thinned = len(x) > MOST_DRAWN_POINTS
    if len(x):
        values, where = np.unique(x, return_inverse=True)
        lowest = np.full(len(values), np.inf)
        np.minimum.at(lowest, where, drawn)
        axes.plot(values, lowest, "-", color="tab:blue", linewidth=1.2,
                  label="lowest RE at each value")
        shown = (np.linspace(0, len(x) - 1, MOST_DRAWN_POINTS).round().astype(int) if thinned
                 else np.arange(len(x)))
        sample_x, sample_re = x[shown], drawn[shown]
        at_floor = re_values[shown] <= ROUND_OFF_FLOOR
        axes.plot(sample_x[~at_floor], sample_re[~at_floor], "o", color="tab:blue",
                  markersize=4, label="RE of a point")
        if at_floor.any():
            axes.plot(sample_x[at_floor], sample_re[at_floor], "v", color="tab:orange",
                      markersize=6, label=f"RE {FLOOR_LABEL}")
    axes.axhline(ROUND_OFF_FLOOR, color="grey", linestyle=":", linewidth=1,
                 label=f"round-off floor {ROUND_OFF_FLOOR:g}")
    axes.set_yscale("log")
    axes.set_title(title, fontsize="medium")
    axes.set_xlabel(axis_label(axis.path))
    axes.set_ylabel("RE")
    axes.grid(True, which="major", alpha=0.3)
    if numeric:
        axes.xaxis.set_major_locator(MaxNLocator(nbins=6))
    else:
        places = _category_positions(axis)
        labels = {int(place): value for place, value in zip(places.tolist(), axis.values,
                                                            strict=True)}
        step = max(1, math.ceil(len(labels) / MOST_TICK_LABELS))
        shown_labels = list(labels.items())[::step]
        axes.set_xticks([place for place, _ in shown_labels],
                        [_cell(label) for _, label in shown_labels], rotation=30, ha="right")
    return thinned


def _tolerance_figure(result: Any) -> Any:
    figure = _figure((SINGLE_SIZE_IN[0] * 1.6, SINGLE_SIZE_IN[1]))
    table = result.percentile_table()
    for index, (metric, label) in enumerate(TOLERANCE_FIGURES):
        axes = figure.add_subplot(1, 3, index + 1)
        values = np.asarray(getattr(result, metric), dtype=float)
        positive = values[values > ROUND_OFF_FLOOR]
        logarithmic = metric == "residual_error" and len(positive) > 1 and (
            positive.max() > 100 * positive.min())
        if logarithmic:
            bins = np.geomspace(positive.min(), positive.max(), 51)
            axes.hist(np.maximum(values, positive.min()), bins=bins, color="tab:blue", alpha=0.8)
            axes.set_xscale("log")
        else:
            axes.hist(values, bins=50, color="tab:blue", alpha=0.8)
            axes.ticklabel_format(axis="x", style="sci", scilimits=(-3, 4))
        nominal = getattr(result.nominal, metric)
        if not logarithmic or nominal >= positive.min():
            axes.axvline(nominal, color="black", label="nominal")
        else:
            axes.text(0.02, 0.97, f"nominal {format_number(nominal, 3)},\nleft of this axis",
                      transform=axes.transAxes, va="top", fontsize="small")
        for value in table[metric].values():
            axes.axvline(value, color="tab:red", linestyle=":", linewidth=1)
        axes.set_xlabel(label.replace(" (dimensionless)", ""), fontsize="small")
        axes.set_ylabel("samples" if index == 0 else "")
    labelled = [axes for axes in figure.axes if axes.get_legend_handles_labels()[0]]
    if labelled:
        labelled[0].legend(loc="upper right")
    title = (f"{result.samples} samples, {result.distribution} deviations; red dotted: "
             f"p{', p'.join(f'{q:g}' for q in result.percentiles)}\n"
             + "\n".join(textwrap.wrap(f"design: {result.study_of}", 110)))
    figure.suptitle(title, fontsize="medium")
    return figure


def _figure(size_in: tuple[float, float]) -> Any:
    from matplotlib.figure import Figure

    return Figure(figsize=size_in, dpi=FIGURE_DPI, layout="constrained")


def _png(figure: Any) -> bytes:
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png")
    return buffer.getvalue()


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _numeric(axis: Any) -> bool:
    return all(_is_number(value) for value in axis.values)


def _numbers(values: Sequence[float]) -> str:
    return "[" + ", ".join(format_number(value) for value in values) + "]"


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return format_number(value)
    if isinstance(value, (list, tuple)):
        if all(isinstance(item, (int, float)) and not isinstance(item, bool) for item in value):
            return _numbers(value)
        return shown(value)  # a value the point refused (a nested list), shown abbreviated
    return str(value)


register_report_kind("sweep", render_sweep, SWEEP_FOLDER)
register_report_kind("tolerance", render_tolerance, TOLERANCE_FOLDER)
