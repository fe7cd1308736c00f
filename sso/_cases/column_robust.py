"""Case keys of robust yoke phasing in a ``column`` case: positions, tolerances, band, feel.

* ``[hardpoints.positions]``: named positions of one adjustable column (tilt,
  telescope), each a list of points with the joint count of ``hardpoints.points_mm``;
  ``phasing.positions_objective`` (``"worst"`` or ``"mean"``) and
  ``phasing.position_weights`` (with ``"mean"``) choose one phasing for all of them;
* ``[tolerances]``: manufacturing tolerances and their seeded sample, and
  ``robust_objective`` (``"mean"`` or ``"pNN"``) of the tolerance-aware phasing;
* ``[band] re_limit``: the RE limit of the tolerance bands;
* ``[feel]``: straight ahead, on-centre window and lock for the steering feel.

The single-geometry studies (tolerances, band, feel) run on ``hardpoints.points_mm``.
Semantics: ``docs/robust.md``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from sso._cases.column_points import point_list
from sso._cases.schema import REQUIRED, Key, choice, number, whole_number
from sso._column.cancel import can_cancel
from sso._column.feel import MAX_ON_CENTRE_WEIGHT
from sso._column.geometry import ColumnGeometry
from sso._column.positions import POSITIONS_OBJECTIVES
from sso._column.robust_phasing import LOWEST_PERCENTILE, PERCENTILE_PATTERN
from sso._column.tolerances import (
    DISTRIBUTIONS,
    MAX_HARDPOINT_MM,
    MAX_SAMPLES,
    MAX_YOKE_PHASE_DEG,
    MIN_SAMPLES,
)
from sso._limits import (
    DEFAULT_ON_CENTRE_WEIGHT,
    DEFAULT_TOLERANCE_SAMPLES,
    DEFAULT_WINDOW_DEG,
    MAX_COLUMN_SAMPLES,
)

MAX_POSITIONS = 20
ROBUST_TABLES = frozenset({"tolerances", "band", "feel"})


def positions_table(label: str, value: Any) -> dict[str, tuple[tuple[float, float, float], ...]]:
    """Parser of ``[hardpoints.positions]``: position name -> list of ``[x, y, z]`` points."""
    if not isinstance(value, dict) or not 2 <= len(value) <= MAX_POSITIONS:
        raise ValueError(f"{label} must be a table of 2 to {MAX_POSITIONS} named positions, "
                         "each a list of [x, y, z] points in mm (e.g. tilt_up = [[...], ...])")
    return {name: point_list(f"{label}.{name}", points) for name, points in value.items()}


def position_weights(label: str, value: Any) -> dict[str, float]:
    """Parser of ``phasing.position_weights``: position name -> weight in ``[0, inf)``."""
    if not isinstance(value, dict) or not value:
        raise ValueError(f"{label} = {value!r} must be a table of position names to weights, "
                         "each a number in [0, inf)")
    item = number(0.0, math.inf)
    return {name: item(f"{label}.{name}", weight) for name, weight in value.items()}


def robust_objective(label: str, value: Any) -> str:
    """Parser of ``tolerances.robust_objective``: ``"mean"`` or ``"pNN"``, 50 <= NN < 100."""
    match = PERCENTILE_PATTERN.fullmatch(value) if isinstance(value, str) else None
    if value != "mean" and (match is None
                            or not LOWEST_PERCENTILE <= float(match.group(1)) < 100.0):
        raise ValueError(f"{label} = {value!r} is not 'mean' or a percentile 'pNN' with "
                         "50 <= NN < 100 (e.g. 'p95')")
    return str(value)


def _when_given(table_key: str, default: Any) -> Callable[[dict[str, Any], str], Any]:
    """A default that applies only when the optional table holding ``table_key`` is given
    (so a case without the table round-trips through ``to_dict``)."""
    def value(values: dict[str, Any], path: str) -> Any:
        return default if table_key in values else None

    return value


ROBUST_KEYS: tuple[Key, ...] = (
    Key("hardpoints", "positions", positions_table, None, "mm",
        f"a table of 2 to {MAX_POSITIONS} named positions ([hardpoints.positions] "
        "tilt_up = [[x, y, z], ...]), each with as many points as hardpoints.points_mm"),
    Key("phasing", "positions_objective", choice(POSITIONS_OBJECTIVES), "worst", "",
        "'worst' (least worst-position RE) or 'mean' (least weighted mean RE)"),
    Key("phasing", "position_weights", position_weights, None, "",
        "with positions_objective = 'mean': a weight in [0, inf) for every position "
        "(not all 0); default equal"),
    Key("tolerances", "hardpoint_mm", number(0.0, MAX_HARDPOINT_MM, "mm"), REQUIRED, "mm",
        f"[0, {MAX_HARDPOINT_MM:g}]: error of every coordinate of every hardpoint"),
    Key("tolerances", "yoke_phase_deg", number(0.0, MAX_YOKE_PHASE_DEG, "deg"), REQUIRED, "deg",
        f"[0, {MAX_YOKE_PHASE_DEG:g}]: error of each yoke phasing (spline backlash, assembly)"),
    Key("tolerances", "samples", whole_number(MIN_SAMPLES, MAX_SAMPLES),
        _when_given("tolerances.hardpoint_mm", DEFAULT_TOLERANCE_SAMPLES), "",
        f"[{MIN_SAMPLES}, {MAX_SAMPLES}] built columns in the sample"),
    Key("tolerances", "yield_samples", whole_number(1, MAX_COLUMN_SAMPLES), None, "",
        f"[1, {MAX_COLUMN_SAMPLES:,}] built columns the yield against [limits] is judged on "
        "(sso run, sso evaluate), drawn from the same errors and seed; default: samples. "
        "Beyond the sample the tolerance-aware phasing carries (at most "
        f"{MAX_SAMPLES:,}), so the yield's interval narrows (about 36 us a built column "
        "and design judged)"),
    Key("tolerances", "seed", whole_number(0, 2**63 - 1),
        _when_given("tolerances.hardpoint_mm", 0), "", "[0, 2^63 - 1]: seed of the sample"),
    Key("tolerances", "distribution", choice(DISTRIBUTIONS),
        _when_given("tolerances.hardpoint_mm", "normal"), "",
        "'normal' (tolerance = standard deviation) or 'uniform' (= half-width)"),
    Key("tolerances", "robust_objective", robust_objective,
        _when_given("tolerances.hardpoint_mm", "p95"), "",
        "'mean' or 'pNN' with 50 <= NN < 100 (CVaR, the mean of the worst 100 - NN %)"),
    Key("band", "re_limit", number(0.0, math.inf, lower_open=True, upper_open=True), REQUIRED,
        "", "(0, inf), at or above the least RE any phasing of the column reaches"),
    Key("feel", "straight_ahead_deg", number(-360.0, 360.0, "deg"), REQUIRED, "deg",
        "[-360, 360]: input angle theta at straight ahead"),
    Key("feel", "lock_deg", number(0.0, 3600.0, "deg"), REQUIRED, "deg",
        "[0, 3600]: steering-wheel angle from straight ahead to each lock"),
    Key("feel", "window_deg", number(0.0, 90.0, "deg", lower_open=True, upper_open=True),
        _when_given("feel.lock_deg", DEFAULT_WINDOW_DEG), "deg",
        "(0, 90): half-width of the on-centre and lock windows"),
    Key("feel", "on_centre_weight", number(0.0, MAX_ON_CENTRE_WEIGHT),
        _when_given("feel.lock_deg", DEFAULT_ON_CENTRE_WEIGHT), "",
        f"[0, {MAX_ON_CENTRE_WEIGHT:g}]: weight of the on-centre variance in the on-centre "
        "phasing's objective"),
)


def check_robust(values: dict[str, Any], geometry: ColumnGeometry) -> None:
    """Check the robust keys against each other and the column; raise naming the key.

    Raises
    ------
    ValueError
        A position that is not a column or has another joint count, weights that do
        not name exactly the positions (or with ``"worst"``), a percentile with no
        sample in its tail, or ``band.re_limit`` below the least RE reachable.
    """
    positions = values.get("hardpoints.positions")
    weights = values.get("phasing.position_weights")
    if positions is not None:
        for name, points in positions.items():
            label = f"hardpoints.positions.{name}"
            try:
                column = ColumnGeometry(points)
            except ValueError as error:
                raise ValueError(f"{label}: {error}") from None
            if column.joint_count != geometry.joint_count:
                raise ValueError(f"{label} has {column.joint_count} joints "
                                 f"({len(points)} points) but hardpoints.points_mm has "
                                 f"{geometry.joint_count}: every position of one column must "
                                 "have the same joint count")
    if weights is not None:
        if positions is None:
            raise ValueError("phasing.position_weights needs [hardpoints.positions]")
        if values["phasing.positions_objective"] != "mean":
            raise ValueError("phasing.position_weights applies to phasing.positions_objective = "
                             f"'mean', not {values['phasing.positions_objective']!r}")
        if set(weights) != set(positions):
            raise ValueError(f"phasing.position_weights names {sorted(weights)}; it must name "
                             f"exactly the positions {sorted(positions)}")
        if not any(weight > 0 for weight in weights.values()):
            raise ValueError("phasing.position_weights are all 0: at least one must be positive")
    objective = values.get("tolerances.robust_objective")
    if objective not in (None, "mean"):
        level = float(objective[1:]) / 100.0
        samples = values["tolerances.samples"]
        if (1.0 - level) * samples < 1.0:
            raise ValueError(f"tolerances.robust_objective = {objective!r} needs at least "
                             f"{math.ceil(1.0 / (1.0 - level))} samples to have one in its "
                             f"tail; tolerances.samples = {samples}")
    limit = values.get("band.re_limit")
    if limit is not None:
        least = can_cancel(geometry.beta_deg).minimum_residual_error
        if limit < least:
            raise ValueError(f"band.re_limit = {limit:g} is below the least RE any yoke phasing "
                             f"of the column at hardpoints.points_mm reaches ({least:.6g}): no "
                             "design meets it")
