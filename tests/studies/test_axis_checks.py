"""Axis values read where a sweep's chunks run, against each value read on its own.

Reference: :func:`sso._studies.axis_checks.check_values` of one value at a time (the base
case read with the value set, as a case file is read); a chunk's reading, whichever
chunk reads a value first and whatever the worker kept, must give the same verdict and
warnings.
"""

from __future__ import annotations

import numpy as np

from sso._studies import axis_checks
from sso._studies.axes import base_case
from sso._studies.axis_checks import check_values, chunk_axes

DOCUMENT = base_case({"design": {"beta_deg": [30.0, 40.0, 40.0], "phase_deg": [90.0, 90.0]},
                      "bounds": {"beta_deg": [10.0, 40.0], "phase_deg": [0.0, 180.0]},
                      "option": 3, "model": "exact",
                      "solver": {"solvers": ["lm"], "starts": 2}}).to_dict()
PATHS = ("design.beta_deg[2]", "design.beta_deg[0]")
TARGETS = (("beta_deg", 2), ("beta_deg", 0))
VALUES = ((25.0, 50.0, 95.0, 30.0, 12.0), (20.0, 91.0, 35.0))


def alone(axis, position):
    accepted, notes = check_values(DOCUMENT, PATHS[axis], [VALUES[axis][position]],
                                   TARGETS[axis], "optimise")
    return bool(accepted[0]), notes[0]


def read(run, lows, highs, taken):
    """chunk_axes of a chunk holding values lows[k]:highs[k] of each axis, its points
    taking the positions ``taken[k]`` (relative to the chunk's values)."""
    return chunk_axes(run, DOCUMENT, "optimise", PATHS, TARGETS,
                      [VALUES[axis][low:high] for axis, (low, high) in
                       enumerate(zip(lows, highs, strict=True))],
                      [np.array(positions) for positions in taken], lows)


def test_values_read_by_chunks_are_those_read_one_by_one():
    first = read("run-a", (0, 0), (3, 3), ([0, 1, 2], [0, 1, 2]))
    second = read("run-a", (2, 0), (5, 3), ([0, 1, 2], [0, 2]))  # 95.0 read before
    assert [axis.accepted.tolist() for axis in first] == [[True, True, False],
                                                          [True, False, True]]
    for axis, low, chunk in ((0, 0, first[0]), (1, 0, first[1]), (0, 2, second[0])):
        for position, (accepted, notes) in enumerate(zip(chunk.accepted, chunk.notes,
                                                         strict=True)):
            assert (bool(accepted), notes) == alone(axis, low + position)
    assert any("start beta_deg[2] = 50 deg lies outside its bounds" in note
               for note in first[0].notes[1])
    assert second[1].notes[2] == alone(1, 2)[1]


def test_a_value_no_point_takes_is_not_read():
    (chunk,) = chunk_axes("run-b", DOCUMENT, "optimise", PATHS[:1], TARGETS[:1],
                          [VALUES[0]], [np.array([0, 3])], (0,))
    assert alone(0, 1)[0]  # accepted when read, but no point of the chunk takes it
    assert chunk.accepted.tolist() == [True, False, False, True, False]


def test_only_the_latest_run_is_kept_and_a_new_run_reads_again():
    read("run-c", (0, 0), (5, 3), ([0, 1, 2, 3, 4], [0, 1, 2]))
    assert list(axis_checks._READ) == ["run-c"]
    assert len(axis_checks._READ["run-c"]) == 8
    read("run-d", (0, 0), (1, 1), ([0], [0]))
    assert list(axis_checks._READ) == ["run-d"]
    assert len(axis_checks._READ["run-d"]) == 2
