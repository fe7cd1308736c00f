"""What a worker process runs: one chunk of sweep points, one row per point.

The functions here are top-level and take plain data, so a spawned process or a
Dask worker can import and run them. Each process builds the CasADi NLP of a
shape once (the per-thread cache of :mod:`sso.solvers.nlp`) and reuses it for
every point of that shape it is given.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import partial
from typing import Any

from sso.batch.axes import point_document
from sso.batch.batched import BatchedPoints, batchable
from sso.batch.point_row import PointRow, design_columns, solver_columns

ACTIONS = ("optimise", "evaluate")


@dataclass(frozen=True)
class SweepChunk:
    """A unit of work: some points of one sweep.

    Attributes
    ----------
    document : dict
        The base case as a complete case-file document.
    action : {"optimise", "evaluate"}
        What to do at each point.
    points : tuple of (int, dict)
        Point index and the point's axis values.
    """

    document: dict[str, Any]
    action: str
    points: tuple[tuple[int, dict[str, Any]], ...]


def run_sweep_chunk(chunk: SweepChunk) -> list[dict[str, Any]]:
    """Rows of the chunk's points, in order; a point that fails gives an error row.

    Optimising, the points whose case the least-squares solver solves alone
    (:func:`sso.batch.batched.batchable`) are solved together, one
    :func:`sso.optimise_batch` call per shape (:mod:`sso.batch.batched`); every other
    point is solved by :func:`sso.optimise` on its own.
    """
    batched = BatchedPoints(_optimise_row)
    rows = []
    for index, point in chunk.points:
        row = PointRow({"point": index, **point})
        case = _parsed_case(row, index, chunk.document, point)
        if case is not None and chunk.action == "optimise" and batchable(case):
            batched.add(row, case)
        elif case is not None:
            row.fill(partial(_solve_row, case, chunk.action))
        rows.append(row)
    batched.solve()
    return [row.finish() for row in rows]


def run_point(index: int, document: dict[str, Any], point: dict[str, Any],
              action: str) -> dict[str, Any]:
    """The result row of one point: inputs, best RE, solver statuses, times.

    The point's case is checked like a case file (the same messages, naming the
    key and the allowed range). Never raises for a bad point: the error is
    recorded in the row's ``error`` column and its ``status`` is ``"failed"``.
    """
    row = PointRow({"point": index, **point})
    case = _parsed_case(row, index, document, point)
    if case is not None:
        row.fill(lambda: _solve_row(case, action))
    return row.finish()


def _parsed_case(row: PointRow, index: int, document: dict[str, Any],
                 point: dict[str, Any]) -> Any:
    """The point's case, checked like a case file, or None (an error row) if it is bad."""
    from sso.cases.schema import parse_case

    case = row.attempt(lambda: parse_case(point_document(document, point), f"point {index}"))
    if case is not None:
        row.notes[:0] = case.warnings
    return case


def _solve_row(case: Any, action: str) -> dict[str, Any]:
    return _optimise_row(case) if action == "optimise" else _evaluate_row(case)


def failed_rows(chunk: SweepChunk, error: BaseException) -> list[dict[str, Any]]:
    """Rows for every point of a chunk whose task itself failed (a lost worker).

    Their status is ``"lost"``: a resumed sweep computes them again.
    """
    message = f"{type(error).__name__}: {error}"
    return [{"point": index, **point, "status": "lost", "error": message}
            for index, point in chunk.points]


def _evaluate_row(case: Any) -> dict[str, Any]:
    series = case.series()
    evaluation = series.evaluate(case.input_speed_rpm, quadrature_rtol=case.quadrature_rtol,
                                 quadrature_atol=case.quadrature_atol)
    return design_columns(evaluation, series.beta_deg, series.phase_deg)


def _optimise_row(case: Any) -> dict[str, Any]:
    from sso.shafts.optimise import optimise

    result = optimise(case.series(), case.option, **case.optimise_options())
    row = {
        **design_columns(result.optimum, result.best_series.beta_deg,
                         result.best_series.phase_deg),
        "success": result.success,
        "best_solver": result.best.solver,
    }
    if result.crosscheck is not None:
        row["crosscheck_agree"] = result.crosscheck.agree
        row["crosscheck_objective_gap"] = result.crosscheck.objective_gap
    for name, solution in result.solutions.items():
        row.update(solver_columns(
            name, solution.fun, solution.status, solution.success, solution.message,
            solution.kkt, sum(run.time_s for run in result.runs if run.solver == name)))
    return row
