"""Report blocks of a column's steering figures: lock to lock, per assembly, and the criteria.

Rendered from the run's :class:`sso.SteeringAssessment` (``ColumnRun.steering``).
"""

from __future__ import annotations

from collections.abc import Sequence

from sso._column.steering_criteria import AssessedDesign
from sso._reports.summary import Block, Heading, Paragraph, Table, number
from sso._run.column import ColumnRun

STEERING_PLOT = "steering.png"
STEERING_CAPTION = ("Speed ratio (output over input speed), output torque ratio and "
                    "transmission error (output turn minus steering-wheel turn from straight "
                    "ahead) of every assembly compared, against the steering-wheel angle from "
                    "lock to lock (positive: clockwise as the driver sees the wheel).")


def steering_blocks(run: ColumnRun) -> list[Block]:
    """The section "Steering from lock to lock"."""
    steering = run.steering
    lock = steering.lock_deg
    designs = steering.designs
    settings = (f"Steering-wheel angle from -{lock:g} to +{lock:g} deg (steering.lock_deg; "
                f"{2.0 * lock / 360.0:.3g} turns lock to lock), straight ahead at input yoke "
                f"angle theta = {steering.straight_ahead_deg:g} deg "
                "(steering.straight_ahead_deg, from the first bend plane's normal), positive "
                "clockwise as the driver sees the wheel. Speed ratio: output over input speed "
                "(mean 1 over a turn); output torque ratio: its inverse (no friction, no "
                "inertia); transmission error: output turn minus steering-wheel turn from "
                "straight ahead. Fluctuations are peak to peak, in percent of the mean ratio "
                f"1; on-centre: within +-{steering.on_centre_deg:g} deg of straight ahead "
                "(steering.on_centre_deg). Extremes are exact (the chain's stationary angles), "
                "not sampled.")
    figure_rows = tuple(_figure_row(design) for design in designs)
    return [Heading(2, "Steering from lock to lock"), Paragraph(settings),
            Table(("assembly", "speed-ratio fluctuation (%)", "output-torque fluctuation (%)",
                   "transmission error min / max, peak to peak (deg)", "speed ratio on-centre",
                   "on-centre fluctuation (%)", "speed ratio at the locks (acw / cw)",
                   "transmission error at the locks (acw / cw, deg)"), figure_rows),
            Heading(3, "Steering criteria"), _criteria_table(designs),
            *_built_columns_note(run), Paragraph(_excitation_note(run))]


def _built_columns_note(run: ColumnRun) -> list[Block]:
    """Where the case has tolerances: the criteria judge nominal designs, the yield the
    built columns (so a 'within' cannot hide a failing yield)."""
    yields = run.judged_yields
    if yields is None:
        return []
    return [Paragraph(f"'within' judges each design as drawn. Built as production builds it "
                      f"(the [tolerances] sample), {run.judged_columns}: {yields.sentence} "
                      "(Robust phasing, below).")]


def _excitation_note(run: ColumnRun) -> str:
    if run.excitation["as_built"].application == "driveline":
        return ("Excitation limits: the SAE AE-7 driveline limits judge the excitation rows "
                "below (excitation.application = 'driveline').")
    return f"Excitation limits: {run.steering.excitation_note}."


def _figure_row(design: AssessedDesign) -> tuple[str, ...]:
    figures = design.range
    return (design.label, number(figures.speed_fluctuation_percent, ".4g"),
            number(figures.torque_fluctuation_percent, ".4g"),
            f"{number(figures.transmission_error_min_deg, '.4g')} / "
            f"{number(figures.transmission_error_max_deg, '.4g')}, "
            f"{number(figures.transmission_error_peak_to_peak_deg, '.4g')}",
            number(figures.on_centre_speed_ratio, ".6g"),
            number(figures.on_centre_fluctuation_percent, ".4g"),
            " / ".join(number(value, ".6g") for value in figures.lock_speed_ratio),
            " / ".join(number(value, ".4g") for value in figures.lock_transmission_error_deg))


def _criteria_table(designs: Sequence[AssessedDesign]) -> Table:
    rows = []
    for index, criterion in enumerate(designs[0].criteria):
        limit = ("not set" if criterion.limit is None else
                 f"{criterion.sense} {criterion.limit:g} {criterion.unit}")
        cells = [f"{criterion.name} ({criterion.unit})", limit, criterion.source]
        for design in designs:
            judged = design.criteria[index]
            verdict = {None: "no limit", True: "within", False: "OUTSIDE"}[judged.within]
            cells.append(f"{number(judged.value, '.4g')} ({verdict})")
        rows.append(tuple(cells))
    return Table(("criterion", "limit", "source of the limit",
                  *(design.label for design in designs)), tuple(rows))
