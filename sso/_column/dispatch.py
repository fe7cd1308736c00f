"""``sso.optimise``: the one optimiser entry point; it sends each problem to its optimiser.

* a :class:`sso.ShaftSeries` goes to :func:`sso._shafts.optimise.optimise`
  unchanged (every argument as before);
* a :class:`sso.FourBar` goes to :func:`sso._linkages.fourbar_swing.design_fourbar`
  (the crank-rocker with the largest rocker swing);
* a :class:`ColumnGeometry` (after a :class:`sso._column.practice.PracticeWarning` for
  each way it leaves practice) goes to :func:`sso._column.phasing.optimise_phasing`
  (best yoke phasing for fixed hardpoints), or, with one of these keywords, to:

  - ``joint_boxes_mm=``: :func:`sso._column.joint_centres.optimise_joint_centres`
    (joint centres free in boxes);
  - ``tolerances=``: :func:`sso._column.robust_phasing.optimise_robust`;
  - ``lock_deg=``: :func:`sso._column.feel.optimise_on_centre` (steering feel);
  - ``teeth=``: :func:`sso._column.splines.best_spline_teeth` (the best phasing on
    the splines, exact over whole teeth);

* a mapping of names to :class:`ColumnGeometry` (one column in several tilt or
  telescope positions; a :class:`sso._column.practice.PracticeWarning` for each way
  one leaves practice) goes to :func:`sso._column.positions.optimise_positions`.

It lives here, above the shaft series, the linkages and the column, because none of
them may import the others' optimisers (imports point down the layers).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Mapping
from typing import Any

from sso._shafts.optimise import optimise as optimise_series
from sso._shafts.series import ShaftSeries

COLUMN_OPTIMISER_KEYWORDS = ("joint_boxes_mm", "tolerances", "lock_deg", "teeth")
"""Keywords that each select a column optimiser (:func:`_column_optimiser`)."""


def optimise(problem: Any, *args: Any, **options: Any) -> Any:
    """Optimise a shaft series, a four-bar, a column, or a column in several positions.

    Parameters
    ----------
    problem : sso.ShaftSeries, sso.FourBar, sso.ColumnGeometry or mapping of str to ColumnGeometry
        What to optimise (see the module notes for where each goes).
    *args, **options
        The arguments of the optimiser it goes to. A four-bar and a column take
        keywords only; a column's optimiser is chosen by at most one of
        ``joint_boxes_mm=``, ``tolerances=``, ``lock_deg=`` and ``teeth=``.

    Returns
    -------
    result : OptimisationResult or FourBarDesignResult or a column's result
        The result of the optimiser ``problem`` went to: ``sso.OptimisationResult``
        for a series, ``sso.FourBarDesignResult`` for a four-bar,
        ``sso.PhasingResult``, ``sso.JointCentresResult``, ``sso.RobustResult``,
        ``sso.OnCentreResult`` or ``sso.SplineResult`` for a column (by keyword), and
        ``sso.PositionsResult`` for a column in several positions.

    Raises
    ------
    TypeError
        If a four-bar or a column is given positional options, a column two
        selecting keywords, a keyword is unknown to the optimiser, or ``problem``
        is none of the above.
    ValueError
        For bad input, from the optimiser it goes to.
    """
    if isinstance(problem, ShaftSeries):
        # It raises its warnings at the caller's line itself: no second catch here,
        # which would cost a single solve more than the dispatch.
        return optimise_series(problem, *args, **options)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            return _optimiser_of(problem, args, options)(problem, **options)
    finally:
        for warning in caught:  # re-raised here, even on error, so they name the caller's line
            warnings.warn(warning.message, warning.category, stacklevel=2)


def _optimiser_of(problem: Any, args: tuple[Any, ...],
                  options: Mapping[str, Any]) -> Callable[..., Any]:
    # Imported here, not at the top: a shaft series' solve never needs them, and they
    # cost about 22 ms of a fresh process's 0.15 s (python -X importtime).
    from sso._column.geometry import ColumnGeometry
    from sso._column.practice import PracticeWarning, practice_notes
    from sso._linkages.mechanisms import FourBar

    if isinstance(problem, FourBar):
        _keywords_only("sso.optimise(fourbar, ...)", args)
        from sso._linkages.fourbar_swing import design_fourbar
        return design_fourbar
    if isinstance(problem, ColumnGeometry):
        _keywords_only("sso.optimise(geometry, ...)", args)
        for note in practice_notes(problem):
            warnings.warn(note.text, PracticeWarning, stacklevel=2)
        selected = [keyword for keyword in COLUMN_OPTIMISER_KEYWORDS if keyword in options]
        if len(selected) > 1:
            raise TypeError(f"sso.optimise(geometry, ...) got {' and '.join(selected)}; give "
                            "at most one of " + ", ".join(COLUMN_OPTIMISER_KEYWORDS))
        return _column_optimiser(selected[0] if selected else None)
    if isinstance(problem, Mapping):
        _keywords_only("sso.optimise({name: geometry, ...}, ...)", args)
        for name, geometry in problem.items():
            if isinstance(geometry, ColumnGeometry):
                for note in practice_notes(geometry, label=f"[{name!r}].points_mm"):
                    warnings.warn(note.text, PracticeWarning, stacklevel=2)
        from sso._column.positions import optimise_positions
        return optimise_positions
    raise TypeError("problem must be an sso.ShaftSeries, an sso.FourBar, an "
                    "sso.ColumnGeometry or a mapping of names to ColumnGeometry, not "
                    f"{type(problem).__name__}")


def _keywords_only(call: str, args: tuple[Any, ...]) -> None:
    if args:
        raise TypeError(f"{call} takes keyword options only; got {len(args)} positional")


def _column_optimiser(keyword: str | None) -> Callable[..., Any]:
    """The column optimiser a keyword of :data:`COLUMN_OPTIMISER_KEYWORDS` selects (None: the
    yoke phasing for fixed hardpoints). Each is imported here: it loads CasADi, which a
    shaft series' dispatch has loaded lazily already and a column's evaluation never needs."""
    if keyword == "joint_boxes_mm":
        from sso._column.joint_centres import optimise_joint_centres
        return optimise_joint_centres
    if keyword == "tolerances":
        from sso._column.robust_phasing import optimise_robust
        return optimise_robust
    if keyword == "lock_deg":
        from sso._column.feel import optimise_on_centre
        return optimise_on_centre
    if keyword == "teeth":
        from sso._column.splines import best_spline_teeth
        return best_spline_teeth
    from sso._column.phasing import optimise_phasing
    return optimise_phasing
