"""The figures an engineer signs of a run, and the trade of the design recommended.

A column run's verdict leads with what a steering or driveline engineer signs off:
the speed-ratio and output-torque fluctuation (%), the largest transmission error
(deg) and the excitation at the top speed (rad/s^2), each of the design as given and
of the design recommended; RE, the optimiser's measure, comes last. Where the design
recommended makes any of them worse than the design as given (say, drive inertial
excitation up while torsional excitation falls), that is its trade, said beside the
gains.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from sso._display import format_number
from sso._limits import ROUND_OFF_FLOOR

if TYPE_CHECKING:  # a shaft series' report uses this module and loads no column module
    from sso._column.excitation import ExcitationTable
    from sso._column.steering_criteria import AssessedDesign
    from sso._shafts.evaluation import Evaluation

SIGNED_CRITERIA = {"speed-ratio fluctuation, lock to lock (peak to peak)":
                   "speed-ratio fluctuation (lock to lock)",
                   "largest transmission error, lock to lock":
                   "largest transmission error (lock to lock)"}
"""The steering criteria signed (:func:`sso._column.steering_criteria.criteria`'s names)
and their short names; the output-torque fluctuation stays in the steering table, and
the operating angles are the geometry's, the same for every phasing."""
WORSE_FRACTION = 1e-3
"""A figure counts as made worse when it grows by more than this fraction of its value
as given (changes within it are rounding of the figures, not a trade)."""
SIGNED_DIGITS = 4
ROUND_OFF_FRACTION = 1e-9
"""A figure at most this fraction of the larger of its two values is round-off, shown 0
(the plots' rule too: :data:`sso._reports.plots.ROUND_OFF`)."""
EXCITATION_FIGURES = (("drive_rad_s2", "drive inertial excitation"),
                      ("coast_rad_s2", "coast inertial excitation"),
                      ("torsional_rad_s2", "torsional excitation"))
"""Attribute of an excitation row, and its name in words (SAE AE-7 small-angle figures)."""


@dataclass(frozen=True)
class SignedFigure:
    """One figure of the design as given and of the design recommended.

    Attributes
    ----------
    name : str
        What the figure is, in words (``"torsional excitation at 2500 rpm"``).
    unit : str
        Its unit (``"%"``, ``"deg"``, ``"rad/s2"``; ``""`` for RE).
    as_given : float
        The design as given (``phasing.yoke_phase_deg``).
    recommended : float
        The design recommended.
    """

    name: str
    unit: str
    as_given: float
    recommended: float

    @property
    def worse(self) -> bool:
        """Whether the design recommended makes this figure worse (larger)."""
        growth = self.recommended - self.as_given
        return growth > WORSE_FRACTION * abs(self.as_given) and growth > ROUND_OFF_FLOOR

    def change(self) -> str:
        """``name as_given to recommended unit``, four significant digits."""
        unit = f" {self.unit}" if self.unit else ""
        return (f"{self.name} {self._shown(self.as_given)} to "
                f"{self._shown(self.recommended)}{unit}")

    def _shown(self, value: float) -> str:
        """Four digits; a figure at round-off of the larger of the two is 0 (its digits
        are those of the machine's rounding, not of the design). RE keeps its own
        convention, ``< 1e-15``."""
        scale = max(abs(self.as_given), abs(self.recommended))
        if self.unit and abs(value) <= ROUND_OFF_FRACTION * scale:
            return "0"
        return format_number(value, SIGNED_DIGITS)

    def value(self) -> str:
        """``name as_given unit`` (a design analysed as given, no recommendation)."""
        unit = f" {self.unit}" if self.unit else ""
        return f"{self.name} {format_number(self.as_given, SIGNED_DIGITS)}{unit}"

    def growth(self) -> str:
        """How much worse, in words: ``+12 %``, or ``5.4 times`` from twice up."""
        if self.as_given > 0.0 and self.recommended >= 2.0 * self.as_given:
            return f"{self.recommended / self.as_given:.3g} times"
        if self.as_given > 0.0:
            return f"+{100.0 * (self.recommended / self.as_given - 1.0):.3g} %"
        return f"+{format_number(self.recommended - self.as_given, SIGNED_DIGITS)}"


def figure_lines(figures: Sequence[SignedFigure], compared: bool) -> tuple[str, str | None]:
    """The figures in one line, and the trade in another (None when there is none).

    Parameters
    ----------
    figures : sequence of SignedFigure
        Signed figures first, RE last.
    compared : bool
        Whether a design was recommended (else the figures are of the design as
        given alone).
    """
    if not compared:
        return "; ".join(figure.value() for figure in figures), None
    worse = [figure for figure in figures if figure.worse]
    trade = None if not worse else (
        "Trade: the design recommended makes worse " + "; ".join(
            f"{figure.change()} ({figure.growth()})" for figure in worse))
    return "; ".join(figure.change() for figure in figures), trade


def signed_figures(given: AssessedDesign, recommended: AssessedDesign,
                   given_excitation: ExcitationTable, recommended_excitation: ExcitationTable,
                   residual_errors: tuple[float, float]) -> tuple[SignedFigure, ...]:
    """The signed figures of two designs: fluctuations, transmission error, excitation at
    the top speed, then RE.

    Parameters
    ----------
    given, recommended : AssessedDesign
        The steering figures of the design as given and of the one recommended.
    given_excitation, recommended_excitation : ExcitationTable
        Their excitation over rpm (the top speed is the last row: every excitation
        grows with the square of the speed).
    residual_errors : (float, float)
        RE as given and recommended.
    """
    figures = [SignedFigure(SIGNED_CRITERIA[first.name], first.unit, first.value, second.value)
               for first, second in zip(given.criteria, recommended.criteria, strict=True)
               if first.name in SIGNED_CRITERIA]
    top_given, top_recommended = given_excitation.rows[-1], recommended_excitation.rows[-1]
    figures += [SignedFigure(f"{name} at {top_given.input_speed_rpm:g} rpm", "rad/s2",
                             getattr(top_given, attribute), getattr(top_recommended, attribute))
                for attribute, name in EXCITATION_FIGURES]
    figures.append(SignedFigure("RE", "", *residual_errors))
    return tuple(figures)


def shaft_series_figures(initial: Evaluation, optimum: Evaluation | None
                         ) -> tuple[SignedFigure, ...]:
    """The signed figures of a shaft series, as given and optimised (the design as given
    twice without an optimum): speed fluctuation, transmission error, output
    acceleration at the input speed, then RE."""
    best = initial if optimum is None else optimum
    return (SignedFigure("speed fluctuation (peak to peak)", "%", 100.0 * initial.fluctuation,
                         100.0 * best.fluctuation),
            SignedFigure("transmission error, max |out - in|", "deg",
                         initial.transmission_error_deg, best.transmission_error_deg),
            SignedFigure(f"output acceleration at {initial.input_speed_rpm:g} rpm", "rad/s2",
                         initial.max_output_accel_rad_s2, best.max_output_accel_rad_s2),
            SignedFigure("RE", "", initial.residual_error, best.residual_error))
