"""A case file, read and solved (or evaluated) into its result: what ``sso run`` and
``sso evaluate`` do before they write the report, and :func:`sso.run_case` in Python."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # each run imports only the module its case's kind needs
    from sso._run.column import ColumnRun
    from sso._run.mechanism_run import MechanismRun
    from sso._run.shaft_series import ShaftSeriesRun


def run_case(path: str | Path, *, solve: bool = True
             ) -> ShaftSeriesRun | MechanismRun | ColumnRun:
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
    ShaftSeriesRun or MechanismRun or ColumnRun
        The result of the case's kind; :func:`sso.write_report` writes its report, the
        same files ``sso run`` writes. Solver failures are recorded in it, not raised.

    Raises
    ------
    ValueError
        If the file cannot be read or breaks the schema (the message names the file, the
        line where known, the key and the allowed range), or the design it describes is
        refused (the field and its allowed range).
    """
    from sso._cases.schema import load_case

    return run_parsed_case(load_case(path), solve)


def run_parsed_case(case: Any, solve: bool) -> ShaftSeriesRun | MechanismRun | ColumnRun:
    """The result of a case already read and checked (see :func:`run_case`)."""
    from sso._cases.shaft_series import KIND as SHAFT_SERIES_KIND

    if case.kind == SHAFT_SERIES_KIND:
        from sso._run.shaft_series import run_shaft_series

        return run_shaft_series(case, solve)
    from sso._cases.column import COLUMN_KIND

    if case.kind == COLUMN_KIND:
        from sso._run.column import run_column

        return run_column(case, solve)
    from sso._cases.mechanism import MECHANISM_KINDS

    if case.kind not in MECHANISM_KINDS:
        raise TypeError(f"no case run solves a case of kind {case.kind!r}")
    from sso._run.mechanism_run import run_mechanism

    return run_mechanism(case, solve)
