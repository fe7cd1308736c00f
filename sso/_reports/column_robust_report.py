"""Report blocks of a column's robust phasing (``ColumnRun.robust``).

The robust designs beside the nominal optimum: RE per position with the active
ones, the tolerance study of every design on the same sample (p50, p95, max), the
nominal RE given up, the tolerance bands in the fitter's convention of yoke
phasing, and the steering feel. Rendered from the run's robust part alone
(:class:`sso._run.column_robust.ColumnRobustPart`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from sso._column.band import Interval, ToleranceBand
from sso._column.positions import PositionsResult
from sso._column.scenarios import PhasingOutcome
from sso._column.tolerances import SampleStudy
from sso._column.yields import limit_text, percent
from sso._reports.summary import Block, Heading, Paragraph, Table, number
from sso._run.column import ColumnRun
from sso._run.column_robust import (
    ColumnRobustPart,
    FeelPart,
    PositionsPart,
    RobustDesign,
    TolerancesPart,
)

SAME_FIGURE_RTOL = 1e-9
"""Two p95s of one design computed two ways agree to this (relative)."""
ROBUST_CAPTIONS = {
    "positions.png": "RE at every position (log scale) of each position's own optimum and of "
                     "the designs compared; the shared phasing's worst position is its "
                     "objective.",
    "tolerance_study.png": "RE over the same seeded sample of built columns (hardpoint and yoke "
                           "phase errors), as the fraction of columns at or below each RE, for "
                           "every design compared; p95 marked.",
    "phase_error.png": "RE against the error of each yoke phasing (the others at nominal), "
                       "every design compared; the band's RE limit dotted. A narrow valley "
                       "means a design that production cannot hold.",
    "steering_feel.png": "Speed ratio (output over input) against the steering-wheel angle from "
                         "straight ahead: around the left lock, on-centre and around the right "
                         "lock (shaded: the windows).",
}


def robust_blocks(run: ColumnRun) -> list[Block]:
    """Blocks of the robust part, or none when the run has none."""
    robust = run.robust
    if robust is None:
        return []
    blocks: list[Block] = [Heading(2, "Robust phasing"), Paragraph(
        "Designs compared, on the column of hardpoints.points_mm unless a position is named; "
        "yoke phasing delta in the fitter's convention (turn about the shaft from the pin axis "
        "of its yoke at joint k to that at joint k+1, 0 = in phase)."),
        _design_table(robust)]
    if robust.positions is not None:
        blocks += [Heading(3, "One phasing for every position"),
                   *_positions_blocks(robust, robust.positions)]
    if robust.tolerances is not None:
        blocks += [Heading(3, "Tolerance study on one sample"),
                   *_tolerance_blocks(robust, robust.tolerances)]
    if robust.band_re_limit is not None:
        blocks += [Heading(3, "Tolerance bands"), *_band_blocks(robust, robust.band_re_limit)]
    if robust.feel is not None:
        blocks += [Heading(3, "Steering feel"), *_feel_blocks(robust, robust.feel)]
    return blocks


def _design_table(robust: ColumnRobustPart) -> Table:
    rows = tuple((design.label, _angles(design.yoke_phase_deg), number(design.nominal_re, ".6g"))
                 for design in robust.designs)
    return Table(("design", "yoke phasing delta (deg)", "RE at the hardpoints"), rows)


def _positions_blocks(robust: ColumnRobustPart, positions: PositionsPart) -> list[Block]:
    names = list(positions.geometries)
    blocks: list[Block] = []
    geometry_rows = tuple((name, _angles(positions.geometries[name].beta_deg, ".2f"),
                           _angles(positions.geometries[name].plane_angle_deg, ".1f"))
                          for name in names)
    blocks.append(Table(("position", "operating angles beta (deg)",
                         "bend-plane angles gamma (deg)"), geometry_rows))
    header = ("phasing", "delta (deg)", *(f"RE {name}" for name in names), "worst",
              "active positions")
    rows = []
    result = positions.result
    if result is not None:
        for name, single in result.single_position.items():
            rows.append((f"{name}'s own optimum", _angles(single.yoke_phase_deg),
                         *(number(single.position_re[other], ".4g") for other in names),
                         number(single.worst_re, ".4g"), _worst_names(single.position_re)))
    for design in robust.designs:
        figures = design.positions
        if figures is None:
            continue
        rows.append((design.label, _angles(design.yoke_phase_deg),
                     *(number(figures.position_re[name], ".4g") for name in names),
                     number(figures.worst_re, ".4g"), ", ".join(figures.active_positions)))
    blocks.append(Table(header, tuple(rows)))
    if result is not None:
        blocks.append(_shared_phasing_paragraph(result))
    return blocks


def _shared_phasing_paragraph(result: PositionsResult) -> Paragraph:
    singles = {name: single.worst_re for name, single in result.single_position.items()}
    at_or_below = all(result.worst_re <= value * (1.0 + 1e-9) for value in singles.values())
    return Paragraph(
        f"Shared phasing ({result.positions_objective}): worst-position RE "
        f"{number(result.worst_re, '.6g')} at {', '.join(result.active_positions)}; "
        f"the best single-position optimum's worst is {number(min(singles.values()), '.6g')}"
        f". At or below every single-position optimum's worst: "
        f"{'yes' if at_or_below else 'NO'}. {_agreement(result)}.")


def _tolerance_blocks(robust: ColumnRobustPart, tolerances: TolerancesPart) -> list[Block]:
    settings = tolerances.tolerances
    blocks: list[Block] = [Paragraph(
        f"Sample: {settings.samples} built columns ({settings.distribution}, seed "
        f"{settings.seed}): every hardpoint coordinate off by {settings.hardpoint_mm:g} mm "
        f"and each yoke phasing by {settings.yoke_phase_deg:g} deg "
        f"({'standard deviation' if settings.distribution == 'normal' else 'half-width'}). "
        "Every design is judged on the same columns (common random numbers); percentiles by "
        "linear interpolation, CVaR95 the mean of the worst 5 %.")]
    rows = [_study_row(design.label, design.study) for design in robust.designs
            if design.study is not None]
    rows += [_study_row(f"equivalent nominal optimum ({_angles(equivalent.yoke_phase_deg)})",
                        equivalent.study)
             for equivalent in tolerances.nominal_equivalents]
    blocks.append(Table(("design", "nominal RE", "mean", "p50", "p95", "max", "CVaR95"),
                        tuple(rows)))
    blocks += yield_blocks(robust.designs)
    result = tolerances.result
    if result is not None:
        robust_study, nominal_study = result.robust_study, result.nominal_study
        fresh_robust = result.validation_robust_study
        fresh_nominal = result.validation_nominal_study
        equivalents = [equivalent.study.p95 for equivalent in tolerances.nominal_equivalents]
        # an equivalent optimum may be the chosen phasing itself, its p95 a round-off apart
        at_or_below = all(robust_study.p95 <= value * (1.0 + SAME_FIGURE_RTOL)
                          for value in equivalents)
        against_all = (f"; against every equivalent nominal optimum: "
                       f"{'yes' if at_or_below else 'NO'}" if equivalents else "")
        exact = (None if result.exact_choice is None
                 else result.exact_choice.optimisation.exact_optima)
        chosen = (f"least {result.objective_short}" if exact is None else
                  f"{result.exact_optimum_criterion}, chosen within the set of exact optima of "
                  f"dimension {exact.dimension} from {exact.starts} found")
        blocks.append(Paragraph(
            f"Tolerance-aware phasing ({chosen}): p95 "
            f"{number(robust_study.p95, '.4g')} against {number(nominal_study.p95, '.4g')} "
            f"for the nominal optimum on the same sample (at or below: "
            f"{'yes' if robust_study.p95 <= nominal_study.p95 else 'NO'}{against_all}); "
            f"nominal RE given up {number(result.nominal_re_given_up, '.3g')} "
            f"({number(result.nominal_re, '.3g')} against "
            f"{number(result.nominal_optimum_re, '.3g')}). On a fresh sample (seed "
            f"{settings.seed + 1}): p95 {number(fresh_robust.p95, '.4g')} against "
            f"{number(fresh_nominal.p95, '.4g')}. {_agreement(result)}."))
    return blocks


def yield_blocks(designs: Sequence[RobustDesign]) -> list[Block]:
    """Each design's built columns against the case's limits: the yields, their 95 %
    confidence intervals and the verdict (:mod:`sso._column.yields`)."""
    judged = [(design.label, design.yields) for design in designs if design.yields is not None]
    if not judged:
        return []
    first = judged[0][1]
    header = ("design", *(f"yield: {item.label} {limit_text(item)}" for item in first.limits),
              "yield of every limit (95 % CI)", "verdict")
    rows = tuple((label, *(percent(item.fraction) for item in yields.limits),
                  yields.together.text, yields.verdict_text)
                 for label, yields in judged)
    return [Paragraph(
        "The same built columns against the case's [limits]: the yield is the fraction whose "
        "figure (from lock to lock) meets the limit, with Wilson's 95 % score interval; the "
        "verdict against [limits] yield is 'meets' when the interval of every limit together "
        "lies at or above it, 'fails' when below, 'not decided' when it straddles it, with the "
        "samples that would decide it (sso run exits 1 unless the recommended assembly meets "
        "it, sso evaluate unless the assembly as built does). The steering criteria's 'within' "
        "judge each nominal design only."), Table(header, rows)]


def _band_blocks(robust: ColumnRobustPart, limit: float) -> list[Block]:
    blocks: list[Block] = [Paragraph(
        f"RE limit {number(limit, '.4g')}. Each interval: where one angle may lie with every "
        "other at nominal and RE at or below the limit (edges where RE equals the limit; "
        "'whole period' where the phasing never reaches it). Yoke phasings delta in the "
        "fitter's convention; the box: half-widths of a joint tolerance on all phasings at "
        "once whose worst corner stays at the limit.")]
    for design in robust.designs:
        band: ToleranceBand | None = design.band
        if band is None:
            blocks.append(Paragraph(f"{design.label}: {design.band_note}."))
            continue
        rows = [_interval_row(interval) for interval in band.yoke_phase]
        rows += [_interval_row(interval) for interval in band.operating_angle]
        blocks += [Paragraph(f"{design.label} (RE {number(band.nominal_re, '.3g')}):"),
                   Table(("angle", "nominal (deg)", "lower (deg)", "upper (deg)"), tuple(rows)),
                   Paragraph(f"Box of phase errors: +-{_angles(band.box_half_width_deg)} deg "
                             f"(scale {number(band.box_scale, '.3g')}); worst corner RE "
                             f"{number(band.box_corner_max_re, '.4g')}, grid maximum "
                             f"{number(band.box_grid_max_re, '.4g')}.")]
    return blocks


def _interval_row(interval: Interval) -> tuple[str, ...]:
    name = interval.name.replace("yoke_phase_deg", "delta").replace("beta_deg", "beta")
    lower = number(interval.lower_deg, ".3f")
    upper = number(interval.upper_deg, ".3f")
    if not interval.lower_at_limit and not interval.upper_at_limit \
            and name.startswith("delta"):
        lower, upper = "whole period", "whole period"
    elif not interval.lower_at_limit:
        lower += " (never reaches the limit)"
    return (name, number(interval.nominal_deg, ".3f"), lower, upper)


def _feel_blocks(robust: ColumnRobustPart, feel: FeelPart) -> list[Block]:
    blocks: list[Block] = [Paragraph(
        f"Straight ahead at input angle theta = {feel.straight_ahead_deg:g} deg (from the "
        f"first bend plane's normal), windows +-{feel.window_deg:g} deg, lock "
        f"{feel.lock_deg:g} deg from straight ahead. Fluctuation: peak-to-peak speed "
        "ratio in the window.")]
    rows = tuple((design.label, number(design.feel.re, ".4g"),
                  number(design.feel.on_centre_fluctuation, ".4g"),
                  number(design.feel.lock_fluctuation, ".4g"))
                 for design in robust.designs if design.feel is not None)
    blocks.append(Table(("design", "RE", "fluctuation on-centre", "fluctuation at lock"), rows))
    if feel.note is not None:
        blocks.append(Paragraph(f"On-centre phasing: {feel.note}."))
    elif feel.result is not None:
        blocks.append(Paragraph(
            f"On-centre phasing (RE + {feel.result.on_centre_weight:g} x on-centre variance): "
            f"{feel.result.message}."))
    return blocks


def _study_row(label: str, study: SampleStudy) -> tuple[str, ...]:
    return (label, number(study.nominal_re, ".3g"),
            *(number(getattr(study, name), ".4g")
              for name in ("mean", "p50", "p95", "max", "cvar95")))


def _agreement(result: PhasingOutcome) -> str:
    crosscheck = result.crosscheck
    return str(crosscheck.message) if crosscheck else "one solver, no cross-check"


def _worst_names(values: Mapping[str, float]) -> str:
    worst = max(values.values())
    return ", ".join(name for name, value in values.items() if value >= worst * (1.0 - 1e-6))


def _angles(values: Sequence[float], spec: str = ".3f") -> str:
    return ", ".join(number(value, spec) for value in values)
