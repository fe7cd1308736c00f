"""The report of a column's tolerance study, registered as the report kind
``"column_tolerance"`` of :func:`sso.write_report`.

``tolerance.csv`` (every built column: its angles, its yoke phase errors and its
figures, 6 digits), ``report.md`` and ``report.html`` from the same blocks as every
report, ``tolerance_histogram.png`` (one histogram per figure, the case's limits
drawn) and ``tolerance_sensitivity.png`` (which tolerance matters,
:mod:`sso._studies.column_yields_report`); ``result.json``,
the saved result, is added by :func:`sso.write_report`. The result is read by its
attributes only (its module imports this one, to register the kind).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from sso._column.yields import percent
from sso._display import format_number
from sso._files import FileContents, StreamedFile
from sso._reports.kinds import register_report_kind
from sso._reports.summary import Block, Heading, Image, Paragraph, Table
from sso._studies.column_yields_report import (
    SENSITIVITY_PLOT,
    limit_of,
    sensitivity_figure,
    yield_blocks,
)
from sso._studies.report import (
    SINGLE_SIZE_IN,
    TOLERANCE_CSV,
    TOLERANCE_FOLDER,
    TOLERANCE_PLOT,
    _add_documents,
    _figure,
    _numbers,
    _png,
    sample_table,
)

# (figure, label with unit), in the order of the study's figures.
FIGURES = (
    ("residual_error", "residual error RE (dimensionless)"),
    ("speed_fluctuation_percent", "speed-ratio fluctuation, lock to lock (%)"),
    ("torque_fluctuation_percent", "output-torque fluctuation, lock to lock (%)"),
    ("largest_transmission_error_deg", "largest |transmission error|, lock to lock (deg)"),
)


def render_column_tolerance(result: Any, formats: tuple[str, ...]) -> dict[str, FileContents]:
    """Report files of a column's tolerance study, keyed by file name (the samples' table
    streamed as it is written)."""
    files: dict[str, FileContents] = {}
    if "csv" in formats:
        files[TOLERANCE_CSV] = _csv(result)
    images = {TOLERANCE_PLOT: _png(_histograms(result))} if "png" in formats else {}
    sensitivity = sensitivity_figure(result, _figure) if "png" in formats else None
    if sensitivity is not None:
        images[SENSITIVITY_PLOT] = _png(sensitivity)
    files.update(images)
    _add_documents(files, formats, _blocks(result, tuple(images)), images)
    return files


def _csv(result: Any) -> StreamedFile:
    joints = result.geometry.joint_count
    header = ["sample", *(f"beta_deg[{k}]" for k in range(joints)),
              *(f"plane_angle_deg[{k}]" for k in range(joints - 1)),
              *(f"yoke_phase_error_deg[{k}]" for k in range(joints - 1)),
              *(name for name, _ in FIGURES)]
    return sample_table(header, (result.beta_deg, result.plane_angle_deg,
                                 result.yoke_phase_error_deg,
                                 *(getattr(result, name) for name, _ in FIGURES)))


def _blocks(result: Any, image_files: tuple[str, ...]) -> list[Block]:
    spread = "standard deviation" if result.distribution == "normal" else "half-width"
    table = result.percentile_table()
    blocks: list[Block] = [
        Heading(1, "Tolerance study of a steering column"),
        Paragraph(f"Design studied: {result.study_of}. Yoke phasing "
                  f"{_numbers(result.yoke_phase_deg)} deg; operating angles "
                  f"{_numbers(result.geometry.beta_deg)} deg, bend-plane angles "
                  f"{_numbers(result.geometry.plane_angle_deg)} deg."),
        Paragraph(f"Errors: {result.distribution} ({spread}): every coordinate of every "
                  f"hardpoint {format_number(result.hardpoint_mm)} mm, each yoke phasing "
                  f"{format_number(result.yoke_phase_tolerance_deg)} deg; {result.samples} "
                  f"built columns, seed {result.seed}. Each built column runs with its own "
                  "operating and bend-plane angles; its steering figures are taken from lock "
                  f"to lock, +-{format_number(result.lock_deg)} deg of the steering wheel from "
                  f"straight ahead (input angle {format_number(result.straight_ahead_deg)} deg "
                  "from its first bend plane's normal)."),
        Table(("figure", "nominal", *(f"p{q:g}" for q in result.percentiles)),
              tuple((label, format_number(result.nominal[name]),
                     *(format_number(value) for value in table[name].values()))
                    for name, label in FIGURES)),
    ]
    if TOLERANCE_PLOT in image_files:
        blocks.append(Image(TOLERANCE_PLOT, "Histograms of the built columns' figures; black: "
                            "nominal, red dotted: the percentiles above, orange dashed: the "
                            "case's limit."))
    judged = yield_blocks(result, image_files)
    percentiles_heading: list[Block] = ([Heading(2, "Percentiles of the built columns' figures")]
                                        if judged else [])
    return [*blocks[:3], *judged, *percentiles_heading, *blocks[3:]]


def _histograms(result: Any) -> Any:
    figure = _figure((SINGLE_SIZE_IN[0] * 1.6, SINGLE_SIZE_IN[1] * 1.4))
    table = result.percentile_table()
    for index, (name, label) in enumerate(FIGURES):
        axes = figure.add_subplot(2, 2, index + 1)
        axes.hist(np.asarray(getattr(result, name), dtype=float), bins=50, color="tab:blue",
                  alpha=0.8)
        axes.axvline(result.nominal[name], color="black", label="nominal")
        for value in table[name].values():
            axes.axvline(value, color="tab:red", linestyle=":", linewidth=1)
        limit = limit_of(result, name)
        if limit is not None and limit.limit is not None:
            axes.axvline(limit.limit, color="tab:orange", linestyle="--", linewidth=1.5,
                         label=f"limit {format_number(limit.limit)} {limit.unit}, yield "
                               f"{percent(limit.fraction)}")
            axes.legend(loc="upper right", fontsize="small")
        axes.ticklabel_format(axis="x", style="sci", scilimits=(-3, 4))
        axes.set_xlabel(label, fontsize="small")
        axes.set_ylabel("built columns" if index % 2 == 0 else "")
    figure.axes[0].legend(loc="upper right")
    figure.suptitle(f"{result.samples} built columns, {result.distribution} errors; red dotted: "
                    f"p{', p'.join(f'{q:g}' for q in result.percentiles)}", fontsize="medium")
    return figure


register_report_kind("column_tolerance", render_column_tolerance, TOLERANCE_FOLDER)
