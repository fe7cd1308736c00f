"""``sso.optimise``: one entry point that sends each kind of problem to its optimiser.

* a :class:`sso.ShaftSeries` goes to :func:`sso.shafts.optimise.optimise`
  unchanged (every argument as before);
* a :class:`ColumnGeometry` (after a :class:`sso.column.practice.PracticeWarning` for
  each way it leaves practice) goes to :func:`sso.column.phasing.optimise_phasing`
  (best yoke phasing for fixed hardpoints); with ``joint_boxes_mm=`` to
  :func:`sso.column.joint_positions.optimise_joint_positions` (joint centres free
  in boxes); with ``tolerances=`` to ``sso.column.robust.optimise_robust``;
* a mapping of names to :class:`ColumnGeometry` (one column in several positions;
  a :class:`sso.column.practice.PracticeWarning` for each way one leaves practice)
  goes to ``sso.column.robust.optimise_positions``.

It lives here, above both the shaft series and the column, because the shaft
series may not import the column (imports point down the layers).
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from importlib import import_module
from typing import Any

from sso.column.geometry import ColumnGeometry
from sso.column.practice import PracticeWarning, practice_notes
from sso.shafts.series import ShaftSeries


def optimise(problem: Any, *args: Any, **options: Any) -> Any:
    """Optimise a shaft series, a column's yoke phasing or joints, or a column in several positions.

    Parameters
    ----------
    problem : sso.ShaftSeries, sso.ColumnGeometry or mapping of str to ColumnGeometry
        What to optimise (see the module notes for where each goes).
    *args, **options
        The arguments of the optimiser it goes to. A column takes keywords only.

    Returns
    -------
    result : OptimisationResult or PhasingResult or JointPositionResult or robust result
        The result of the optimiser ``problem`` went to: ``sso.OptimisationResult``
        for a series, ``sso.PhasingResult`` or ``sso.JointPositionResult`` for a
        column, ``sso.PositionsResult`` or ``sso.RobustResult`` for the robust
        phasing.

    Raises
    ------
    TypeError
        If a column is given positional options, a keyword is unknown to the
        optimiser, or ``problem`` is none of the above.
    ValueError
        For bad input, from the optimiser it goes to.
    """
    if isinstance(problem, ShaftSeries):
        from sso.shafts.optimise import optimise as optimise_series

        # It raises its warnings at the caller's line itself: no second catch here,
        # which would cost a single solve more than the dispatch.
        return optimise_series(problem, *args, **options)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            return _dispatch(problem, args, options)
    finally:
        for warning in caught:  # re-raised here, even on error, so they name the caller's line
            warnings.warn(warning.message, warning.category, stacklevel=2)


def _dispatch(problem: Any, args: tuple[Any, ...], options: dict[str, Any]) -> Any:
    if isinstance(problem, ColumnGeometry):
        if args:
            raise TypeError("sso.optimise(geometry, ...) takes keyword options only; "
                            f"got {len(args)} positional")
        for note in practice_notes(problem):
            warnings.warn(note.text, PracticeWarning, stacklevel=2)
        if "tolerances" in options:
            return _robust("optimise_robust")(problem, **options)
        if "joint_boxes_mm" in options:
            from sso.column.joint_positions import optimise_joint_positions

            return optimise_joint_positions(problem, **options)
        from sso.column.phasing import optimise_phasing

        return optimise_phasing(problem, **options)
    if isinstance(problem, Mapping):
        if args:
            raise TypeError("sso.optimise({name: geometry, ...}, ...) takes keyword options "
                            f"only; got {len(args)} positional")
        for name, geometry in problem.items():
            if isinstance(geometry, ColumnGeometry):
                for note in practice_notes(geometry, label=f"[{name!r}].points_mm"):
                    warnings.warn(note.text, PracticeWarning, stacklevel=2)
        return _robust("optimise_positions")(problem, **options)
    from sso.shafts.optimise import optimise as optimise_series

    return optimise_series(problem, *args, **options)


def _robust(name: str) -> Any:
    """``sso.column.robust.<name>``, imported on first use."""
    return getattr(import_module("sso.column.robust"), name)
