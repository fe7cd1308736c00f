"""``sso tolerance`` of a column case: the design studied, the study and its report.

The optimum is studied unless ``--at start``: the best assembly on the case's splines
(``[splines]``), else the best continuous yoke phasing, found first; or the
recommended assembly read from ``--result`` (a ``result.json`` of ``sso run``). The
tolerances are the case's ``[tolerances]`` (hardpoint mm, yoke phasing deg), else
sso's defaults (:data:`sso._limits.DEFAULT_HARDPOINT_TOLERANCE_MM`,
:data:`sso._limits.DEFAULT_YOKE_PHASE_TOLERANCE_DEG`); the steering range is the
case's ``[steering]``. The built columns are judged against the case's ``[limits]``:
the command exits 1 unless the yield of all of them together is shown to reach
``[limits] yield`` (its 95 % confidence interval's lower bound at or above it;
:mod:`sso._column.yields`).
"""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path
from typing import Any

from sso._cli.common import DEFAULT_OUT, EXIT_FAILED, EXIT_OK
from sso._cli.saved_results import read_saved_result
from sso._column.phasing import optimise_phasing
from sso._column.splines import best_spline_teeth
from sso._limits import OUTPUT_FORMATS
from sso._reports.kinds import write_report
from sso._run.column import ColumnRun
from sso._studies.column_tolerance import column_tolerance_study, study_settings


def run_column_tolerance(args: argparse.Namespace, case: Any, client: Any) -> int:
    """Study the column case's design; write the report; 0 when the required yield is
    shown (or none is required), else 1 (bad input raises ValueError)."""
    design, study_of = _studied_design(args, case)
    tolerances, count = study_settings(None, case, args.samples, args.seed, None)
    result = column_tolerance_study(
        design, tolerances, samples=count, lock_deg=case.values["steering.lock_deg"],
        straight_ahead_deg=case.values["steering.straight_ahead_deg"], study_of=study_of,
        client=client, workers=args.workers, progress=False if args.quiet else None,
        memory_limit_mb=args.memory_limit, limits=case.steering_limits(),
        required_yield=case.required_yield)
    formats = tuple(name for name in OUTPUT_FORMATS if not (args.no_plots and name == "png"))
    folder = Path(args.out or DEFAULT_OUT) / case.name
    result = replace(result, files=tuple(write_report(result, folder, formats)))
    print(result.summary(), flush=True)
    return EXIT_OK if result.yields is None or result.yields.signed_off else EXIT_FAILED


def _studied_design(args: argparse.Namespace, case: Any) -> tuple[tuple[Any, Any], str]:
    """``(geometry, yoke_phase_deg)`` studied, and the words that say which it is."""
    geometry = case.geometry()
    name = Path(args.case).name
    if args.at == "start":
        return ((geometry, case.values["phasing.yoke_phase_deg"]),
                f"the assembly as built (phasing.yoke_phase_deg) in {name}")
    if args.result is not None:
        return _recommended(args.result)
    if not args.quiet:
        print(f"{case.name}: optimising first, to study the optimum", flush=True)
    if case.teeth is not None:
        splines = best_spline_teeth(geometry, case.teeth)
        return ((geometry, splines.yoke_phase_deg),
                f"the best assembly on the splines (teeth {list(case.teeth)}, tooth offsets "
                f"{list(splines.tooth_offset)}) of {name}, found first")
    phasing = optimise_phasing(geometry, **case.solver_options())
    return ((geometry, phasing.yoke_phase_deg),
            f"the best yoke phasing of {name}, optimised first")


def _recommended(path: str) -> tuple[tuple[Any, Any], str]:
    """The recommended assembly of a column run's saved result.

    Raises
    ------
    ValueError
        If ``path`` holds no saved column run (a RecordError names the field).
    """
    run = read_saved_result(path)
    if not isinstance(run, ColumnRun):
        raise ValueError(f"{path} is no column case's result (type = {type(run).__name__}); "
                         "give the result.json of sso run of this column case, or --at start")
    chosen = run.assembly(run.recommended)
    return ((run.geometry, chosen.yoke_phase_deg),
            f"the recommended assembly ({chosen.label}) read from {path}")
