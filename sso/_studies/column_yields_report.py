"""The yields and sensitivity of a column tolerance study, as summary parts, report blocks
and the bar chart ``tolerance_sensitivity.png``.

Read from the study's result alone (:mod:`sso._studies.column_tolerance`): its
``yields``, ``sensitivity`` and ``halved`` (:mod:`sso._studies.column_yields`).
"""

from __future__ import annotations

from typing import Any

from sso._column.sensitivity import FigureSensitivity
from sso._column.yields import LimitYield, YieldJudgement, limit_text, percent
from sso._display import Part, TextTable, format_number
from sso._reports.summary import Block, Heading, Image, Paragraph, Table

SENSITIVITY_PLOT = "tolerance_sensitivity.png"
SUMMARY_CONTRIBUTORS = 3
"""Tolerances the summary names per figure (the report lists them all)."""
SHOWN_INDEX = 0.005
"""Tolerances whose every index is below this are left out of the report's table."""
PLOTTED_TOLERANCES = 10


def nominal_value(result: Any, figure: str) -> float:
    """The nominal design's value of a limited figure."""
    if figure == "largest_operating_angle_deg":
        return float(max(result.geometry.beta_deg))
    return float(result.nominal[figure])


def limit_of(result: Any, figure: str) -> LimitYield | None:
    """The yield of the limit on ``figure``, or None when it has none."""
    yields: YieldJudgement | None = result.yields
    for item in () if yields is None else yields.limits:
        if item.figure == figure:
            return item
    return None


def _rows(result: Any, yields: YieldJudgement) -> tuple[tuple[str, ...], ...]:
    def row(item: LimitYield) -> tuple[str, ...]:
        if item.limit is None:
            nominal = ""
        else:
            value = nominal_value(result, item.figure)
            nominal = (f"{format_number(value)} {item.unit} "
                       f"({'meets' if value <= item.limit else 'EXCEEDS'})")
        return (item.label, limit_text(item), nominal, f"{item.passed} of {item.samples}",
                percent(item.fraction), f"{percent(item.low)} to {percent(item.high)}")

    return tuple(row(item) for item in (*yields.limits, yields.together))


YIELD_HEADER = ("limit on", "limit", "nominal design", "built columns meeting it", "yield",
                "95 % confidence interval")


def yield_parts(result: Any) -> list[Part]:
    """The verdict, the yields, the largest contributors and the halved ones, for
    the study's summary."""
    yields: YieldJudgement | None = result.yields
    if yields is None:
        return []
    parts: list[Part] = [f"  verdict: {yields.sentence}",
                         TextTable(YIELD_HEADER, _rows(result, yields))]
    for found in result.sensitivity:
        named = ", ".join(f"{item.tolerance} {percent(item.index)}"
                          for item in found.contributions[:SUMMARY_CONTRIBUTORS])
        parts.append(f"  largest first-order shares of the {found.label} variance: {named}; "
                     f"interactions {percent(found.interactions)}")
    parts += [f"  with {item.tolerance} halved to {format_number(item.tolerance_value)} "
              f"{item.unit} (re-sampled): yield of every limit {item.yields.together.text}"
              for item in result.halved]
    return parts


def yield_blocks(result: Any, image_files: tuple[str, ...]) -> list[Block]:
    """Report blocks: the yields and verdict, the sensitivity table and chart, the
    halved tolerances."""
    yields: YieldJudgement | None = result.yields
    if yields is None:
        return []
    blocks: list[Block] = [
        Heading(2, "Yield against the case's limits"),
        Paragraph(f"Verdict: {yields.sentence}."),
        Table(YIELD_HEADER, _rows(result, yields)),
        Paragraph("Yield: the fraction of built columns whose figure is at or below the limit. "
                  "Interval: Wilson's score interval at 95 % (Wilson 1927). Verdict: meets "
                  "when the interval of every limit together lies at or above the required "
                  "yield, fails when it lies below, not decided when it straddles it; only "
                  "'meets' signs the column off (sso tolerance exits 1 otherwise)."),
    ]
    if result.sensitivity:
        blocks += [Heading(2, "Which tolerance matters"), Paragraph(
            "First-order variance-based sensitivity index of each limited figure that some "
            "built column fails, to each tolerance: the share of the figure's variance that "
            "tolerance explains alone, Var(E[Y | X_i]) / Var(Y), estimated from the study's own "
            "samples (equal-count bins, Plischke, Borgonovo and Smith 2013). 'interactions': "
            "the share no single tolerance explains. delta_k: the error of yoke phasing k "
            "(spline clearance and assembly)."), _sensitivity_table(result.sensitivity)]
        if SENSITIVITY_PLOT in image_files:
            blocks.append(Image(SENSITIVITY_PLOT, "First-order sensitivity index of each "
                                "limited figure to the tolerances that matter most."))
    for item in result.halved:
        blocks.append(Paragraph(
            f"{item.tolerance} halved to {format_number(item.tolerance_value)} {item.unit} "
            f"(the largest contributor to the {' and the '.join(item.largest_in)}), "
            f"re-sampled (the same draws, its errors halved): yield of every limit "
            f"{item.yields.together.text}, against {yields.together.text} as toleranced."))
    return blocks


def _sensitivity_table(found: tuple[FigureSensitivity, ...]) -> Table:
    by_tolerance = [{item.tolerance: item.index for item in figure.contributions}
                    for figure in found]
    order = [item.tolerance for item in found[0].contributions]
    order.sort(key=lambda name: -max(indices[name] for indices in by_tolerance))
    rows = [(name, *(percent(indices[name]) for indices in by_tolerance)) for name in order
            if max(indices[name] for indices in by_tolerance) >= SHOWN_INDEX]
    rows.append(("interactions", *(percent(figure.interactions) for figure in found)))
    return Table(("tolerance", *(f"share of {figure.label}" for figure in found)), tuple(rows))


def sensitivity_figure(result: Any, figure_factory: Any) -> Any:
    """The bar chart of the largest indices, or None without sensitivity."""
    found: tuple[FigureSensitivity, ...] = result.sensitivity
    if not found:
        return None
    by_tolerance = [{item.tolerance: item.index for item in figure.contributions}
                    for figure in found]
    names = sorted(by_tolerance[0], key=lambda name: -max(indices[name]
                                                          for indices in by_tolerance))
    names = names[:PLOTTED_TOLERANCES][::-1]
    figure = figure_factory((7.0, 4.5))
    axes = figure.add_subplot(1, 1, 1)
    height = 0.8 / len(found)
    for index, (sensitivity, indices) in enumerate(zip(found, by_tolerance, strict=True)):
        positions = [place + (index - (len(found) - 1) / 2) * height
                     for place in range(len(names))]
        axes.barh(positions, [indices[name] for name in names], height=height,
                  label=sensitivity.label)
    axes.set_yticks(range(len(names)), names)
    axes.set_xlabel("first-order sensitivity index (share of the figure's variance)")
    axes.set_xlim(0.0, 1.0)
    axes.legend(loc="lower right", fontsize="small")
    figure.suptitle("Which tolerance matters", fontsize="medium")
    return figure
