"""``speeds.csv``: input angle, input speed and each design's output speed."""

from __future__ import annotations

import csv
import io
from collections.abc import Mapping
from typing import Any

from sso.reports.curves import speed_curves


def render_speeds_csv(document: Mapping[str, Any]) -> str:
    """CSV text: one row per input angle (deg, 0 to 360 by 1), speeds in rpm.

    Columns: ``input_angle_deg``, ``input_speed_rpm``, then
    ``output_speed_<role>_rpm`` for each design (initial, optimum, reference).
    """
    curves = speed_curves(document)
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    roles = list(curves.output_speed_rpm)
    writer.writerow(["input_angle_deg", "input_speed_rpm",
                     *[f"output_speed_{role}_rpm" for role in roles]])
    for index, angle in enumerate(curves.input_angle_deg):
        writer.writerow([f"{angle:g}", f"{curves.input_speed_rpm:.12g}",
                         *[f"{curves.output_speed_rpm[role][index]:.12g}" for role in roles]])
    return buffer.getvalue()
