"""Planar mechanisms of the mechanism papers: four-bar, slider-crank, quick-return.

Each mechanism is a frozen dataclass of link lengths, validated on
construction; ``analyse`` evaluates the closed-form kinematics of
:mod:`sso._kinematics` over crank angles and returns a :class:`MechanismTable`.
Angles are in degrees here and counter-clockwise from +x; the crank speed is
in rad/s and its acceleration in rad/s^2, counter-clockwise positive; lengths
are in any consistent unit (``"length"`` in the table's units).
"""

import math
from abc import ABC, abstractmethod
from collections.abc import Iterable, Sequence
from dataclasses import Field, dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from sso._kinematics.fourbar import (
    BRANCH_SIDES,
    grashof_class,
    solve_fourbar,
    swing_angle,
)
from sso._kinematics.quick_return import solve_quick_return
from sso._kinematics.slider_crank import series_piston_motion, solve_slider_crank
from sso._kinematics.vector_loop import BoolArray, ComplexArray, FloatArray
from sso._linkages.registry import Linkage, OnUnassembled, register
from sso._linkages.table import MechanismTable
from sso._record import register_record
from sso._validation import check_choice, check_in_range, finite_float

__all__ = [
    "FourBar",
    "MechanismTable",
    "QuickReturn",
    "SliderCrank",
    "slider_crank_method_difference",
]

Column = tuple[str, str, np.ndarray]
"""A table column as (name, unit, values)."""


class CrankDriven(ABC):
    """What the mechanisms share: ``analyse`` over crank angles into a table.

    Every subclass is a frozen dataclass (:class:`sso._linkages.registry.Mechanism`).
    """

    __dataclass_fields__: ClassVar[dict[str, Field[Any]]]
    table_name: ClassVar[str]

    def analyse(
        self,
        crank_angle_deg: ArrayLike,
        *,
        crank_speed: float,
        crank_accel: float = 0.0,
        on_unassembled: OnUnassembled = "raise",
    ) -> MechanismTable:
        """Kinematics over crank angles, one table row per angle.

        Parameters
        ----------
        crank_angle_deg : array_like of float
            Crank angles (deg), finite, one-dimensional (a scalar is one row).
        crank_speed : float
            Crank angular velocity (rad/s, counter-clockwise positive).
        crank_accel : float
            Crank angular acceleration (rad/s^2, counter-clockwise positive).
        on_unassembled : {"raise", "mark"}
            What to do at crank angles where the mechanism cannot be assembled:
            raise, or return the table with a boolean ``assembled`` column and
            NaN in the quantities of those rows.

        Returns
        -------
        MechanismTable
            ``crank_angle_deg`` followed by the columns listed in the class's
            Notes, and ``assembled`` with ``on_unassembled="mark"``.

        Raises
        ------
        ValueError
            If an argument is invalid; if the mechanism cannot be assembled at
            some angles (with ``on_unassembled="raise"``; the message names
            them); or if it sits at a dead point (links in line, so that the
            velocities are not determined by the crank's).
        """
        angle_deg, crank_speed, crank_accel = _validate_drive(
            self, crank_angle_deg, crank_speed, crank_accel, on_unassembled
        )
        columns, assembled = self._columns(np.radians(angle_deg), crank_speed, crank_accel)
        columns = [("crank_angle_deg", "deg", angle_deg), *columns]
        return _table(self, self.table_name, columns, assembled, on_unassembled)

    @abstractmethod
    def _columns(
        self, crank_angle: FloatArray, crank_speed: float, crank_accel: float
    ) -> tuple[list[Column], BoolArray]:
        """Columns after ``crank_angle_deg`` and the assembled mask (angle in rad)."""


@register_record
@dataclass(frozen=True)
class FourBar(CrankDriven):
    """Four-bar linkage O_A-A-B-O_B driven by the crank O_A-A.

    O_A is the origin and O_B is at ``(ground, 0)``.

    Parameters
    ----------
    ground, crank, coupler, rocker : float
        Lengths O_A-O_B, O_A-A, A-B and O_B-B (length units, finite, > 0).
    branch : {"open", "crossed"}
        Assembly branch. "open" puts B to the left of the directed line
        A -> O_B (above the ground line when the crank is at 0 deg), as in the
        four-bar paper; "crossed" is its mirror image about that line.

    Raises
    ------
    ValueError
        If a length is not a finite number > 0 or the branch is unknown.

    Notes
    -----
    Columns of :meth:`analyse`: ``coupler_angle_deg`` (A -> B) and
    ``rocker_angle_deg`` (O_B -> B), both in [0, 360);
    ``transmission_angle_deg`` (interior angle at B, 0..180); ``joint_a_x``,
    ``joint_a_y``, ``joint_b_x``, ``joint_b_y`` (length);
    ``coupler_angular_velocity_rad_s``, ``rocker_angular_velocity_rad_s``,
    ``coupler_angular_accel_rad_s2``, ``rocker_angular_accel_rad_s2``.
    """

    ground: float
    crank: float
    coupler: float
    rocker: float
    branch: str = "open"

    table_name: ClassVar[str] = "four-bar"

    def __post_init__(self) -> None:
        _validate_lengths(self, ("ground", "crank", "coupler", "rocker"))
        _validate_choice(self, "branch", BRANCH_SIDES)

    def grashof(self) -> str:
        """Grashof class of the linkage with this crank as input.

        Returns
        -------
        str
            One of "crank-rocker", "rocker-crank", "double-crank",
            "double-rocker", "change-point", "non-Grashof triple-rocker"
            (see :func:`sso._kinematics.fourbar.grashof_class`).
        """
        return grashof_class(self.ground, self.crank, self.coupler, self.rocker)

    def swing_angle_deg(self) -> float:
        """Angle swept by the rocker over one crank revolution (deg).

        Returns
        -------
        float
            Difference of the rocker angles at the two limit positions, where
            crank and coupler are in line.

        Raises
        ------
        ValueError
            If the linkage is not a crank-rocker (the rocker then has no such
            pair of limit positions over a full crank turn).
        """
        kind = self.grashof()
        if kind != "crank-rocker":
            raise ValueError(f"swing angle needs a crank-rocker, but {self} is a {kind}")
        return math.degrees(swing_angle(self.ground, self.crank, self.coupler, self.rocker))

    def _columns(
        self, crank_angle: FloatArray, crank_speed: float, crank_accel: float
    ) -> tuple[list[Column], BoolArray]:
        motion = solve_fourbar(
            self.ground, self.crank, self.coupler, self.rocker, BRANCH_SIDES[self.branch],
            crank_angle, crank_speed, crank_accel,
        )
        columns = [
            ("coupler_angle_deg", "deg", _direction_deg(motion.coupler_angle)),
            ("rocker_angle_deg", "deg", _direction_deg(motion.rocker_angle)),
            ("transmission_angle_deg", "deg", np.degrees(motion.transmission_angle)),
            *_point_columns("joint_a", motion.joint_a),
            *_point_columns("joint_b", motion.joint_b),
            ("coupler_angular_velocity_rad_s", "rad/s", motion.coupler_angular_velocity),
            ("rocker_angular_velocity_rad_s", "rad/s", motion.rocker_angular_velocity),
            ("coupler_angular_accel_rad_s2", "rad/s^2", motion.coupler_angular_accel),
            ("rocker_angular_accel_rad_s2", "rad/s^2", motion.rocker_angular_accel),
        ]
        return columns, motion.assembled


@register_record
@dataclass(frozen=True)
class SliderCrank(CrankDriven):
    """Slider-crank: crank O-A, connecting rod A-B, piston pin B on a line.

    O is the origin; B slides along ``y = offset`` on the +x side of the crank.

    Parameters
    ----------
    crank, rod : float
        Lengths O-A and A-B (length units, finite, > 0).
    offset : float
        Height of the slider line above the crank pivot (length units, finite).

    Raises
    ------
    ValueError
        If a length is not a finite number > 0 or the offset is not finite.

    Notes
    -----
    Columns of :meth:`analyse`: ``rod_angle_deg`` (A -> B, in [0, 360));
    ``joint_a_x``, ``joint_a_y`` and ``piston_position`` (x of B) (length);
    ``rod_angular_velocity_rad_s``, ``rod_angular_accel_rad_s2``;
    ``piston_velocity`` (length/s) and ``piston_accel`` (length/s^2) along
    +x, exact. For zero offset also ``piston_velocity_approximate`` and
    ``piston_accel_approximate``: the classical two-term series (Holowenko),
    which holds for an in-line slider-crank only.
    """

    crank: float
    rod: float
    offset: float = 0.0

    table_name: ClassVar[str] = "slider-crank"

    def __post_init__(self) -> None:
        _validate_lengths(self, ("crank", "rod"))
        _validate_finite(self, "offset")

    def _columns(
        self, crank_angle: FloatArray, crank_speed: float, crank_accel: float
    ) -> tuple[list[Column], BoolArray]:
        motion = solve_slider_crank(
            self.crank, self.rod, self.offset, crank_angle, crank_speed, crank_accel
        )
        columns = [
            ("rod_angle_deg", "deg", _direction_deg(motion.rod_angle)),
            *_point_columns("joint_a", motion.crank_pin),
            ("piston_position", "length", motion.piston_position),
            ("rod_angular_velocity_rad_s", "rad/s", motion.rod_angular_velocity),
            ("rod_angular_accel_rad_s2", "rad/s^2", motion.rod_angular_accel),
            ("piston_velocity", "length/s", motion.piston_velocity),
            ("piston_accel", "length/s^2", motion.piston_accel),
        ]
        if self.offset == 0.0:
            velocity, accel = series_piston_motion(
                self.crank, self.rod, crank_angle, crank_speed, crank_accel
            )
            columns += [
                ("piston_velocity_approximate", "length/s", _mask(velocity, motion.assembled)),
                ("piston_accel_approximate", "length/s^2", _mask(accel, motion.assembled)),
            ]
        return columns, motion.assembled


@register_record
@dataclass(frozen=True)
class QuickReturn(CrankDriven):
    """Quick-return mechanism: four-bar O2-A-B-O4 driving slider C through link B-C.

    O2 is the origin, O4 is at ``(ground, 0)`` and C slides on ``y = 0`` on the
    far (+x) side of B, as in the quick-return paper.

    Parameters
    ----------
    crank, coupler, rocker : float
        Lengths O2-A, A-B and O4-B (length units, finite, > 0).
    slider_link : float
        Length B-C (length units, finite, > 0).
    ground : float
        Length O2-O4 (length units, finite, > 0).
    branch : {"crossed", "open"}
        Four-bar branch as in :class:`FourBar`. The paper's configuration, B
        below the line A -> O4, is "crossed".

    Raises
    ------
    ValueError
        If a length is not a finite number > 0 or the branch is unknown.

    Notes
    -----
    Columns of :meth:`analyse`: ``coupler_angle_deg`` (A -> B),
    ``rocker_angle_deg`` (O4 -> B), ``slider_link_angle_deg`` (B -> C), in
    [0, 360), and ``transmission_angle_deg``; positions
    ``joint_{a,b,c}_{x,y}`` (length); ``joint_{b,c}_velocity_{x,y}`` and
    ``joint_{b,c}_speed`` (length/s); ``joint_{b,c}_accel_{x,y}`` and
    ``joint_{b,c}_accel_magnitude`` (length/s^2); angular velocities
    ``{coupler,rocker,slider_link}_angular_velocity_rad_s`` and accelerations
    ``{coupler,rocker,slider_link}_angular_accel_rad_s2``.
    """

    crank: float
    coupler: float
    rocker: float
    slider_link: float
    ground: float
    branch: str = "crossed"

    table_name: ClassVar[str] = "quick-return"

    def __post_init__(self) -> None:
        _validate_lengths(self, ("crank", "coupler", "rocker", "slider_link", "ground"))
        _validate_choice(self, "branch", BRANCH_SIDES)

    def _columns(
        self, crank_angle: FloatArray, crank_speed: float, crank_accel: float
    ) -> tuple[list[Column], BoolArray]:
        motion = solve_quick_return(
            self.ground, self.crank, self.coupler, self.rocker, self.slider_link,
            BRANCH_SIDES[self.branch], crank_angle, crank_speed, crank_accel,
        )
        linkage = motion.linkage
        columns = [
            ("coupler_angle_deg", "deg", _direction_deg(linkage.coupler_angle)),
            ("rocker_angle_deg", "deg", _direction_deg(linkage.rocker_angle)),
            ("slider_link_angle_deg", "deg", _direction_deg(motion.slider_link_angle)),
            ("transmission_angle_deg", "deg", np.degrees(linkage.transmission_angle)),
            *_point_columns("joint_a", linkage.joint_a),
            *_point_columns("joint_b", linkage.joint_b),
            *_point_columns("joint_c", motion.joint_c),
            *_vector_columns("joint_b", "velocity", motion.joint_b_velocity),
            *_vector_columns("joint_c", "velocity", motion.slider_velocity + 0j),
            *_vector_columns("joint_b", "accel", motion.joint_b_accel),
            *_vector_columns("joint_c", "accel", motion.slider_accel + 0j),
            ("coupler_angular_velocity_rad_s", "rad/s", linkage.coupler_angular_velocity),
            ("rocker_angular_velocity_rad_s", "rad/s", linkage.rocker_angular_velocity),
            ("slider_link_angular_velocity_rad_s", "rad/s", motion.slider_link_angular_velocity),
            ("coupler_angular_accel_rad_s2", "rad/s^2", linkage.coupler_angular_accel),
            ("rocker_angular_accel_rad_s2", "rad/s^2", linkage.rocker_angular_accel),
            ("slider_link_angular_accel_rad_s2", "rad/s^2", motion.slider_link_angular_accel),
        ]
        return columns, motion.assembled


def slider_crank_method_difference(
    crank: float | Sequence[float],
    rod: float,
    crank_speed: float,
    crank_angle_deg: ArrayLike,
) -> MechanismTable:
    """Mean percentage difference between exact and series piston motion.

    Regenerates Tabel 2 of the slider-crank paper with correct formulas:
    for each crank length, the mean over the crank angles of
    ``|exact - series| / |exact| * 100``, with rows where both are zero (to
    rounding) counted as 0, for the piston velocity and the piston
    acceleration of an in-line slider-crank with constant crank speed.

    Parameters
    ----------
    crank : float or sequence of float
        Crank length(s), one table row each (length units, > 0).
    rod : float
        Connecting rod length (length units, > 0).
    crank_speed : float
        Crank angular velocity (rad/s).
    crank_angle_deg : array_like of float
        Crank angles averaged over (deg); the paper uses 0..360 step 15.

    Returns
    -------
    MechanismTable
        Columns ``crank``, ``rod`` (length), ``velocity_difference_pct`` and
        ``acceleration_difference_pct`` (%).

    Raises
    ------
    ValueError
        As in :class:`SliderCrank` and :meth:`SliderCrank.analyse`.
    """
    mechanisms = [SliderCrank(crank=length, rod=rod) for length in np.atleast_1d(crank)]
    velocity_pct, accel_pct = [], []
    for mechanism in mechanisms:
        table = mechanism.analyse(crank_angle_deg, crank_speed=crank_speed)
        velocity_scale = mechanism.crank * abs(crank_speed)
        velocity_pct.append(_mean_percent_difference(table, "piston_velocity", velocity_scale))
        accel_scale = velocity_scale * abs(crank_speed)
        accel_pct.append(_mean_percent_difference(table, "piston_accel", accel_scale))
    columns: list[Column] = [
        ("crank", "length", np.array([mechanism.crank for mechanism in mechanisms])),
        ("rod", "length", np.array([mechanism.rod for mechanism in mechanisms])),
        ("velocity_difference_pct", "%", np.array(velocity_pct)),
        ("acceleration_difference_pct", "%", np.array(accel_pct)),
    ]
    return _make_table("slider-crank method difference", columns)


def _mean_percent_difference(table: MechanismTable, quantity: str, scale: float) -> float:
    exact = table[quantity]
    approximate = table[f"{quantity}_approximate"]
    # sin(pi) is 1.2e-16, not 0: "zero" means zero to rounding relative to the
    # quantity's natural scale (r w for velocity, r w^2 for acceleration).
    rounding = 64.0 * np.finfo(float).eps * scale
    difference = np.abs(approximate - exact)
    both_zero = (np.abs(exact) <= rounding) & (difference <= rounding)
    ratio = np.divide(difference, np.abs(exact), out=np.zeros_like(difference), where=~both_zero)
    return float(100.0 * np.mean(ratio))


def _direction_deg(angle: FloatArray) -> FloatArray:
    degrees = np.mod(np.degrees(angle), 360.0)
    # np.mod(-1e-17, 360.0) rounds to 360.0; keep the range half-open.
    return np.where(degrees >= 360.0, 0.0, degrees)


def _point_columns(name: str, point: ComplexArray) -> list[Column]:
    return [(f"{name}_x", "length", point.real), (f"{name}_y", "length", point.imag)]


_VECTOR_QUANTITIES = {"velocity": ("speed", "length/s"), "accel": ("accel_magnitude", "length/s^2")}
"""Vector quantity of a joint -> (name of its magnitude, unit)."""


def _vector_columns(
    joint: str, quantity: str, vector: NDArray[np.complexfloating[Any, Any]]
) -> list[Column]:
    magnitude, unit = _VECTOR_QUANTITIES[quantity]
    return [
        (f"{joint}_{quantity}_x", unit, vector.real),
        (f"{joint}_{quantity}_y", unit, vector.imag),
        (f"{joint}_{magnitude}", unit, np.abs(vector)),
    ]


def _mask(values: FloatArray, keep: BoolArray) -> FloatArray:
    return np.where(keep, values, np.nan)


def _table(
    mechanism: object,
    name: str,
    columns: list[Column],
    assembled: BoolArray,
    on_unassembled: OnUnassembled,
) -> MechanismTable:
    """Check assembly and dead points, then build the table of ``columns``.

    The first column must be the crank angles (deg); they name the failing rows.
    """
    angle_deg = columns[0][2]
    if on_unassembled == "raise" and not assembled.all():
        raise ValueError(
            f"{mechanism} cannot be assembled at crank angle(s) "
            f"{_list_angles(angle_deg[~assembled])} deg; pass on_unassembled='mark' for a "
            f"table that marks those rows"
        )
    finite = np.all([np.isfinite(values) for _, _, values in columns], axis=0)
    dead = assembled & ~finite
    if dead.any():
        raise ValueError(
            f"{mechanism} is at a dead point (links in line, where its velocity equations "
            f"have no unique solution) at crank angle(s) {_list_angles(angle_deg[dead])} deg"
        )
    if on_unassembled == "mark":
        columns = [*columns, ("assembled", "", assembled)]
    return _make_table(name, columns)


def _make_table(name: str, columns: list[Column]) -> MechanismTable:
    return MechanismTable(
        name=name,
        columns={column: values for column, _, values in columns},
        units={column: unit for column, unit, _ in columns},
    )


def _list_angles(angles: FloatArray, most: int = 12) -> str:
    shown = ", ".join(f"{angle:g}" for angle in angles[:most])
    return f"[{shown}, ... ({len(angles)} in all)]" if len(angles) > most else f"[{shown}]"


def _validate_drive(
    mechanism: object,
    crank_angle_deg: ArrayLike,
    crank_speed: float,
    crank_accel: float,
    on_unassembled: str,
) -> tuple[FloatArray, float, float]:
    owner = f"{type(mechanism).__name__}.analyse: "
    try:
        angle_deg = np.atleast_1d(np.asarray(crank_angle_deg, dtype=float))
    except (TypeError, ValueError):
        angle_deg = np.array([np.nan])
    if angle_deg.ndim != 1 or angle_deg.size == 0 or not np.all(np.isfinite(angle_deg)):
        raise ValueError(
            f"{owner}crank_angle_deg = {crank_angle_deg!r} must be a non-empty "
            f"one-dimensional sequence of finite numbers (deg)"
        )
    check_choice(f"{owner}on_unassembled", on_unassembled, ("raise", "mark"))
    return (
        angle_deg,
        finite_float(f"{owner}crank_speed", crank_speed),
        finite_float(f"{owner}crank_accel", crank_accel),
    )


def _validate_lengths(mechanism: object, fields: tuple[str, ...]) -> None:
    for field in fields:
        name = f"{type(mechanism).__name__}.{field}"
        try:
            length = finite_float(name, getattr(mechanism, field))
        except ValueError as error:
            raise ValueError(f"{error}; allowed range (0, inf) length units") from None
        check_in_range(
            name, length, 0.0, math.inf, "length units", lower_open=True, upper_open=True
        )
        object.__setattr__(mechanism, field, length)


def _validate_finite(mechanism: object, field: str) -> None:
    name = f"{type(mechanism).__name__}.{field}"
    object.__setattr__(mechanism, field, finite_float(name, getattr(mechanism, field)))


def _validate_choice(mechanism: object, field: str, allowed: Iterable[str]) -> None:
    check_choice(f"{type(mechanism).__name__}.{field}", getattr(mechanism, field), allowed)


# ---------------------------------------------------------------- registry entries

register(
    Linkage(
        kind="fourbar",
        mechanism=FourBar,
        links=("ground", "crank", "coupler", "rocker"),
        extra="branch",
        report_columns=(
            "crank_angle_deg",
            "coupler_angle_deg",
            "rocker_angle_deg",
            "transmission_angle_deg",
            "joint_a_x",
            "joint_a_y",
            "joint_b_x",
            "joint_b_y",
            "coupler_angular_velocity_rad_s",
            "rocker_angular_velocity_rad_s",
            "coupler_angular_accel_rad_s2",
            "rocker_angular_accel_rad_s2",
        ),
        extreme_columns=(
            "transmission_angle_deg",
            "rocker_angle_deg",
            "coupler_angular_velocity_rad_s",
            "rocker_angular_velocity_rad_s",
            "coupler_angular_accel_rad_s2",
            "rocker_angular_accel_rad_s2",
        ),
        series_plots=(
            (
                "angular_motion.png",
                "coupler and rocker angular velocity and acceleration",
                (
                    (
                        "angular velocity (rad/s)",
                        (
                            ("coupler_angular_velocity_rad_s", "coupler"),
                            ("rocker_angular_velocity_rad_s", "rocker"),
                        ),
                    ),
                    (
                        "angular acceleration (rad/s$^2$)",
                        (
                            ("coupler_angular_accel_rad_s2", "coupler"),
                            ("rocker_angular_accel_rad_s2", "rocker"),
                        ),
                    ),
                ),
            ),
        ),
        coupler_point=True,
        transmission_plot=True,
        drawing="fourbar_like",
    )
)
register(
    Linkage(
        kind="slider_crank",
        mechanism=SliderCrank,
        links=("crank", "rod"),
        extra="offset",
        report_columns=(
            "crank_angle_deg",
            "rod_angle_deg",
            "piston_position",
            "rod_angular_velocity_rad_s",
            "rod_angular_accel_rad_s2",
            "piston_velocity",
            "piston_velocity_approximate",
            "piston_accel",
            "piston_accel_approximate",
        ),
        extreme_columns=(
            "piston_position",
            "piston_velocity",
            "piston_velocity_approximate",
            "piston_accel",
            "piston_accel_approximate",
            "rod_angular_velocity_rad_s",
            "rod_angular_accel_rad_s2",
        ),
        series_plots=(
            (
                "piston_motion.png",
                "piston velocity and acceleration, exact vs series (Holowenko)",
                (
                    (
                        "piston velocity ({length}/s)",
                        (
                            ("piston_velocity", "exact"),
                            ("piston_velocity_approximate", "series approximation", "--"),
                        ),
                    ),
                    (
                        "velocity, series - exact\n({length}/s)",
                        (("piston_velocity_approximate-piston_velocity", "series - exact"),),
                    ),
                    (
                        "piston acceleration ({length}/s$^2$)",
                        (
                            ("piston_accel", "exact"),
                            ("piston_accel_approximate", "series approximation", "--"),
                        ),
                    ),
                    (
                        "acceleration, series - exact\n({length}/s$^2$)",
                        (("piston_accel_approximate-piston_accel", "series - exact"),),
                    ),
                ),
            ),
            (
                "rod_motion.png",
                "connecting-rod angle, angular velocity and acceleration",
                (
                    ("rod angle (deg)", (("rod_angle_deg", "rod A->B"),)),
                    ("angular velocity (rad/s)", (("rod_angular_velocity_rad_s", "rod"),)),
                    ("angular acceleration (rad/s$^2$)", (("rod_angular_accel_rad_s2", "rod"),)),
                ),
            ),
        ),
        drawing="slider_crank",
    )
)
register(
    Linkage(
        kind="quick_return",
        mechanism=QuickReturn,
        links=("crank", "coupler", "rocker", "slider_link", "ground"),
        extra="branch",
        report_columns=(
            "crank_angle_deg",
            "joint_a_x",
            "joint_a_y",
            "joint_b_x",
            "joint_b_y",
            "joint_c_x",
            "joint_b_speed",
            "joint_c_velocity_x",
            "joint_b_accel_magnitude",
            "joint_c_accel_x",
            "rocker_angular_velocity_rad_s",
        ),
        extreme_columns=(
            "rocker_angle_deg",
            "transmission_angle_deg",
            "joint_c_x",
            "joint_c_velocity_x",
            "joint_c_accel_x",
            "joint_b_speed",
            "joint_b_accel_magnitude",
            "rocker_angular_velocity_rad_s",
            "slider_link_angular_velocity_rad_s",
        ),
        series_plots=(
            (
                "angular_motion.png",
                "angular velocity and acceleration of the links",
                (
                    (
                        "angular velocity (rad/s)",
                        (
                            ("coupler_angular_velocity_rad_s", "coupler AB"),
                            ("rocker_angular_velocity_rad_s", "rocker O4B"),
                            ("slider_link_angular_velocity_rad_s", "slider link BC"),
                        ),
                    ),
                    (
                        "angular acceleration (rad/s$^2$)",
                        (
                            ("coupler_angular_accel_rad_s2", "coupler AB"),
                            ("rocker_angular_accel_rad_s2", "rocker O4B"),
                            ("slider_link_angular_accel_rad_s2", "slider link BC"),
                        ),
                    ),
                ),
            ),
            (
                "slider_motion.png",
                "slider C and joint B: position, velocity, acceleration",
                (
                    ("slider position x$_C$ ({length})", (("joint_c_x", "slider C"),)),
                    (
                        "velocity ({length}/s)",
                        (
                            ("joint_c_velocity_x", "slider C, along x"),
                            ("joint_b_speed", "joint B, magnitude"),
                        ),
                    ),
                    (
                        "acceleration ({length}/s$^2$)",
                        (
                            ("joint_c_accel_x", "slider C, along x"),
                            ("joint_b_accel_magnitude", "joint B, magnitude"),
                        ),
                    ),
                ),
            ),
        ),
        default_branch="crossed",
        transmission_plot=True,
        drawing="fourbar_like",
    )
)
