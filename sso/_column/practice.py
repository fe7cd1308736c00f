"""Where a column's hardpoints leave practice: notes a designer should read, with their source.

None of these stops an analysis; each says what looks wrong, why, and where the
advice comes from:

* a joint bent less than about 0.5 deg: a Hooke joint's needle bearings then hardly
  roll, and the standing needles brinell the cross's trunnions (driveline makers such
  as Dana Spicer advise at least 1/2 deg of operating angle in their driveshaft
  installation guides);
* a straight joint (0 deg) in a column: the same, and it has no bend plane of its
  own, so a plain shaft would do;
* a joint above the maker's limit (``max_operating_angle_deg``, default 35 deg: a
  typical catalogue maximum of a single steering universal joint, which makers rate
  at about 30 to 40 deg; no standard fixes it, so give the supplier's figure);
* a shaft shorter than 10 mm: steering columns and drivelines have shafts of tens to
  thousands of mm, so hardpoints that make one this short were most likely typed in
  metres (an sso plausibility check, not a published limit:
  :func:`sso._validation.metres_for_mm`, one of the case files' unit checks, which a
  case may confirm with ``[units] confirm``).

``sso.optimise(geometry, ...)`` raises each note as a :class:`PracticeWarning` at the
caller's line; a column case lists them in its warnings.
"""

from __future__ import annotations

from dataclasses import dataclass

from sso._column.geometry import ColumnGeometry, shaft_name
from sso._limits import DEFAULT_MAX_OPERATING_ANGLE_DEG
from sso._validation import UnitSuspicion, metres_for_mm

MIN_OPERATING_ANGLE_DEG = 0.5
BRINELLING_SOURCE = ("needle bearings that hardly roll brinell the trunnions; driveline makers "
                     "(Dana Spicer's driveshaft installation guides) advise at least 1/2 deg")
MAKER_LIMIT_SOURCE = ("the maker's rating of the joint; the default of 35 deg is a typical "
                      "catalogue maximum of a single steering universal joint (no standard "
                      "fixes it)")
METRES_SOURCE = ("sso's plausibility check: shafts of steering columns and drivelines are tens "
                 "to thousands of mm long")


class PracticeWarning(UserWarning):
    """A column leaves practice (:func:`practice_notes`); the analysis still runs."""


@dataclass(frozen=True)
class PracticeNote:
    """One way a column leaves practice.

    Attributes
    ----------
    key : str
        What the note is about, as the user wrote it (``"points_mm[2]"``; a case
        prefixes its table).
    reason : str
        What looks wrong, with the figures.
    source : str
        Where the advice comes from.
    unit : UnitSuspicion or None
        Set when the note is a value implausible in its unit (hardpoints in
        metres): a case may confirm it (``[units] confirm``).
    """

    key: str
    reason: str
    source: str
    unit: UnitSuspicion | None = None

    @property
    def text(self) -> str:
        """``key: reason (source)``, one line."""
        return f"{self.key}: {self.reason} ({self.source})"


def practice_notes(geometry: ColumnGeometry, *,
                   max_operating_angle_deg: float = DEFAULT_MAX_OPERATING_ANGLE_DEG,
                   label: str = "points_mm") -> tuple[PracticeNote, ...]:
    """Every way ``geometry`` leaves practice (module notes), joints first.

    Parameters
    ----------
    geometry : ColumnGeometry
        The column.
    max_operating_angle_deg : float
        The joint maker's largest operating angle, deg.
    label : str
        The name of the points as the user gave them (a case passes
        ``"hardpoints.points_mm"``).

    Returns
    -------
    tuple of PracticeNote
        Empty when the column is within practice.
    """
    notes = []
    for joint, (beta, straight) in enumerate(zip(geometry.beta_deg, geometry.straight_joints,
                                                 strict=True), start=1):
        key = f"{label}[{joint}]"
        if straight:
            notes.append(PracticeNote(
                key, f"joint {joint} is straight (0 deg): it has no bend plane, and a plain "
                "shaft would do its work", BRINELLING_SOURCE))
        elif beta < MIN_OPERATING_ANGLE_DEG:
            notes.append(PracticeNote(
                key, f"joint {joint} runs at {beta:.3g} deg, below about "
                f"{MIN_OPERATING_ANGLE_DEG:g} deg", BRINELLING_SOURCE))
        elif beta > max_operating_angle_deg:
            notes.append(PracticeNote(
                key, f"joint {joint} runs at {beta:.3g} deg, above the maker's limit of "
                f"{max_operating_angle_deg:g} deg", MAKER_LIMIT_SOURCE))
    lengths = geometry.shaft_length_mm
    shortest = min(range(len(lengths)), key=lambda index: lengths[index])
    what = f"{shaft_name(shortest, len(lengths))}, P{shortest} to P{shortest + 1}"
    metres = metres_for_mm(label, lengths[shortest], what)
    if metres is not None:
        notes.append(PracticeNote(
            label, f"the shortest shaft ({what}) is {lengths[shortest]:.3g} mm long: the "
            "hardpoints look like metres; give them in mm", METRES_SOURCE, unit=metres))
    return tuple(notes)
