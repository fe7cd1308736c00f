"""``steering.png``: one figure of the three steering curves of every assembly.

The curves are the steering range's own (tests/column/test_column_steering_range.py
checks them against the 3D simulation); here the image is a real PNG of the report's
size, and it changes when an assembly changes.
"""

from __future__ import annotations

import json
import struct
from pathlib import Path

from sso._column.geometry import ColumnGeometry
from sso._column.steering_criteria import assess_steering
from sso._reports.column_steering_plots import steering_plot
from sso._reports.plots import HEIGHT_PX, WIDTH_PX

TRUCK = json.loads((Path(__file__).resolve().parents[1] / "data" / "columns"
                    / "truck_three_joints.json").read_text())["points_mm"]


def plot(yoke: tuple[float, float]) -> bytes:
    designs = [("as_built", "as built", yoke), ("in_phase", "yokes in phase", (0.0, 0.0))]
    steering = assess_steering(ColumnGeometry(TRUCK), designs, lock_deg=900.0)
    return steering_plot(steering)


def test_the_plot_is_a_png_of_the_report_size_and_follows_the_assemblies():
    image = plot((10.0, -80.0))
    assert image[:8] == b"\x89PNG\r\n\x1a\n"
    assert struct.unpack(">II", image[16:24]) == (WIDTH_PX, HEIGHT_PX)
    assert plot((20.0, -80.0)) != image
