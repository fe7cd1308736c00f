"""Driveline excitation over an rpm range: SAE AE-7 small-angle figures and the exact model.

Small-angle figures (SAE AE-7, "Universal Joint and Driveshaft Design Manual";
the form below reproduces the published calibration of an open-source driveline
calculator to its printed precision, see ``docs/column.md``). Joint ``j`` of ``n``
alone makes the speed ratio ``1 - (beta_j^2 / 2) cos(2 (theta + Phi_j))``, with
``Phi_j`` the accumulated model phase, so each joint is a phasor
``z_j = beta_j^2 exp(2 i Phi_j)`` (deg^2):

* torsional equivalent angle ``sqrt(|sum_j z_j|)``: the output's excitation;
* drive equivalent angle ``sqrt(|sum_j (n - j) z_j|)``: the summed angular
  acceleration of the ``n - 1`` intermediate shafts (equal inertias) with the
  input at constant speed (joint ``j`` drives the ``n - j`` shafts after it);
* coast equivalent angle ``sqrt(|sum_j (j - 1) z_j|)``: the same with the output
  at constant speed (joint ``j`` drives the ``j - 1`` shafts before it);
* excitation ``omega^2 sin^2(equivalent angle)``, rad/s^2, ``omega`` the input speed.

For a planar column with yokes in phase or crossed the phasors are ``+-beta^2``,
the sign rules of the manual.

Exact model: the chain is one 2x2 matrix ``M``; as a single joint it has the
equivalent angle ``beta_eq`` with ``cos beta_eq = s_min / s_max`` (singular values),
``omega^2 sin^2 beta_eq`` is its small-angle excitation, and the output
acceleration amplitude is the largest ``|d w_out / dt|`` of
:meth:`sso.ShaftSeries.evaluate`.

Published limits (as used by driveline makers): inertial 1000 rad/s^2 for cars
and 2000 for trucks; torsional 300 / 500 rad/s^2. They are limits for propeller
shafts at driveline speeds, so they judge a driveline (``application="driveline"``)
and never a steering column, whose rows carry no limit and no verdict.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Any, overload

import numpy as np

from sso._column.chain_matrix import chain_matrix
from sso._display import Part, Readable, TextTable, format_number
from sso._record import Record, register_record
from sso._shafts.series import ShaftSeries
from sso._validation import as_float_tuple, check_choice, validate_speed

RPM_TO_RAD_S = 2.0 * math.pi / 60.0
INERTIAL_LIMIT_RAD_S2 = {"car": 1000.0, "truck": 2000.0}
TORSIONAL_LIMIT_RAD_S2 = {"car": 300.0, "truck": 500.0}
APPLICATIONS = ("steering", "driveline")


@register_record
@dataclass(frozen=True)
class EquivalentAngles:
    """Speed-independent excitation angles of a design, deg.

    Attributes
    ----------
    drive_deg, coast_deg, torsional_deg : float
        SAE AE-7 small-angle equivalent angles.
    exact_deg : float
        ``beta_eq`` of the exact chain (the single joint with the same matrix ``M``).
    """

    drive_deg: float
    coast_deg: float
    torsional_deg: float
    exact_deg: float


@register_record
@dataclass(frozen=True)
class ExcitationRow:
    """Excitation at one input speed, rad/s^2, with the published limits.

    Attributes
    ----------
    input_speed_rpm : float
    drive_rad_s2, coast_rad_s2, torsional_rad_s2 : float
        SAE AE-7 small-angle excitations ``omega^2 sin^2(angle)``.
    exact_torsional_rad_s2 : float
        ``omega^2 sin^2 beta_eq`` of the exact chain.
    exact_output_accel_rad_s2 : float
        Largest output angular acceleration of the exact model at constant input speed.
    inertial_limit_rad_s2, torsional_limit_rad_s2 : float or None
        Published limits for the vehicle kind; None for a steering column.
    within_limits : bool or None
        Drive and coast at or below the inertial limit, torsional at or below the
        torsional limit; None for a steering column (the limits do not apply).
    """

    input_speed_rpm: float
    drive_rad_s2: float
    coast_rad_s2: float
    torsional_rad_s2: float
    exact_torsional_rad_s2: float
    exact_output_accel_rad_s2: float
    inertial_limit_rad_s2: float | None
    torsional_limit_rad_s2: float | None
    within_limits: bool | None


@dataclass(frozen=True, eq=False, repr=False)
class ExcitationTable(Record, Readable):
    """Outcome of :func:`excitation_table`: one row per input speed, and what they came from.

    It reads as the tuple of its rows (``len``, indexing, iteration, unpacking).

    Attributes
    ----------
    vehicle : {"car", "truck"}
        Whose published limits the rows compare with.
    application : {"driveline", "steering"}
        A driveline is judged by the published limits; a steering column is not.
    angles : EquivalentAngles
        The design's equivalent angles, deg (the rows' excitations follow from them).
    rows : tuple of ExcitationRow
        One per input speed, in the order given.
    """

    vehicle: str
    application: str
    angles: EquivalentAngles
    rows: tuple[ExcitationRow, ...]

    @property
    def within_limits(self) -> bool | None:
        """True when every row is within the published limits; None where none apply."""
        if self.application != "driveline":
            return None
        return all(row.within_limits for row in self.rows)

    def _verdict(self) -> str:
        if self.within_limits is None:
            return "not judged (the published limits are a driveline's)"
        return "within" if self.within_limits else "NOT within"

    def __len__(self) -> int:
        return len(self.rows)

    def __iter__(self) -> Iterator[ExcitationRow]:
        return iter(self.rows)

    @overload
    def __getitem__(self, index: int) -> ExcitationRow: ...

    @overload
    def __getitem__(self, index: slice) -> tuple[ExcitationRow, ...]: ...

    def __getitem__(self, index: int | slice) -> ExcitationRow | tuple[ExcitationRow, ...]:
        return self.rows[index]

    def _repr_text(self) -> str:
        speeds = [row.input_speed_rpm for row in self.rows]
        return (f"{self.application}, {self.vehicle}, {len(self.rows)} speeds "
                f"{format_number(min(speeds))} to {format_number(max(speeds))} rpm, "
                f"{self._verdict()}")

    def _summary_parts(self) -> list[Part]:
        angles = self.angles
        def judged(value: bool | None) -> str:
            return "n/a" if value is None else "yes" if value else "no"

        return [
            f"Excitation ({self.application}, {self.vehicle} limits): {self._verdict()}",
            f"equivalent angles (deg): drive {format_number(angles.drive_deg)}, coast "
            f"{format_number(angles.coast_deg)}, torsional {format_number(angles.torsional_deg)}"
            f", exact {format_number(angles.exact_deg)}",
            TextTable(("input speed (rpm)", "drive (rad/s^2)", "coast (rad/s^2)",
                       "torsional (rad/s^2)", "exact torsional (rad/s^2)",
                       "exact output accel (rad/s^2)", "within limits"),
                      tuple((format_number(row.input_speed_rpm), format_number(row.drive_rad_s2),
                             format_number(row.coast_rad_s2), format_number(row.torsional_rad_s2),
                             format_number(row.exact_torsional_rad_s2),
                             format_number(row.exact_output_accel_rad_s2),
                             judged(row.within_limits)) for row in self.rows)),
            f"limits (rad/s^2): inertial {format_number(self.rows[0].inertial_limit_rad_s2)}, "
            f"torsional {format_number(self.rows[0].torsional_limit_rad_s2)}",
        ]


def equivalent_angles(series: ShaftSeries) -> EquivalentAngles:
    """The SAE AE-7 and exact equivalent angles of a design (exact-model phases).

    Raises
    ------
    TypeError
        If ``series`` is not a :class:`sso.ShaftSeries`.
    """
    _check_series(series)
    beta_deg = np.asarray(series.beta_deg)
    joints = len(beta_deg)
    accumulated = np.radians(np.concatenate([[0.0], np.cumsum(series.phase_deg)]))
    phasors = beta_deg**2 * np.exp(2j * accumulated)
    number = np.arange(1, joints + 1)
    matrix = chain_matrix(np.radians(beta_deg), np.radians(series.phase_deg))
    singular = np.linalg.svd(matrix, compute_uv=False)
    return EquivalentAngles(
        drive_deg=float(np.sqrt(abs(np.sum((joints - number) * phasors)))),
        coast_deg=float(np.sqrt(abs(np.sum((number - 1) * phasors)))),
        torsional_deg=float(np.sqrt(abs(np.sum(phasors)))),
        exact_deg=float(np.degrees(np.arccos(singular[1] / singular[0]))),
    )


def excitation_table(series: ShaftSeries, input_speed_rpm: Sequence[float],
                     vehicle: str = "car",
                     application: str = "driveline") -> ExcitationTable:
    """Excitation of a design over input speeds, beside the published limits.

    Parameters
    ----------
    series : sso.ShaftSeries
        The design (for a column: ``geometry.series(yoke_phase_deg)``); the exact
        figures use the exact model whatever ``series.model`` says.
    input_speed_rpm : sequence of float
        Input speeds, rpm, each finite and > 0.
    vehicle : {"car", "truck"}
        Which published limits apply.
    application : {"driveline", "steering"}
        A driveline is judged by the published limits; a steering column is not
        (its rows carry ``None`` limits and verdicts).

    Returns
    -------
    ExcitationTable
        The rows, one per speed (it reads as their tuple), with the vehicle and the
        equivalent angles.

    Raises
    ------
    TypeError
        If ``series`` is not a :class:`sso.ShaftSeries`.
    ValueError
        If a speed is not finite and positive, the list is empty, or the vehicle
        kind or the application is unknown.
    """
    _check_series(series)
    check_choice("vehicle", vehicle, tuple(INERTIAL_LIMIT_RAD_S2))
    check_choice("application", application, APPLICATIONS)
    judged = application == "driveline"
    speeds = as_float_tuple("input_speed_rpm", input_speed_rpm)
    if not speeds:
        raise ValueError("input_speed_rpm is empty: give at least one speed in rpm")
    speeds = tuple(validate_speed(f"input_speed_rpm[{index}]", speed)
                   for index, speed in enumerate(speeds))
    angles = equivalent_angles(series)
    exact = series if series.model == "exact" else _exact_copy(series)
    # The output acceleration at constant input speed scales with the speed squared.
    accel_per_rpm2 = exact.evaluate(input_speed_rpm=1.0).max_output_accel_rad_s2
    inertial = INERTIAL_LIMIT_RAD_S2[vehicle]
    torsional_limit = TORSIONAL_LIMIT_RAD_S2[vehicle]
    rows = []
    for speed in speeds:
        omega_squared = (speed * RPM_TO_RAD_S) ** 2
        drive, coast, torsional = (omega_squared * math.sin(math.radians(angle)) ** 2
                                   for angle in (angles.drive_deg, angles.coast_deg,
                                                 angles.torsional_deg))
        rows.append(ExcitationRow(
            input_speed_rpm=speed,
            drive_rad_s2=drive,
            coast_rad_s2=coast,
            torsional_rad_s2=torsional,
            exact_torsional_rad_s2=omega_squared * math.sin(math.radians(angles.exact_deg)) ** 2,
            exact_output_accel_rad_s2=accel_per_rpm2 * speed**2,
            inertial_limit_rad_s2=inertial if judged else None,
            torsional_limit_rad_s2=torsional_limit if judged else None,
            within_limits=(drive <= inertial and coast <= inertial
                           and torsional <= torsional_limit) if judged else None,
        ))
    return ExcitationTable(vehicle=vehicle, application=application, angles=angles,
                           rows=tuple(rows))


def _exact_copy(series: ShaftSeries) -> ShaftSeries:
    return ShaftSeries(series.beta_deg, series.phase_deg, "exact")


def _check_series(series: Any) -> None:
    if not isinstance(series, ShaftSeries):
        raise TypeError(f"series must be an sso.ShaftSeries, not {type(series).__name__}")
