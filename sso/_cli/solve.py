"""``sso run`` and ``sso evaluate``: solve (or evaluate) case files and write their reports."""

from __future__ import annotations

import argparse
import time
import traceback
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from sso._cli.common import (
    DEFAULT_OUT,
    EXIT_BAD_INPUT,
    EXIT_FAILED,
    EXIT_OK,
    REPORT_FOLDER_HELP,
    Command,
    add_report_arguments,
    list_argument,
    print_error,
    print_warnings,
    report_formats,
    say,
)
from sso._display import format_number
from sso._limits import SOLVERS


@dataclass
class Outcome:
    """What happened to one case, for the closing summary table."""

    case: str
    status: str
    exit_code: int
    residual_errors: tuple[str, str, str] = ("", "", "")
    seconds: float = 0.0
    folder: str = ""
    headline: tuple[str, ...] = ()
    """The figures an engineer signs and the trade, where the result has them (a column)."""


def _configure_run(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("cases", nargs="+", metavar="CASE.toml", help="case files to solve")
    parser.add_argument("--solvers", type=list_argument(SOLVERS, "solvers"),
                        metavar="LIST", help=f"solvers to run, comma-separated from "
                        f"{','.join(SOLVERS)}; lm (least squares) for a shaft series of the "
                        "exact model only (default: the case's [solver] solvers)")
    add_report_arguments(parser, REPORT_FOLDER_HELP)


def _configure_evaluate(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("cases", nargs="+", metavar="CASE.toml", help="case files to evaluate")
    add_report_arguments(parser, REPORT_FOLDER_HELP)


def _solve_cases(args: argparse.Namespace, optimising: bool) -> int:
    from sso._cases.schema import CaseError, load_case

    outcomes: list[Outcome] = []
    folders: dict[str, str] = {}
    for path in args.cases:
        started = time.perf_counter()
        try:
            case = load_case(path)
        except CaseError as error:
            print_error(str(error))
            outcomes.append(Outcome(path, "bad input", EXIT_BAD_INPUT))
            continue
        if case.name in folders:
            print_error(f"{path}: name = {case.name!r} is already used by {folders[case.name]} "
                        "in this run; its report would overwrite that one")
            outcomes.append(Outcome(path, "bad input", EXIT_BAD_INPUT))
            continue
        folders[case.name] = path
        try:
            case = case.with_overrides(solvers=getattr(args, "solvers", None),
                                       formats=report_formats(args, case.formats))
        except ValueError as error:
            print_error(f"{path}: --solvers: {error}")
            outcomes.append(Outcome(path, "bad input", EXIT_BAD_INPUT))
            continue
        folder = Path(args.out or DEFAULT_OUT) / case.name
        _import_solvers(case, optimising)
        outcomes.append(_solve_one(args, case, folder, optimising, started))
    _print_summary(outcomes, optimising)
    return max(outcome.exit_code for outcome in outcomes)


def _import_solvers(case: Any, optimising: bool) -> None:
    """Import the solvers' libraries the case's run needs here, near the top of the
    stack (:func:`sso._run.run_case.import_solvers_for`). A library that fails to import
    is left to the run, which reports it as the case's failure."""
    from sso._run.run_case import import_solvers_for

    try:
        import_solvers_for(case, optimising)
    except ImportError as error:
        interruption = _interruption_behind(error)
        if interruption is not None:
            raise interruption from None


def _interruption_behind(error: BaseException) -> KeyboardInterrupt | None:
    """The Ctrl-C or SIGTERM that caused ``error``, if one did: a signal that arrives
    while an extension module initialises becomes that module's ``ImportError:
    initialization failed`` (SciPy's HiGHS bindings), the interruption its cause."""
    seen: set[int] = set()
    current: BaseException | None = error
    while current is not None and id(current) not in seen:
        if isinstance(current, KeyboardInterrupt):
            return current
        seen.add(id(current))
        current = current.__cause__ or current.__context__
    return None


def _solve_one(args: argparse.Namespace, case: Any, folder: Path, optimising: bool,
               started: float) -> Outcome:
    """Solve one case and write its report, holding its folder from start to end: a
    second run into the same folder is refused at once, not after its solve."""
    from sso._files import check_report_folder
    from sso._folder_lock import folder_lock
    from sso._reports.kinds import CASE_REPORT

    try:
        with folder_lock(folder, f"write the report of {case.name}"):
            check_report_folder(folder, CASE_REPORT)
            return _solve_in(args, case, folder, optimising, started)
    except (OSError, ValueError) as error:
        print_error(f"{case.name}: cannot write the report into {folder}: "
                    f"{error.strerror if isinstance(error, OSError) and error.strerror else error}")
        return Outcome(case.name, "cannot write", EXIT_BAD_INPUT)


def _solve_in(args: argparse.Namespace, case: Any, folder: Path, optimising: bool,
              started: float) -> Outcome:
    """Solve (or evaluate) ``case`` and write its report into ``folder``.

    Raises
    ------
    OSError, ValueError
        If the report cannot be written into ``folder``.
    """
    from sso._files import replace_folder
    from sso._reports.kinds import CASE_REPORT, render_report
    from sso._run.run_case import run_parsed_case

    say(args, f"{case.name}: {'solving' if optimising else 'evaluating'} {case.source}")
    try:
        result = run_parsed_case(case, optimising)
    except ValueError as error:
        print_error(f"{case.source}: {error}")
        return Outcome(case.name, "bad input", EXIT_BAD_INPUT)
    except Exception as error:
        interruption = _interruption_behind(error)
        if interruption is not None:
            raise interruption from None
        print_error(f"{case.source}: internal error while solving; please report it:\n"
                    + traceback.format_exc())
        return Outcome(case.name, "internal error", EXIT_FAILED)
    told = _told(result)
    print_warnings(case.name, told.warnings)
    written = replace_folder(folder, render_report(result, case.formats), CASE_REPORT)
    status, code = _status(told)
    if not told.success:
        print_error(f"{case.name}: {told.verdict}")
    if told.shortfall is not None:
        print_error(f"{case.name}: {told.shortfall}")
    say(args, f"{case.name}: {status}; wrote {', '.join(path.name for path in written)} "
         f"in {folder}")
    initial, optimum, reference = (format_number(value, 3) if value is not None else "-"
                                   for value in told.residual_errors)
    if told.objective_note is not None:
        # the recommended teeth were searched for the case's own objective: say it
        optimum += f" ({told.objective_note})"
    return Outcome(case.name, status, code, (initial, optimum, reference),
                   time.perf_counter() - started, str(folder), told.headline)


@dataclass(frozen=True)
class _Told:
    """What the command tells of one case's result."""

    mode: str
    success: bool
    verdict: str
    warnings: tuple[str, ...]
    residual_errors: tuple[float | None, ...]
    """RE of the initial design, the optimum and the reference (None: not in the result)."""
    objective_note: str | None = None
    """The objective the recommended teeth were searched for, at the teeth and continuous
    (a column with positions, tolerances or a steering feel), else None."""
    shortfall: str | None = None
    """Why the recommended column's built columns are not shown to reach the required
    yield (``[limits] yield``), else None."""
    headline: tuple[str, ...] = ()
    """The figures an engineer signs (as built to recommended) and the trade (a column)."""


def _told(result: Any) -> _Told:
    """What to tell of a case run's result."""
    # Each kind's run module is imported only when the result is not of an earlier
    # kind: the run of a shaft series loads neither the column's nor the linkages'.
    from sso._run.shaft_series import ShaftSeriesRun

    if isinstance(result, ShaftSeriesRun):
        from sso._reports.shaft_report import shaft_headline

        designs = (result.design(role) for role in ("initial", "optimum", "reference"))
        errors = tuple(None if design is None else design.evaluation.residual_error
                       for design in designs)
        figures, trade = shaft_headline(result.designs)
        return _Told(result.mode, result.success, result.verdict, result.warnings, errors,
                     headline=(figures, *([trade] if trade is not None else [])))
    from sso._run.mechanism_run import MechanismRun

    if isinstance(result, MechanismRun):
        return _Told(result.mode, result.success, result.verdict, result.warnings,
                     (None, None, None))
    from sso._run.driveline import DrivelineRun

    if isinstance(result, DrivelineRun):
        return _Told("analyse", result.success, result.verdict, result.warnings,
                     (None, None, None))
    from sso._run.column import ColumnRun

    if not isinstance(result, ColumnRun):
        raise TypeError(f"no case run gives a {type(result).__name__}")
    optimum = result.optimum
    note = None if optimum is None or optimum.objective is None else (
        f"{optimum.objective} {format_number(optimum.objective_at_teeth, 3)} at the teeth, "
        f"{format_number(optimum.objective_continuous, 3)} continuous")
    yields = result.judged_yields
    shortfall = None if yields is None or yields.signed_off else (
        f"{result.judged_columns} ([tolerances] sample): {yields.sentence}")
    figures, trade = result.headline
    return _Told(result.mode, result.success, result.verdict, result.warnings,
                 (result.initial.residual_error,
                  None if optimum is None else optimum.residual_error, None), note, shortfall,
                 (f"{figures} (as built to recommended)" if optimum is not None else figures,
                  *([trade] if trade is not None else [])))


def _status(told: _Told) -> tuple[str, int]:
    from sso._shafts.optimise import UNRELIABLE_VERDICT

    if told.success and told.shortfall is not None:
        return "below the required yield", EXIT_FAILED
    if told.mode == "evaluate":
        return "evaluated", EXIT_OK
    if told.mode == "analyse":
        return "analysed", EXIT_OK
    if told.success:
        return "solved", EXIT_OK
    if told.verdict.startswith("solver failed"):
        return "solver failed", EXIT_FAILED
    if told.verdict.startswith(UNRELIABLE_VERDICT):
        return UNRELIABLE_VERDICT, EXIT_FAILED
    return "solvers disagree", EXIT_FAILED


def _print_summary(outcomes: list[Outcome], optimising: bool) -> None:
    header = ("case", "status", "RE initial", "RE optimum" if optimising else "-",
              "RE reference", "time (s)", "report")
    rows: list[tuple[str, ...]] = [header]
    rows += [(outcome.case, outcome.status, *outcome.residual_errors,
              f"{outcome.seconds:.2f}" if outcome.folder else "", outcome.folder)
             for outcome in outcomes]
    if not optimising:
        rows = [row[:3] + row[4:] for row in rows]
    widths = [max(len(row[column]) for row in rows) for column in range(len(rows[0]))]
    lines = ["  ".join(cell.ljust(width) for cell, width in zip(row, widths, strict=True)).rstrip()
             for row in rows]
    lines.insert(1, "  ".join("-" * width for width in widths))
    headlines = [f"{outcome.case}: {line}" for outcome in outcomes for line in outcome.headline]
    print("\n" + "\n".join([*headlines, *([""] if headlines else []), *lines]), flush=True)


def _run(args: argparse.Namespace) -> int:
    return _solve_cases(args, optimising=True)


def _evaluate(args: argparse.Namespace) -> int:
    return _solve_cases(args, optimising=False)


COMMANDS = (
    Command("run", "solve case files and write their reports",
            "Solve each case (IPOPT and SLSQP, several starts, cross-checked) and write its "
            "report into DIR/<case name>/. One failing case does not stop the others; a "
            "summary table closes the run. Exit 0: all solved and the solvers agree; 1: a "
            "solver failed or the solvers disagreed; 2: bad input.",
            _configure_run, _run),
    Command("evaluate", "evaluate the designs as given, without optimising",
            "Evaluate each case's design as given (and its reference design), with no "
            "optimisation and no NLP, and write the same report without the optimum. Exit "
            "0: evaluated; 1: a column's built columns as built do not meet its "
            "[limits] yield; 2: bad input.",
            _configure_evaluate, _evaluate),
)
