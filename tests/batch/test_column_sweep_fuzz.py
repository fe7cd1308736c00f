"""Fuzzed sweep files of the shipped truck column, run as a user runs them (``sso sweep``):
never a traceback; one axis either runs (exit 0) or is refused before any point runs
(exit 2) with a message naming the axis; two axes may leave failed points (exit 1)."""

from __future__ import annotations

import json
from pathlib import Path

from fuzzing import run_sso, toml_document
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

ROOT = Path(__file__).resolve().parents[2]
TRUCK = ROOT / "cases" / "column_truck_three_joints.toml"
EXAMPLES = settings(max_examples=40, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                           HealthCheck.function_scoped_fixture])

KEYS = st.one_of(
    st.builds(lambda point, axis: f"hardpoints.points_mm[{point}][{axis}]",
              st.integers(0, 6), st.integers(0, 4)),
    st.builds(lambda shaft: f"phasing.yoke_phase_deg[{shaft}]", st.integers(0, 3)),
    st.builds(lambda shaft: f"splines.teeth[{shaft}]", st.integers(0, 3)),
    st.sampled_from(["tilt.angle_deg", "tilt.axis", "tilt.through_mm", "hardpoints.points_mm",
                     "steering.lock_deg", "excitation.rpm", "phasing.mode", "limits.bogus",
                     "joint_boxes.min_mm[0][2]", "tilt.angle_deg[0]", "kind", "solver.starts"]),
    st.text(max_size=20),
)
SCALARS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=-2000.0, max_value=2000.0),
    st.integers(min_value=-(10**30), max_value=10**30),
    st.integers(min_value=-5, max_value=40),
    st.sampled_from([1239.3, 328.7, -1690.3, 0.0, 89.99, 90.0, -90.0, 1e308, 5e-324, 36]),
    st.text(max_size=10),
    st.booleans(),
)
VALUES = st.one_of(
    st.lists(st.one_of(SCALARS, st.lists(SCALARS, max_size=3)), max_size=4),
    st.fixed_dictionaries({"start": SCALARS, "stop": SCALARS,
                           "num": st.one_of(st.integers(-2, 5), SCALARS.filter(
                               lambda value: not isinstance(value, int) or value < 6))}),
    st.fixed_dictionaries({"start": SCALARS, "stop": SCALARS, "step": SCALARS}),
    SCALARS,
)

# Axes a user would write, with values inside and just outside their ranges.
PLAUSIBLE = st.one_of(
    st.builds(lambda values: {"hardpoints.points_mm[1][2]": values},
              st.lists(st.floats(1230.0, 1250.0), min_size=1, max_size=3)),
    st.builds(lambda values: {"hardpoints.points_mm[0][0]": values},
              st.lists(st.floats(-2500.0, 0.0), min_size=1, max_size=3)),
    st.builds(lambda values: {"tilt.angle_deg": values},
              st.lists(st.floats(-95.0, 95.0), min_size=1, max_size=3)),
    st.builds(lambda values: {"phasing.yoke_phase_deg[1]": values},
              st.lists(st.floats(-200.0, 200.0), min_size=1, max_size=3)),
    st.builds(lambda values: {"splines.teeth[0]": values},
              st.lists(st.integers(-1, 60), min_size=1, max_size=2)),
    st.builds(lambda start, stop: {"tilt.angle_deg": {"start": start, "stop": stop, "num": 3}},
              st.floats(-20.0, 20.0), st.floats(-20.0, 20.0)),
)


@EXAMPLES
@given(axes=st.one_of(PLAUSIBLE, st.dictionaries(KEYS, VALUES, min_size=1, max_size=2)),
       action=st.sampled_from(["evaluate", "evaluate", "optimise"]))
def test_a_fuzzed_column_sweep_file_never_tracebacks(tmp_path_factory, axes, action):
    folder = tmp_path_factory.mktemp("fuzz")
    if action == "optimise":  # a few points only: each solves
        axes = {key: value[:2] if isinstance(value, list) else value
                for key, value in axes.items()}
    sweep_file = folder / "sweep.toml"
    sweep_file.write_text(toml_document({"case": str(TRUCK), "action": action, "name": "fuzz",
                                         "axes": axes}))
    code, text = run_sso(["sweep", str(sweep_file), "--out", str(folder / "out"), "--quiet",
                          "--workers", "1", "--no-plots"])
    event(f"exit {code}")
    assert code != "traceback", text
    allowed = (0, 2) if len(axes) == 1 else (0, 1, 2)
    assert code in allowed, text
    if code == 2:
        assert "error:" in text and "Traceback" not in text
        known = [key for key in axes if isinstance(key, str) and key.isprintable()
                 and json.dumps(key)[1:-1] == key and key in text]
        assert known or "axes" in text or "axis" in text or "sweep file" in text, text
