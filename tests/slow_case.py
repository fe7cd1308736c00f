"""A case that keeps a solver busy: the paper model, five joints, one solver, many
starts (each a few milliseconds), and a sweep over it. For tests and benchmarks that
signal or race a run while it is solving."""

from __future__ import annotations

SLOW_CASE = """\
name = "slow"
model = "paper"
option = 3

[design]
beta_deg = [15.0, 20.0, 9.0, 12.0, 18.0]
phase_deg = [30.0, 40.0, 20.0, 10.0]

[bounds]
beta_deg = [0.0, 40.0]
phase_deg = [0.0, 180.0]

[solver]
solvers = ["{solver}"]
starts = {starts}
"""


SLOW_SWEEP = """\
name = "slow_sweep"
case = "slow.toml"
action = "optimise"
chunk_size = 1

[axes]
input_speed_rpm = [10, 20, 30, 40]
"""
"""A sweep of four points of the case saved as ``slow.toml`` beside it."""


def slow_case(solver: str = "ipopt", starts: int = 60) -> str:
    """The case file's text (its name is ``slow``)."""
    return SLOW_CASE.format(solver=solver, starts=starts)
