"""The example columns of tests/data/columns and random non-planar columns."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

DATA = Path(__file__).resolve().parent.parent / "data" / "columns"


def load(name: str) -> dict[str, Any]:
    """One example column (``truck_three_joints``, ``car_intermediate_shaft``)."""
    return json.loads((DATA / f"{name}.json").read_text())


def random_column(rng: np.random.Generator, joints: int, beta_range_deg=(2.0, 35.0)) -> np.ndarray:
    """Points of a random non-planar column: random shaft lengths, operating angles
    in ``beta_range_deg`` and bend directions, so the bend planes turn arbitrarily."""
    direction = rng.normal(size=3)
    direction /= np.linalg.norm(direction)
    points = [rng.uniform(-500, 500, 3)]
    points.append(points[-1] + rng.uniform(100, 600) * direction)
    for _ in range(joints):
        side = np.cross(direction, rng.normal(size=3))
        side /= np.linalg.norm(side)
        beta = np.radians(rng.uniform(*beta_range_deg))
        direction = np.cos(beta) * direction + np.sin(beta) * side
        points.append(points[-1] + rng.uniform(100, 600) * direction)
    return np.asarray(points)


def planar_points(bends_deg, shaft_mm: float = 400.0) -> np.ndarray:
    """Points of a planar column in the xy plane: each joint turns the heading by its
    signed bend (deg), so the operating angles are ``|bend|`` and gamma is 0 or 180."""
    heading, point, points = 0.0, np.zeros(3), [np.zeros(3)]
    for bend in [0.0, *bends_deg]:
        heading += np.radians(bend)
        point = point + shaft_mm * np.array([np.cos(heading), np.sin(heading), 0.0])
        points.append(point)
    return np.asarray(points)
