"""A driveline case analysed (``sso evaluate``) or analysed and phased (``sso run``).

The result is :class:`DrivelineRun`: the case as read and the
:class:`sso.DrivelineResult` that :func:`sso.analyse_driveline` returns for it (with the
recommended yoke phasing when run), with the warnings and the package versions. Its
report renders it alone (:mod:`sso._reports.driveline_report`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from sso._cases.driveline import DrivelineCase
from sso._display import Part
from sso._driveline.figures import DrivelineResult, analyse_driveline
from sso._run.case_run import CaseRun, created_utc, package_versions

MODES = ("optimise", "evaluate")


@dataclass(frozen=True, eq=False, repr=False)
class DrivelineRun(CaseRun):
    """What one driveline case gave.

    Attributes
    ----------
    case : DrivelineCase
    mode : {"optimise", "evaluate"}
        ``sso run`` (with the phasing for the excitation limits) or ``sso evaluate``.
    result : sso.DrivelineResult
    """

    case: DrivelineCase
    mode: str
    result: DrivelineResult
    report_kind: ClassVar[str] = "driveline_run"

    def __post_init__(self) -> None:
        if self.mode not in MODES:
            raise ValueError(f"mode = {self.mode!r} is not one of {MODES}")

    @property
    def success(self) -> bool:
        """True: the analysis runs no solver that could fail (a rule may still fail)."""
        return True

    @property
    def verdict(self) -> str:
        """The rules' verdict in words."""
        failed = [rule for rule in self.result.rules if rule.passed is False]
        if not failed:
            return "every rule passes"
        return f"{len(failed)} rule checks fail (first: {failed[0].rule}, {failed[0].where})"

    def _repr_text(self) -> str:
        return f"{self.case.name}: {self.mode}, {self.verdict}"

    def _summary_parts(self) -> list[Part]:
        return [f"Driveline case {self.case.name} ({self.mode})", *self.result._summary_parts()]


def run_driveline(case: DrivelineCase, optimising: bool) -> DrivelineRun:
    """Analyse a driveline case; with ``optimising`` also recommend its yoke phasing (and
    its layout within the case's ``[layout]`` box; ``sso evaluate`` analyses it as given).

    Raises
    ------
    ValueError
        If the public API refuses the case's values.
    """
    result = analyse_driveline(case.driveline(), phasing=optimising,
                               layout=case.layout_box() if optimising else None)
    return DrivelineRun(warnings=case.warnings, versions=package_versions(),
                        created_utc=created_utc(), case=case,
                        mode="optimise" if optimising else "evaluate", result=result)
