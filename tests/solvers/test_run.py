"""The records of one solver run."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from sso._solvers.run import RunLimits, RunOutcome


def test_limits_are_constrained_only_with_constraint_functions():
    bounds_only = RunLimits(np.zeros(2), np.ones(2))
    assert not bounds_only.constrained
    assert bounds_only.constraint_lower.shape == (0,)
    assert RunLimits(np.zeros(2), np.ones(2), np.array([-np.inf]), np.array([0.0])).constrained


def test_records_are_frozen():
    outcome = RunOutcome(np.zeros(2), 0.5, 3, 4, 4, 0, True, "ok", 0.01)
    with pytest.raises(dataclasses.FrozenInstanceError):
        outcome.fun = 1.0  # type: ignore[misc]
    assert [field.name for field in dataclasses.fields(RunOutcome)] == [
        "x",
        "fun",
        "nit",
        "nfev",
        "njev",
        "status",
        "success",
        "message",
        "time_s",
    ]
