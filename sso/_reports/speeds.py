"""``speeds.csv``: input angle, input speed and each design's output speed."""

from __future__ import annotations

import csv
import io
from collections.abc import Sequence

from sso._limits import REPORT_DIGITS
from sso._shafts.curves import ComparedDesign


def render_speeds_csv(designs: Sequence[ComparedDesign]) -> str:
    """CSV text: one row per input angle (deg, 0 to 360 by 1), speeds in rpm (6 digits).

    Columns: ``input_angle_deg``, ``input_speed_rpm``, then
    ``output_speed_<role>_rpm`` for each design (initial, optimum, reference), as
    the designs carry them.
    """
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(["input_angle_deg", "input_speed_rpm",
                     *[f"output_speed_{design.role}_rpm" for design in designs]])
    speed_rpm = designs[0].evaluation.input_speed_rpm
    for index, angle in enumerate(designs[0].input_angle_deg):
        writer.writerow([f"{angle:g}", f"{speed_rpm:.{REPORT_DIGITS}g}",
                         *[f"{design.output_speed_rpm[index]:.{REPORT_DIGITS}g}"
                           for design in designs]])
    return buffer.getvalue()
