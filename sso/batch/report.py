"""Summary reports of sweeps and tolerance studies: Markdown, CSV/JSON, and plots.

matplotlib is imported only inside the plotting functions (object-oriented
``Figure`` API, no pyplot state), so a run without plots never loads it.
"""

from __future__ import annotations

import io
import json
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from sso.files import write_bytes_atomic, write_text_atomic

if TYPE_CHECKING:
    from sso.batch.results import SweepResult, ToleranceResult

# RE of an exactly cancelling design is 0 to round-off; plots floor it here.
RE_PLOT_FLOOR = 1e-32
REPORT_ROWS = 50
FIGURE_SIZE_IN = (7.0, 4.5)
FIGURE_DPI = 120


def write_sweep_report(result: SweepResult, out_dir: Path, plots: bool) -> list[Path]:
    """Write ``report.md`` and, with ``plots``, the sweep's plot; return the paths."""
    paths = []
    plot_name = None
    if plots:
        plot_name, figure = _sweep_figure(result)
        paths.append(_save(figure, out_dir / plot_name))
    paths.insert(0, write_text_atomic(out_dir / "report.md", _sweep_markdown(result, plot_name)))
    return paths


def write_tolerance_report(result: ToleranceResult, out_dir: Path, plots: bool) -> list[Path]:
    """Write ``tolerance.csv``, ``tolerance.json``, ``tolerance.md`` and the histogram."""
    from sso.batch.table import format_cell

    out_dir.mkdir(parents=True, exist_ok=True)
    joints = result.design.n_joints
    header = ["sample", *(f"beta_deg[{k}]" for k in range(joints)),
              *(f"phase_deg[{k}]" for k in range(joints - 1)),
              "residual_error", "fluctuation", "max_output_accel_rad_s2"]
    table = np.column_stack([result.beta_deg, result.phase_deg, result.residual_error,
                             result.fluctuation, result.max_output_accel_rad_s2])
    lines = [",".join(header)]
    lines += [",".join([str(index), *(format_cell(value) for value in row.tolist())])
              for index, row in enumerate(table)]
    paths = [write_text_atomic(out_dir / "tolerance.csv", "\n".join(lines) + "\n"),
             write_text_atomic(out_dir / "tolerance.json",
                               json.dumps(result.to_dict(), indent=2) + "\n")]
    plot_name = None
    if plots:
        plot_name = "tolerance_histogram.png"
        paths.append(_save(_tolerance_figure(result), out_dir / plot_name))
    paths.append(write_text_atomic(out_dir / "tolerance.md",
                                   _tolerance_markdown(result, plot_name)))
    return paths


def _sweep_markdown(result: SweepResult, plot_name: str | None) -> str:
    axes_lines = [f"- `{axis.path}`: {len(axis.values)} values, "
                  f"{_cell(axis.values[0])} .. {_cell(axis.values[-1])}" for axis in result.axes]
    lines = ["# Sweep", "", f"Action: {result.action}; mode: {result.mode}; "
             f"{len(result.rows)} points.", "", *axes_lines, "", "## Summary", "", "```",
             result.summary(), "```", ""]
    if plot_name is not None:
        lines += [f"![residual error]({plot_name})", ""]
    paths = [axis.path for axis in result.axes]
    columns = ["point", *paths, "status", "residual_error", "fluctuation", "success",
               "crosscheck_agree", "time_s"]
    shown = sorted(result.rows, key=_re_key)[:REPORT_ROWS]
    lines += [f"## Lowest residual error ({len(shown)} of {len(result.rows)} points; "
              "all in sweep.csv)", "", "| " + " | ".join(columns) + " |",
              "|" + "---|" * len(columns)]
    lines += ["| " + " | ".join(_cell(row.get(column)) for column in columns) + " |"
              for row in shown]
    if result.failed:
        lines += ["", "## Failed points", "", "| point | error |", "|---|---|"]
        lines += [f"| {row['point']} | {_cell(row['error'])} |" for row in result.failed]
    return "\n".join(lines) + "\n"


def _tolerance_markdown(result: ToleranceResult, plot_name: str | None) -> str:
    percentiles = list(result.percentiles)
    header = ["figure", "nominal", *(f"p{q:g}" for q in percentiles)]
    lines = ["# Tolerance study", "",
             f"Design: beta {list(result.design.beta_deg)} deg, phase "
             f"{list(result.design.phase_deg)} deg, {result.design.model} model, "
             f"{result.input_speed_rpm:g} rpm.",
             f"Deviations: {result.distribution}, beta {list(result.beta_tolerance_deg)} deg, "
             f"phase {list(result.phase_tolerance_deg)} deg "
             f"({'standard deviation' if result.distribution == 'normal' else 'half-width'}); "
             f"{result.samples} samples, seed {result.seed}.", "",
             "| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for metric, values in result.percentile_table().items():
        cells = [f"{getattr(result.nominal, metric):.6g}",
                 *(f"{values[q]:.6g}" for q in percentiles)]
        lines.append(f"| {metric} | " + " | ".join(cells) + " |")
    if plot_name is not None:
        lines += ["", f"![histograms]({plot_name})"]
    return "\n".join(lines) + "\n"


def _sweep_figure(result: SweepResult) -> tuple[str, Any]:
    """``sweep_heatmap.png`` for a two-axis product, else RE against the first axis."""
    from matplotlib.colors import LogNorm

    figure = _figure()
    axes = figure.add_subplot()
    scalar = [axis for axis in result.axes if all(_is_number(value) for value in axis.values)]
    if result.mode == "product" and len(result.axes) == 2 and len(scalar) == 2:
        rows_axis, columns_axis = result.axes
        grid = np.full((len(rows_axis.values), len(columns_axis.values)), np.nan)
        for row in result.rows:
            if row["status"] == "ok":
                grid[row["point"] // grid.shape[1], row["point"] % grid.shape[1]] = max(
                    row["residual_error"], RE_PLOT_FLOOR)
        if np.isfinite(grid).any():
            image = axes.imshow(grid, origin="lower", aspect="auto", cmap="viridis",
                                norm=LogNorm(np.nanmin(grid), np.nanmax(grid)))
            figure.colorbar(image, ax=axes, label="residual error RE (log scale)")
        _index_ticks(axes.set_xticks, columns_axis.values)
        _index_ticks(axes.set_yticks, rows_axis.values)
        axes.set_xlabel(columns_axis.path)
        axes.set_ylabel(rows_axis.path)
        axes.set_title("Residual error over the sweep (blank: failed)")
        return "sweep_heatmap.png", figure
    axis = result.axes[0]
    ok = [row for row in result.rows if row["status"] == "ok"]
    numeric = axis in scalar
    positions = {value: index for index, value in enumerate(dict.fromkeys(map(str, axis.values)))}
    x = [row[axis.path] if numeric else positions[str(row[axis.path])] for row in ok]
    axes.semilogy(x, [max(row["residual_error"], RE_PLOT_FLOOR) for row in ok], "o-"
                  if len(result.axes) == 1 else "o", label="best RE")
    if not numeric:
        axes.set_xticks(list(positions.values()), list(positions))
    axes.set_xlabel(axis.path)
    axes.set_ylabel("residual error RE")
    failed = len(result.rows) - len(ok)
    axes.set_title(f"Residual error against {axis.path}"
                   + (f" ({failed} failed points not shown)" if failed else ""))
    axes.grid(True, which="both", alpha=0.3)
    return "sweep_re.png", figure


def _tolerance_figure(result: ToleranceResult) -> Any:
    figure = _figure(width_scale=1.6)
    labels = {"residual_error": "residual error RE", "fluctuation": "fluctuation (p-p / input)",
              "max_output_accel_rad_s2": "peak output accel, rad/s^2"}
    table = result.percentile_table()
    for index, (metric, label) in enumerate(labels.items()):
        axes = figure.add_subplot(1, 3, index + 1)
        axes.hist(getattr(result, metric), bins=50, color="tab:blue", alpha=0.8)
        axes.axvline(getattr(result.nominal, metric), color="black", label="nominal")
        for value in table[metric].values():
            axes.axvline(value, color="tab:red", linestyle=":", linewidth=1)
        axes.set_xlabel(label)
        axes.set_ylabel("samples" if index == 0 else "")
        axes.ticklabel_format(axis="x", style="sci", scilimits=(-3, 4))
    figure.axes[0].legend(loc="upper right")
    figure.suptitle(f"{result.samples} samples, {result.distribution} deviations; red dotted: "
                    f"p{', p'.join(f'{q:g}' for q in result.percentiles)}")
    return figure


def _figure(width_scale: float = 1.0) -> Any:
    from matplotlib.figure import Figure

    return Figure(figsize=(FIGURE_SIZE_IN[0] * width_scale, FIGURE_SIZE_IN[1]),
                  dpi=FIGURE_DPI, layout="constrained")


def _save(figure: Any, path: Path) -> Path:
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png")
    return write_bytes_atomic(path, buffer.getvalue())


def _index_ticks(set_ticks: Any, values: Sequence[Any]) -> None:
    """Label cell indices with their values, at most about ten labels."""
    step = max(1, -(-len(values) // 10))
    positions = list(range(0, len(values), step))
    set_ticks(positions, [f"{values[index]:g}" for index in positions])


def _re_key(row: dict[str, Any]) -> tuple[bool, float]:
    return row["status"] != "ok", row.get("residual_error") or 0.0


def _is_number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value).replace("|", "\\|").replace("\n", " ")
