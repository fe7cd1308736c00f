"""``sso sweep`` and ``sso tolerance``: arguments and handlers for :mod:`sso._cli`.

Only argparse is imported here at module level, so building the ``sso`` parser
stays light; the handlers import the batch API and, with ``--scheduler``,
dask.distributed. Exit codes and the default output folder are those of
:mod:`sso._cli`.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from dataclasses import replace
from pathlib import Path
from typing import Any

from sso._cli.common import DEFAULT_OUT, EXIT_BAD_INPUT, EXIT_FAILED, EXIT_OK, Command
from sso._display import format_number
from sso._limits import OUTPUT_FORMATS


def configure_sweep(parser: argparse.ArgumentParser) -> None:
    """Arguments of ``sso sweep``."""
    parser.add_argument("sweep", metavar="SWEEP.toml",
                        help="sweep file: a base case, the [axes] to vary, the action")
    parser.add_argument("--resume", action="store_true",
                        help="complete the sweep already in DIR/<name>/: compute only its "
                        "missing points")
    parser.add_argument("--parquet", action="store_true",
                        help="also write the rows as Parquet (sweep.parquet/, a part per "
                        "chunk; needs the 'parquet' extra)")
    _add_execution_arguments(parser, "write sweep.csv, sweep.json, report.md and the plot "
                             f"into DIR/<sweep name>/ (default: {DEFAULT_OUT})")


def configure_tolerance(parser: argparse.ArgumentParser) -> None:
    """Arguments of ``sso tolerance``."""
    parser.add_argument("case", metavar="CASE.toml",
                        help="case file: its optimum is perturbed as its [tolerance] table says")
    parser.add_argument("--at", choices=("optimum", "start"), default="optimum",
                        help="study the case's optimum (default: optimise first, or read it "
                        "with --result) or its design as given (start)")
    parser.add_argument("--result", metavar="RESULT.json",
                        help="take the optimum from this result.json (written by sso run) "
                        "instead of optimising")
    parser.add_argument("--samples", type=int, metavar="N",
                        help="number of samples (default: the case's, or 10000)")
    parser.add_argument("--seed", type=int, metavar="N",
                        help="seed of the draw (default: the case's, or 0)")
    _add_execution_arguments(parser, "write tolerance.csv/.json, report.md/.html and the "
                             f"histogram into DIR/<case name>/ (default: {DEFAULT_OUT})")


def run_sweep(args: argparse.Namespace) -> int:
    """Run ``sso sweep``; exit 0 if every point finished (and converged), 1 if not, 2 bad input."""
    from sso._studies.sweep import sweep
    from sso._studies.sweep_file import load_sweep

    def work(client: Any) -> int:
        spec = load_sweep(args.sweep)
        result = sweep(spec.base, spec.axes, mode=spec.mode, action=spec.action,
                       out_dir=Path(args.out or DEFAULT_OUT) / spec.name, resume=args.resume,
                       client=client, workers=args.workers, chunk_size=spec.chunk_size,
                       progress=False if args.quiet else None, plots=not args.no_plots,
                       memory_limit_mb=args.memory_limit, parquet=args.parquet)
        print(result.summary(), flush=True)
        return EXIT_OK if result.success else EXIT_FAILED

    return _with_client(args, args.sweep, work)


def run_tolerance(args: argparse.Namespace) -> int:
    """Run ``sso tolerance``; exit 0 on success, 2 for bad input.

    The optimum is studied unless ``--at start``: the case is optimised first,
    or its optimum read from ``--result``; the report says which.
    """
    from sso._reports.kinds import write_report
    from sso._studies.axes import base_case
    from sso._studies.tolerance_study import tolerance_study

    def work(client: Any) -> int:
        case = base_case(args.case)
        if args.at == "start" and args.result is not None:
            raise ValueError("--at start studies the case's design as given; --result gives an "
                             "optimum: use one of them")
        if case.kind == "column":
            from sso._cli.column_tolerance import run_column_tolerance

            return run_column_tolerance(args, case, client)
        design, study_of = _studied_design(args, case)
        settings = dict(case.tolerance_study or {})
        settings.update({name: value for name, value in (("samples", args.samples),
                                                         ("seed", args.seed))
                         if value is not None})
        result = tolerance_study(design, **settings, input_speed_rpm=case.input_speed_rpm,
                                 client=client, workers=args.workers,
                                 progress=False if args.quiet else None,
                                 memory_limit_mb=args.memory_limit)
        result = replace(result, study_of=study_of)
        formats = tuple(name for name in OUTPUT_FORMATS if not (args.no_plots and name == "png"))
        folder = Path(args.out or DEFAULT_OUT) / case.name
        result = replace(result, files=tuple(write_report(result, folder, formats)))
        print(result.summary(), flush=True)
        return EXIT_OK

    return _with_client(args, args.case, work)


def _studied_design(args: argparse.Namespace, case: Any) -> tuple[Any, str]:
    """The design ``sso tolerance`` studies, and the words that say which it is."""
    if args.at == "start":
        return case, f"the design as given (start) in {Path(args.case).name}"
    if args.result is not None:
        from sso._cli.saved_results import read_saved_result
        from sso._run.shaft_series import ShaftSeriesRun
        from sso._shafts.optimise import OptimisationResult

        saved = read_saved_result(args.result)
        optimisation = saved.optimisation if isinstance(saved, ShaftSeriesRun) else saved
        if not isinstance(optimisation, OptimisationResult):
            raise ValueError(f"{args.result} holds no optimum (was it written by sso evaluate?); "
                             "give a result of sso run, or --at start")
        optimum = optimisation.compared[1]
        return optimum.series, f"the {optimum.label} read from {args.result}"
    from sso._shafts.optimise import optimise

    if not args.quiet:
        print(f"{case.name}: optimising first, to study the optimum", flush=True)
    result = optimise(case.series(), case.option, **case.optimise_options())
    if not result.success:
        print(f"warning: {case.name}: the optimisation did not succeed "
              f"({'solvers disagree' if result.best.success else 'solver failed'}); "
              "studying its best design", file=sys.stderr, flush=True)
    return result, (f"the optimum ({result.best.solver}, RE {format_number(result.fun, 3)}) of "
                    f"{Path(args.case).name}, optimised first")


def _add_execution_arguments(parser: argparse.ArgumentParser, out_help: str) -> None:
    parser.add_argument("--out", metavar="DIR", help=out_help)
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="run on the Dask cluster whose scheduler is at ADDRESS "
                        "(e.g. tcp://10.0.0.5:8786) instead of local processes")
    parser.add_argument("--workers", type=int, metavar="N",
                        help="local processes (default: every core; 1 runs in this process)")
    parser.add_argument("--no-plots", action="store_true",
                        help="write no plots (matplotlib is not even imported)")
    parser.add_argument("--quiet", action="store_true",
                        help="no progress bar; print only errors and the closing summary")
    parser.add_argument("--memory-limit", type=float, metavar="MB",
                        help="refuse the work if its memory estimate exceeds MB (default: "
                        "environment SSO_MEMORY_LIMIT_MB, else 4096)")


def _with_client(args: argparse.Namespace, source: str, work: Callable[[Any], int]) -> int:
    """Connect to ``--scheduler`` if given, run ``work``, report bad input as exit 2."""
    from sso._studies.execution import NoWorkersError, connect

    client = None
    try:
        if args.scheduler:
            client = connect(args.scheduler)
        return work(client)
    except NoWorkersError as error:  # the work done so far is kept: --resume completes it
        print(f"error: {source}: {error}", file=sys.stderr, flush=True)
        return EXIT_FAILED
    except (ValueError, OSError) as error:
        print(f"error: {source}: {error}", file=sys.stderr, flush=True)
        return EXIT_BAD_INPUT
    finally:
        if client is not None:
            client.close()


COMMANDS = (
    Command("sweep", "optimise or evaluate a base case over a grid of key values",
            "Run a sweep file: a base case, the [axes] to vary (any case key, e.g. "
            "design.beta_deg[1], option, model, input_speed_rpm) and the action. Writes "
            "sweep.csv as chunks finish, report.md and a plot into DIR/<name>/; --resume "
            "computes only the missing points. Exit 0: every point finished (and converged); "
            "1: some did not; 2: bad input.",
            configure_sweep, run_sweep),
    Command("tolerance", "Monte Carlo tolerance study of a case's optimum",
            "Optimise the case (or read its optimum from --result RESULT.json), perturb the "
            "optimum's angles and phases as the case's [tolerance] table says (normal or "
            "uniform, deg), evaluate every sample, and write percentiles of RE, fluctuation "
            "and output acceleration with a histogram into DIR/<case name>/. --at start "
            "studies the case's design as given instead. A column case: its hardpoints (mm) "
            "and yoke phasings (deg) as its [tolerances] table says (default 0.5 mm, 1 deg), "
            "with RE and the steering figures from lock to lock.",
            configure_tolerance, run_tolerance),
)
