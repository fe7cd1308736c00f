"""A case file, read and solved (or evaluated) into its result: what ``sso run`` and
``sso evaluate`` do before they write the report, and :func:`sso.run_case` in Python."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from sso._cases.schema import KIND_MODULES, load_case
from sso._cases.shaft_series import KIND as SHAFT_SERIES_KIND
from sso._run.shaft_series import run_shaft_series

if TYPE_CHECKING:  # each run imports only the module its case's kind needs
    from sso._run.column import ColumnRun
    from sso._run.driveline import DrivelineRun
    from sso._run.mechanism_run import MechanismRun
    from sso._run.shaft_series import ShaftSeriesRun


def run_case(path: str | Path, *, solve: bool = True
             ) -> ShaftSeriesRun | MechanismRun | ColumnRun | DrivelineRun:
    """Read a case file and solve it, as ``sso run`` does (or evaluate it, as
    ``sso evaluate`` does), without writing anything.

    Parameters
    ----------
    path : str or pathlib.Path
        The case file (TOML, the schema of ``sso validate``).
    solve : bool, optional
        True (default): optimise the case's design as ``sso run`` does. False: evaluate
        the design as given, as ``sso evaluate`` does.

    Returns
    -------
    ShaftSeriesRun or MechanismRun or ColumnRun or DrivelineRun
        The result of the case's kind; :func:`sso.write_report` writes its report, the
        same files ``sso run`` writes. Solver failures are recorded in it, not raised.

    Raises
    ------
    ValueError
        If the file cannot be read or breaks the schema (the message names the file, the
        line where known, the key and the allowed range), or the design it describes is
        refused (the field and its allowed range).
    """
    return run_parsed_case(load_case(path), solve)


def run_parsed_case(case: Any, solve: bool
                    ) -> ShaftSeriesRun | MechanismRun | ColumnRun | DrivelineRun:
    """The result of a case already read and checked (see :func:`run_case`)."""
    if case.kind == SHAFT_SERIES_KIND:
        return run_shaft_series(case, solve)
    from sso._cases.column import COLUMN_KIND

    if case.kind == COLUMN_KIND:
        from sso._run.column import run_column

        return run_column(case, solve)
    from sso._cases.schema import KIND_MODULES

    if KIND_MODULES.get(case.kind) == "sso._cases.driveline":  # no import for other kinds
        from sso._run.driveline import run_driveline

        return run_driveline(case, solve)
    from sso._cases.mechanism import MECHANISM_KINDS

    if case.kind not in MECHANISM_KINDS:
        raise TypeError(f"no case run solves a case of kind {case.kind!r}")
    from sso._run.mechanism_run import run_mechanism

    return run_mechanism(case, solve)


def import_solvers_for(case: Any, solve: bool) -> None:
    """Import SciPy's optimiser now if running ``case`` will: solving any case but a
    mechanism's analysis (which runs no solver). ``sso run`` calls this near the top of
    its stack, before the run.

    Imported deep inside the solve instead, SciPy's import (its docstring parsing, whose
    call depth goes up and down across the end of one of CPython 3.11's 16 KiB chunks of
    frame stack) made the interpreter free that chunk and map it again about 15,000
    times: 14,000 page faults, about a tenth of the CPU time of ``sso run --no-plots``
    on the paper's case (CPython issue gh-142183; 3.13 and 3.14 keep the chunk).

    Raises
    ------
    ImportError
        If SciPy cannot be imported (or a signal arrived while one of its extension
        modules initialised: the interruption is the error's cause).
    """
    if not solve:
        return
    if KIND_MODULES.get(case.kind) == "sso._cases.mechanism":
        from sso._cases.mechanism import DESIGN_KIND  # loaded with the case

        if case.kind != DESIGN_KIND:
            return
    import scipy.optimize  # noqa: F401

