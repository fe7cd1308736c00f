"""Resource estimates made before work starts, and the memory limit they must meet.

A tolerance study, a sweep or a multi-start run computes its memory and number of
solves up front (:class:`ResourceEstimate`); :func:`check_memory` refuses one whose
memory estimate exceeds the limit, saying the estimate and how to lower it.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import Any

from sso.limits import (
    DEFAULT_MEMORY_LIMIT_MB,
    MEMORY_LIMIT_VARIABLE,
    QUADRATURE_BLOCK_SAMPLES,
)
from sso.validation import finite_in_range

# Memory of one shaft-series NLP with IPOPT's exact Hessian, MB per joint, per free
# variable and per written-out quadrature angle: measured 17, 70 and 200 MB for 6, 12
# and 20 joints (11, 23, 39 free variables) with a 16-angle block (benchmarks/memory.py
# lists the whole workload), i.e. 0.26 MB per joint and free variable.
NLP_MB_PER_JOINT_VARIABLE_ANGLE = 0.26 / 16
NLP_BASE_MB = 10.0
# A finished run as kept in a result (its design, figures and solver record), MB.
RUN_MB = 0.01

MB = 2**20
FLOAT_BYTES = 8
# Live arrays of shape (block, figure angles) while a block of samples is evaluated
# (the chain's shaft vectors, ratio, slope, lag and their temporaries).
BLOCK_ARRAYS = 16
BLOCK_BYTES = 128 * MB


def block_samples(figure_samples: int) -> int:
    """Samples evaluated per numpy call so that one block needs at most ``BLOCK_BYTES``."""
    return max(1, BLOCK_BYTES // (BLOCK_ARRAYS * FLOAT_BYTES * figure_samples))



@dataclass(frozen=True)
class ResourceEstimate:
    """What a piece of work needs, computed before it starts.

    Attributes
    ----------
    task : str
        What is estimated ("tolerance study", "sweep", "multi-start run").
    memory_mb : float
        Estimated peak memory, MB.
    solves : int
        Solver runs or evaluations it performs.
    lower_it : str
        How to lower the estimate (which argument or key to reduce, and to what).
    """

    task: str
    memory_mb: float
    solves: int
    lower_it: str

    def describe(self) -> str:
        """One line: the estimate in words."""
        return f"{self.task}: about {self.memory_mb:,.0f} MB and {self.solves:,} solves"


def memory_limit_mb(value: Any = None) -> float:
    """The memory limit in MB: ``value`` if given, else ``SSO_MEMORY_LIMIT_MB``, else the
    default :data:`sso.limits.DEFAULT_MEMORY_LIMIT_MB`.

    Raises
    ------
    ValueError
        If the limit is not a number > 0.
    """
    if value is not None:
        return finite_in_range("memory_limit_mb", value, 0.0, math.inf, "MB", lower_open=True,
                               upper_open=True)
    text = os.environ.get(MEMORY_LIMIT_VARIABLE)
    if text is None or not text.strip():
        return DEFAULT_MEMORY_LIMIT_MB
    return finite_in_range(MEMORY_LIMIT_VARIABLE, text.strip(), 0.0, math.inf, "MB",
                           lower_open=True, upper_open=True)


def check_memory(estimate: ResourceEstimate, limit_mb: Any = None) -> ResourceEstimate:
    """Return ``estimate`` if it fits the memory limit, else refuse the work.

    Raises
    ------
    ValueError
        Giving the estimate, the limit and how to lower the estimate or raise the limit.
    """
    limit = memory_limit_mb(limit_mb)
    if estimate.memory_mb > limit:
        raise ValueError(
            f"{estimate.describe()}, above the memory limit of {limit:,.0f} MB; "
            f"{estimate.lower_it}, or raise the limit (memory_limit_mb, --memory-limit or "
            f"{MEMORY_LIMIT_VARIABLE})")
    return estimate


def nlp_memory_mb(joints: int, free_variables: int, samples: int) -> float:
    """Estimated memory of one built shaft-series NLP with its IPOPT instance, MB."""
    written_out = min(samples, QUADRATURE_BLOCK_SAMPLES)
    return NLP_BASE_MB + NLP_MB_PER_JOINT_VARIABLE_ANGLE * joints * free_variables * written_out


def multistart_estimate(joints: int, free_variables: int, samples: int, starts: int,
                        solvers: int) -> ResourceEstimate:
    """Memory and solves of :func:`sso.optimise` from ``starts`` starts per solver."""
    runs = starts * solvers
    return ResourceEstimate(
        task=f"multi-start run ({joints} joints, {free_variables} free angles, {starts} starts x "
             f"{solvers} solvers)",
        memory_mb=nlp_memory_mb(joints, free_variables, samples) + RUN_MB * runs,
        solves=runs,
        lower_it="fix more angles (option 1 or 2, or equal bounds pin a joint), use fewer "
                 "joints or fewer starts")
