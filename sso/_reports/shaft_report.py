"""The report of a shaft series: a case run (:class:`sso._run.shaft_series.ShaftSeriesRun`)
or an optimisation made in Python (:class:`sso.OptimisationResult`).

Both are rendered from the result object alone: its designs carry their figures
and speed curves (:class:`sso._shafts.curves.ComparedDesign`), so nothing is
rebuilt or recomputed here. Files: ``speeds.csv``, ``polar.png`` and
``cartesian.png``, ``report.md`` and ``report.html`` (``result.json`` is added by
:func:`sso._reports.kinds.render_report`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from sso._reports import documents
from sso._reports.plots import render_plots
from sso._reports.speeds import render_speeds_csv
from sso._reports.summary import (
    NUMERICS_HEADING,
    Block,
    Heading,
    Image,
    Paragraph,
    Table,
    closing_blocks,
    number,
    opening_blocks,
)
from sso._run.shaft_series import ShaftSeriesRun
from sso._run.signed_figures import figure_lines, shaft_series_figures
from sso._shafts.curves import ComparedDesign
from sso._shafts.exact_optima import EXTENT_METHOD, ExactOptimumSet, end_kind
from sso._shafts.optimise import OptimisationResult
from sso._shafts.options import OPTION_NAMES

# (evaluation field, row label with unit, format)
FIGURES = (
    ("residual_error", "residual error RE (dimensionless)", ".4g"),
    ("residual_error_rpm2", "residual error U = w_in^2 RE (rpm^2)", ".4g"),
    ("speed_min_rpm", "output speed min (rpm)", ".6g"),
    ("speed_max_rpm", "output speed max (rpm)", ".6g"),
    ("fluctuation_rpm", "fluctuation, peak to peak (rpm)", ".4g"),
    ("fluctuation", "fluctuation / input speed (dimensionless)", ".4g"),
    ("mean_speed_ratio", "mean output / input speed", ".6g"),
    ("transmission_error_deg", "transmission error, max |out - in| (deg)", ".4g"),
    ("max_output_accel_rad_s2", "output acceleration, max |dw/dt| (rad/s^2)", ".4g"),
    ("torque_ratio_min", "torque ratio T_out/T_in min", ".6g"),
    ("torque_ratio_max", "torque ratio T_out/T_in max", ".6g"),
    ("samples", "quadrature angles in [0, 180) deg", "d"),
    ("quadrature_error", "quadrature error estimate of RE", ".2g"),
)
PYTHON_NAME = "optimisation"
"""The name a report gives an optimisation made in Python (it has no case)."""


@dataclass(frozen=True)
class ShaftReport:
    """What a shaft-series report shows, gathered from a run or an optimisation."""

    name: str
    description: str
    case_rows: tuple[tuple[str, str], ...]
    designs: tuple[ComparedDesign, ...]
    optimisation: OptimisationResult | None
    success: bool
    verdict: str
    warnings: tuple[str, ...]
    versions: Mapping[str, str] | None
    plot_heading: str


def run_files(run: ShaftSeriesRun, formats: tuple[str, ...]) -> dict[str, bytes]:
    """Report files of a shaft-series case run."""
    return report_files(_of_run(run), formats)


def optimisation_files(result: OptimisationResult, formats: tuple[str, ...]) -> dict[str, bytes]:
    """Report files of an optimisation made with :func:`sso.optimise`."""
    return report_files(_of_optimisation(result), formats)


def report_files(report: ShaftReport, formats: tuple[str, ...]) -> dict[str, bytes]:
    """The files of ``report`` in ``formats`` (``result.json`` excepted), by file name."""
    return documents.report_files(
        formats, lambda: {"speeds.csv": render_speeds_csv(report.designs)},
        lambda: render_plots(report.designs, report.name, report.plot_heading),
        lambda images: report_blocks(report, images))


def report_blocks(report: ShaftReport, image_files: Sequence[str]) -> list[Block]:
    """Blocks of the whole report."""
    figures, trade = shaft_headline(report.designs)
    blocks = opening_blocks(report.name, report.description,
                            Table(("item", "value"), report.case_rows), report.success, figures)
    if trade is not None:
        blocks.append(Paragraph(trade))
    blocks += [Heading(2, "Designs"), _design_table(report.designs),
               Heading(2, "Figures of merit"), _figure_table(report.designs),
               Heading(2, NUMERICS_HEADING), Paragraph(report.verdict)]
    if report.optimisation is not None and report.optimisation.exact_optima is not None:
        blocks += [Heading(3, "Exact optima"),
                   *exact_optima_blocks(report.optimisation.exact_optima)]
    if report.optimisation is not None:
        blocks += [Heading(3, "Solvers"), _solver_table(report.optimisation),
                   Heading(3, "Cross-check"), Paragraph(_crosscheck_text(report.optimisation)),
                   Heading(3, "Every run"), _runs_table(report.optimisation)]
    images = [Image(name, _caption(name)) for name in image_files]
    return blocks + closing_blocks(report.warnings, report.versions, images)


def shaft_headline(designs: Sequence[ComparedDesign]) -> tuple[str, str | None]:
    """The signed figures of the design as given to the optimum in one line (the design
    as given alone without an optimum), and the trade of the optimum (None: none)."""
    by_role = {design.role: design for design in designs}
    optimum = by_role.get("optimum")
    figures, trade = figure_lines(shaft_series_figures(
        by_role["initial"].evaluation, None if optimum is None else optimum.evaluation),
        optimum is not None)
    return (figures if optimum is None else f"{figures} (initial design to optimum)"), trade


def _of_run(run: ShaftSeriesRun) -> ShaftReport:
    case = run.case
    optimising = run.optimisation is not None
    rows = [("case file", case.source), ("kind", case.kind),
            ("run", "optimisation" if optimising else "evaluation only"),
            *_problem_rows(case.model, case.option, case.input_speed_rpm,
                           case.beta_bounds_deg, case.phase_bounds_deg)]
    if run.optimisation is not None:
        rows += [("solvers", ", ".join(case.solvers)),
                 ("starts per solver", str(run.optimisation.starts)),
                 ("solver tolerance", number(case.solver_tol, "g"))]
    rows += [*_quadrature_rows(run.optimisation, run.designs),
             ("created (UTC)", run.created_utc)]
    return ShaftReport(case.name, case.description, tuple(rows), run.designs, run.optimisation,
                       run.success, run.verdict, run.warnings, run.versions,
                       _plot_heading(case.model, case.option, case.input_speed_rpm))


def _of_optimisation(result: OptimisationResult) -> ShaftReport:
    rows = [("run", "optimisation made with sso.optimise in Python"),
            *_problem_rows(result.model, result.option, result.input_speed_rpm,
                           result.beta_bounds_deg, result.phase_bounds_deg),
            ("solvers", ", ".join(result.solutions)),
            ("starts per solver", str(result.starts)),
            *_quadrature_rows(result, result.compared)]
    return ShaftReport(PYTHON_NAME, "", tuple(rows), result.compared, result, result.success,
                       result.verdict, result.warnings, None,
                       _plot_heading(result.model, result.option, result.input_speed_rpm))


def _problem_rows(model: str, option: int, speed_rpm: float, beta_bounds: Any,
                  phase_bounds: Any) -> list[tuple[str, str]]:
    return [("model", model), ("option", f"{option} ({OPTION_NAMES[option]})"),
            ("input speed (rpm)", number(speed_rpm)),
            ("operating-angle bounds (deg)", _bounds_text(beta_bounds)),
            ("phase bounds (deg)", _bounds_text(phase_bounds))]


def _quadrature_rows(optimisation: OptimisationResult | None,
                     designs: Sequence[ComparedDesign]) -> list[tuple[str, str]]:
    if optimisation is not None:
        samples, error = optimisation.samples, optimisation.quadrature_error
    else:
        samples, error = designs[0].evaluation.samples, designs[0].evaluation.quadrature_error
    return [("quadrature angles (objective)", str(samples)),
            ("quadrature error estimate", number(error, ".2g"))]


def _plot_heading(model: str, option: int, speed_rpm: float) -> str:
    return f"{model} model, option {option} ({OPTION_NAMES[option]}), input {speed_rpm:g} rpm"


def _bounds_text(bounds: Any) -> str:
    if bounds and isinstance(bounds[0], (tuple, list)):
        if all(tuple(pair) == tuple(bounds[0]) for pair in bounds):
            return f"[{number(bounds[0][0], 'g')}, {number(bounds[0][1], 'g')}] each"
        return "; ".join(f"[{number(low, 'g')}, {number(high, 'g')}]" for low, high in bounds)
    return f"[{number(bounds[0], 'g')}, {number(bounds[1], 'g')}] each"


def _design_table(designs: Sequence[ComparedDesign]) -> Table:
    joints = designs[0].series.n_joints
    rows = [(f"beta_{index + 1} (deg)", *[number(design.series.beta_deg[index])
                                          for design in designs])
            for index in range(joints)]
    rows += [(f"phi_{index + 1} (deg)", *[number(design.series.phase_deg[index])
                                          for design in designs])
             for index in range(joints - 1)]
    return Table(("angle", *[design.label for design in designs]), tuple(rows))


def _figure_table(designs: Sequence[ComparedDesign]) -> Table:
    rows = tuple((label, *[number(getattr(design.evaluation, field), spec) for design in designs])
                 for field, label, spec in FIGURES)
    return Table(("figure", *[design.label for design in designs]), rows)


def _solver_table(result: OptimisationResult) -> Table:
    solutions = [*result.solutions.items(),
                 *[(name, run) for name, run in result.confirmations.items()
                   if run != result.solutions.get(name)]]
    rows = tuple((name, solution.role, "yes" if solution.success else "no",
                  str(solution.status), solution.message, number(solution.fun, ".4g"),
                  number(solution.kkt, ".2g"), str(solution.nit), str(solution.nfev),
                  str(solution.total_nfev), number(solution.time_s, ".3f"),
                  str(solution.start_index))
                 for name, solution in solutions)
    return Table(("solver", "run", "success", "status", "message", "RE", "KKT residual (1/rad)",
                  "iterations", "evaluations", "evaluations, all starts", "time (s)", "start"),
                 rows)


def _runs_table(result: OptimisationResult) -> Table:
    rows = tuple((run.solver, run.role, str(run.start_index), "yes" if run.success else "no",
                  number(run.fun, ".4g"), number(run.kkt, ".2g"), str(run.nit),
                  number(run.time_s, ".3f"))
                 for run in result.runs)
    return Table(("solver", "run", "start", "success", "RE", "KKT residual (1/rad)",
                  "iterations", "time (s)"), rows)


def exact_optima_blocks(exact: ExactOptimumSet) -> list[Block]:
    """The set of exact optima: the criterion of the choice, its figures, the set's extent
    with each end's kind and witness."""
    unit = exact.margin_unit
    search = exact.extent_search
    text = (f"RE is at round-off zero on a set of designs of dimension {exact.dimension}; "
            f"the design reported was chosen within it by {exact.criterion}, from "
            f"{exact.starts} exact optimum(s) found. Margin to the bounds: "
            f"{number(exact.margin, '.4g')} {unit} (the first found: "
            f"{number(exact.first_margin, '.4g')} {unit}).")
    tolerances = exact.tolerances
    if exact.p95_residual_error is not None and tolerances is not None:
        text += (f" p95 RE under the tolerances ({tolerances.description}): "
                 f"{number(exact.p95_residual_error, '.4g')} "
                 f"(the first found: {number(exact.first_p95_residual_error, '.4g')}).")
    method = (f"The extent below is that of the whole set within the bounds: {EXTENT_METHOD} "
              f"({search.probes} probes per bound, {search.solves} least-squares solves). "
              f"Each end's witness is the exact optimum found with the variable at that end.")
    rows = tuple((name, unit, number(low.value, ".6g"),
                  SINGLE_VALUE if _single(low.value, high.value) else number(high.value, ".6g"),
                  number(chosen, ".6g"), f"{end_kind(low)} / {end_kind(high)}")
                 for name, unit, (low, high), chosen in zip(exact.variables, exact.units,
                                                            search.ends, exact.chosen,
                                                            strict=True))
    witnesses = tuple((name, side, number(end.value, ".6g"), end_kind(end),
                       ", ".join(number(value, ".6g") for value in end.witness),
                       number(end.witness_residual_error, ".3g"))
                      for name, (low, high) in zip(exact.variables, search.ends, strict=True)
                      for side, end in ((("from = to", low),) if _single(low.value, high.value)
                                         else (("from", low), ("to", high))))
    if all(_single(low.value, high.value) for low, high in search.ends):
        return [Paragraph(f"{text} Every variable holds a single value over the set "
                          f"({search.solves} least-squares solves found no other exact "
                          "optimum near the chosen one), so there is no extent to show.")]
    return [Paragraph(text), Paragraph(method),
            Table(("variable", "unit", "set from", "set to", "chosen", "ends"), rows),
            Table(("variable", "end", "value", "kind",
                   f"witness ({', '.join(exact.variables)})", "witness RE"), witnesses)]


SINGLE_VALUE = "a single value"
"""The "set to" cell of a variable the whole set holds at one value (from = to)."""


def _single(low: float, high: float) -> bool:
    """Whether a set's two ends read as one value in a report (six digits)."""
    return number(low, ".6g") == number(high, ".6g")


def _crosscheck_text(result: OptimisationResult) -> str:
    check = result.crosscheck
    verdict = ("one solver: no cross-check" if check is None
               else f"the solvers' own answers: {check.message}")
    minima = ", ".join(number(value, ".4g") for value in result.local_minima)
    return (f"The reported optimum was found by {result.found_by}. Cross-check of {verdict}. "
            f"Distinct RE values the successful runs stopped at: {minima or 'none'}.")


def _caption(file_name: str) -> str:
    if file_name.startswith("polar"):
        return ("Input and output speed (rpm, radius from 0 at the centre) against input shaft "
                "angle (deg), polar.")
    return "Input and output speed (rpm) against input shaft angle (deg)."
