"""Compare solvers by objective value and first-order optimality, never by design."""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from sso._display import format_number
from sso._limits import DEFAULT_KKT_TOLERANCE, DEFAULT_OBJECTIVE_ATOL, DEFAULT_OBJECTIVE_RTOL
from sso._solvers.solution import CrossCheck, Solution

DEFAULT_DESIGN_TOLERANCE = 1e-5
"""Largest difference of a design variable (solver units: rad for a shaft series) between
two answers at one isolated minimum that counts as the same design; both solvers meet
their stopping tests far closer than this on a strict minimum."""


def allowed_objective_gap(objectives: Iterable[float],
                          objective_rtol: float = DEFAULT_OBJECTIVE_RTOL,
                          objective_atol: float = DEFAULT_OBJECTIVE_ATOL) -> float:
    """The largest spread of ``objectives`` that still counts as one value (round-off).

    ``objective_atol + objective_rtol * max|objective|``: relative to the figures'
    size, so an RE of 26,919 agrees with another 1e-7 away as an RE of 1e-3 agrees
    with one 1e-15 away. The cross-check of two solvers and the column's test of its
    closed-form least RE both use it.
    """
    return objective_atol + objective_rtol * max(abs(value) for value in objectives)


def crosscheck(
    solutions: Mapping[str, Solution],
    objective_rtol: float = DEFAULT_OBJECTIVE_RTOL,
    objective_atol: float = DEFAULT_OBJECTIVE_ATOL,
    kkt_tolerance: float = DEFAULT_KKT_TOLERANCE,
    design_gap: float | None = None,
    design_tolerance: float = DEFAULT_DESIGN_TOLERANCE,
) -> CrossCheck:
    """Verdict on two or more solvers' best answers to the same problem.

    Parameters
    ----------
    solutions : mapping of str to Solution
        Best answer of each solver.
    objective_rtol, objective_atol : float
        Objectives agree when they differ by at most
        ``objective_atol + objective_rtol * max|fun|`` (dimensionless RE).
    kkt_tolerance : float
        Largest stationarity error (per rad for a shaft series) that counts as
        first-order optimal, and largest constraint violation that counts as feasible.
    design_gap : float, optional
        Largest difference of a design variable between the answers, when each is an
        isolated minimum reached from the same start (None: designs not compared).
        The message says whether they found one minimum or two of equal objective
        (two local methods may go to different equal minima, as to mirror-image
        phasings; that is not a disagreement).
    design_tolerance : float
        Largest ``design_gap`` that counts as one design.

    Returns
    -------
    CrossCheck
        A disagreement is reported in the verdict, never raised.
    """
    objective = {name: solution.fun for name, solution in solutions.items()}
    kkt = {name: solution.kkt for name, solution in solutions.items()}
    gap = max(objective.values()) - min(objective.values())
    allowed_gap = allowed_objective_gap(objective.values(), objective_rtol, objective_atol)
    failed = [name for name, solution in solutions.items() if not solution.success]
    not_stationary = [name for name, value in kkt.items() if value > kkt_tolerance]
    infeasible = [name for name, solution in solutions.items()
                  if solution.constraint_violation > kkt_tolerance]
    objectives_agree = gap <= allowed_gap
    better = None if objectives_agree else min(objective, key=objective.__getitem__)

    problems = []
    if failed:
        problems.append(", ".join(f"{name} failed ({solutions[name].message})" for name in failed))
    if not objectives_agree:
        problems.append(
            "objectives differ by "
            f"{format_number(gap, 3)} (allowed {format_number(allowed_gap, 3)}): "
            + ", ".join(f"{name} RE = {format_number(value)}" for name, value in objective.items())
            + f"; {better} is better"
        )
    if not_stationary:
        problems.append(
            ", ".join(f"{name} projected gradient {format_number(kkt[name], 3)}"
                      for name in not_stationary)
            + f" exceeds {kkt_tolerance:g}"
        )
    if infeasible:
        problems.append(", ".join(f"{name} violates a constraint by "
                                  f"{solutions[name].constraint_violation:.3g}"
                                  for name in infeasible))
    if problems:
        message = "solvers disagree: " + "; ".join(problems)
    else:
        message = (f"solvers agree: objectives within {format_number(gap, 3)}, stationarity "
                   "errors " + ", ".join(f"{name} {format_number(value, 2)}"
                                         for name, value in kkt.items())
                   + ("" if design_gap is None else
                      f"; designs within {design_gap:.2g} (one isolated minimum)"
                      if design_gap <= design_tolerance else
                      f"; designs differ by {design_gap:.3g}: two isolated minima of equal "
                      "objective, each stationary"))
    return CrossCheck(
        agree=not problems,
        objective_gap=float(gap),
        objective=objective,
        kkt=kkt,
        better=better,
        message=message,
        objective_atol=objective_atol,
        objective_rtol=objective_rtol,
        kkt_tolerance=kkt_tolerance,
        design_gap=design_gap,
        design_tolerance=design_tolerance,
    )
