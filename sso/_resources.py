"""Resource estimates made before work starts, and the memory limit they must meet.

A tolerance study, a sweep or a multi-start run computes its memory and number of
solves up front (:class:`ResourceEstimate`); :func:`check_memory` refuses one whose
memory estimate exceeds the limit, saying the estimate and how to lower it.
"""

from __future__ import annotations

import functools
import math
import os
from dataclasses import dataclass
from typing import Any

from sso._limits import (
    DEFAULT_MEMORY_LIMIT_MB,
    MEMORY_LIMIT_VARIABLE,
    QUADRATURE_BLOCK_SAMPLES,
)
from sso._validation import finite_in_range

# Memory of one shaft-series NLP with IPOPT's exact Hessian, MB per joint, per free
# variable and per written-out quadrature angle: measured 17, 70 and 200 MB for 6, 12
# and 20 joints (11, 23, 39 free variables) with a 16-angle block (benchmarks/memory.py
# lists the whole workload), i.e. 0.26 MB per joint and free variable.
NLP_MB_PER_JOINT_VARIABLE_ANGLE = 0.26 / 16
NLP_BASE_MB = 10.0
# A finished run as kept in a result (its design, figures and solver record), MB.
RUN_MB = 0.01
# Peak memory of the batched least squares per start, bytes, where every start goes on
# to the Newton steps and saddle tests (RE = 0 out of reach): it grows with the square
# and the cube of the free angles (the Jacobians at the saddle test's 2 x free points),
# plus each start's own record. Measured (benchmarks/memory_estimate.py): sso.optimise's
# screening 265 KB a start at 31 free angles and 1.6 MB at 63 (32 and 64 joints,
# option 1: peaks of 232 MB from 400 starts and over 1.7 GB from 1,000), 7 KB at 5
# (10,000 starts: 195 MB); sso.optimise_batch 5.6, 38 and 398 KB a start at 3, 9 and 31.
SCREEN_BYTES_PER_VARIABLE_PAIR = 135
SCREEN_BYTES_PER_VARIABLE_CUBE = 4.5
SCREEN_BYTES_PER_START = 8000
# Peak of a process that has imported sso and numpy (an optimise_batch call), and of one
# that has also built and run a CasADi NLP with IPOPT and SLSQP (a multi-start run), MB:
# measured 45 and 55 MB (benchmarks/memory_estimate.py).
NUMPY_PROCESS_MB = 50.0
SOLVER_PROCESS_MB = 60.0

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
        return f"{self.task}: about {megabytes(self.memory_mb)} MB and {self.solves:,} solves"


def megabytes(value: float) -> str:
    """A memory in MB as a person reads it: whole MB from 10 MB, else 2 digits (0.0029)."""
    return f"{value:,.0f}" if value >= 10 else f"{value:.2g}"


def memory_limit_mb(value: Any = None) -> float:
    """The memory limit in MB: ``value`` if given, else ``SSO_MEMORY_LIMIT_MB``, else the
    default :data:`sso._limits.DEFAULT_MEMORY_LIMIT_MB`.

    Raises
    ------
    ValueError
        If the limit is not a number > 0.
    """
    if value is not None:
        return finite_in_range("memory_limit_mb", value, 0.0, math.inf, "MB", lower_open=True,
                               upper_open=True)
    return _limit_of_text(os.environ.get(MEMORY_LIMIT_VARIABLE))


def _limit_of_text(text: str | None) -> float:
    """The limit that the environment variable's value ``text`` (None: unset) sets, MB.

    Raises
    ------
    ValueError
        If the text is not a number > 0.
    """
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
        # The limit as given (0.0001 MB, not "0 MB"), and, below 1 MB, that it is in MB.
        unit_hint = (f" (the limit is in MB: {DEFAULT_MEMORY_LIMIT_MB:,.0f}, the default, "
                     f"is {DEFAULT_MEMORY_LIMIT_MB / 1024:g} GB)" if limit < 1 else "")
        raise ValueError(
            f"{estimate.describe()}, above the memory limit of {limit:,.6g} MB{unit_hint}; "
            f"{estimate.lower_it}, or raise the limit to at least "
            f"{megabytes(estimate.memory_mb)} MB (memory_limit_mb, --memory-limit or "
            f"{MEMORY_LIMIT_VARIABLE})")
    return estimate


def nlp_memory_mb(joints: int, free_variables: int, samples: int) -> float:
    """Estimated memory of one built shaft-series NLP with its IPOPT instance, MB."""
    written_out = min(samples, QUADRATURE_BLOCK_SAMPLES)
    return NLP_BASE_MB + NLP_MB_PER_JOINT_VARIABLE_ANGLE * joints * free_variables * written_out


def batch_least_squares_mb(problems: int, variables: int) -> float:
    """Peak memory of the batched least squares (the screening of sso.optimise's starts,
    sso.optimise_batch) on ``problems`` problems of ``variables`` variables each, MB."""
    per_problem = (SCREEN_BYTES_PER_VARIABLE_PAIR * variables**2
                   + SCREEN_BYTES_PER_VARIABLE_CUBE * variables**3 + SCREEN_BYTES_PER_START)
    return problems * per_problem / MB


@functools.lru_cache(maxsize=256)
def multistart_estimate(joints: int, free_variables: int, samples: int, starts: int,
                        solvers: int, screened: bool) -> ResourceEstimate:
    """Memory and solves of :func:`sso.optimise` from ``starts`` starts per solver.

    ``screened``: the starts are first solved by the batched least-squares solver (the
    exact model), whose memory grows with the starts and the square and cube of the
    free angles: 1,000 starts of 64 joints with 63 free angles need about 1.6 GB.
    Kept for repeated calls (a single solve costs a few times what this does).
    """
    runs = kept_runs = starts * solvers
    screening_mb = 0.0
    if screened:  # "lm" screens every start; only IPOPT's and SLSQP's runs are kept
        screening_mb = batch_least_squares_mb(starts, free_variables)
        kept_runs = solvers
    return ResourceEstimate(
        task=f"multi-start run ({joints} joints, {free_variables} free angles, {starts} starts x "
             f"{solvers} solvers)",
        memory_mb=(SOLVER_PROCESS_MB + nlp_memory_mb(joints, free_variables, samples)
                   + screening_mb + RUN_MB * kept_runs),
        solves=runs,
        lower_it="fix more angles (option 1 or 2, or equal bounds pin a joint), use fewer "
                 "joints or fewer starts")


def check_multistart_memory(joints: int, free_variables: int, samples: int, starts: int,
                            solvers: int, screened: bool, limit_mb: Any = None) -> None:
    """``check_memory(multistart_estimate(...), limit_mb)``: refuse a multi-start run whose
    estimate exceeds the limit, with the same message.

    Under the default limit (``limit_mb`` None) a run that fits is known by its sizes and
    the environment variable's text, kept per such key (a single solve costs a few times
    what the full check does).

    Raises
    ------
    ValueError
        As :func:`check_memory`.
    """
    if limit_mb is None and _fits_default_limit(joints, free_variables, samples, starts, solvers,
                                                screened,
                                                os.environ.get(MEMORY_LIMIT_VARIABLE)):
        return
    check_memory(multistart_estimate(joints, free_variables, samples, starts, solvers, screened),
                 limit_mb)


@functools.lru_cache(maxsize=256)
def _fits_default_limit(joints: int, free_variables: int, samples: int, starts: int,
                        solvers: int, screened: bool, limit_text: str | None) -> bool:
    """Whether the multi-start estimate fits the limit that ``limit_text`` (the environment
    variable's value, None if unset) sets; False also where that text is no limit (the
    full check then says why)."""
    try:
        limit = _limit_of_text(limit_text)
    except ValueError:
        return False
    return multistart_estimate(joints, free_variables, samples, starts, solvers,
                               screened).memory_mb <= limit


def batch_estimate(starts: int, joints: int, free_variables: int) -> ResourceEstimate:
    """Memory and solves of :func:`sso.optimise_batch` on ``starts`` starts at once."""
    return ResourceEstimate(
        task=f"batch ({starts:,} starts of {joints} joints, {free_variables} free angles)",
        memory_mb=NUMPY_PROCESS_MB + batch_least_squares_mb(starts, free_variables),
        solves=starts,
        lower_it="fix more angles (option 1 or 2) or use fewer joints")
