"""Memory and solves of a tolerance study or a sweep, estimated before it starts.

The figures come from the arrays each one holds (counted below) and from
measurements where Python objects dominate (a sweep's rows); :func:`check_memory`
of :mod:`sso._resources` then refuses work above the memory limit.
"""

from __future__ import annotations

from sso._limits import DEFAULT_CHUNK_SAMPLES
from sso._resources import (
    BLOCK_ARRAYS,
    FLOAT_BYTES,
    MB,
    ResourceEstimate,
    block_samples,
    nlp_memory_mb,
)

# Arrays of shape (samples, angles) a tolerance study holds at once in the calling
# process: the sampled angles in deg and in rad. Its table is formatted and written
# 10,000 rows at a time (sso._studies.report.TABLE_ROWS) and its record holds no
# samples, so neither grows with the samples.
TOLERANCE_ARRAYS = 2
# The process itself before it draws a sample: Python, numpy, sso and matplotlib for the
# histogram. `sso tolerance` of 10,000 samples peaked at 89 MB, of 1,000,000 at 179 MB
# (the exact model; getrusage of the process, 2 Dec 2026): 80 MB and 91 bytes a sample.
PROCESS_MB = 80.0
# A sweep point held by the calling process: the point (0.2 KB, measured with
# tracemalloc for two axes), its formatted CSV row (1.5 KB for 29 columns, measured)
# and its typed row in the result (about as much again), rounded up.
SWEEP_BYTES_PER_POINT = 4096
# A point of an array sweep (sso._studies.array_engine), held as columns: 200 bytes
# optimising three joints and 136 evaluating (tests/docs/test_scaling_page.py), about
# 530 and 320 at the peak (a chunk's arrays and CSV text on top, measured with
# tracemalloc on sweeps of 8,000 and 27,000 points); rounded up.
ARRAY_SWEEP_BYTES_PER_POINT = 1024
# A point of a chunk being computed (sso._studies.array_engine) with its CSV text: 1.3 KB
# evaluating and 1.8 KB optimising at the peak, measured with tracemalloc on chunks of
# 50,000 points of three joints; rounded up. Each worker holds one chunk at a time.
ARRAY_CHUNK_BYTES_PER_POINT = 2048


def tolerance_estimate(samples: int, joints: int, figure_samples: int,
                       workers: int, chunk_size: int = DEFAULT_CHUNK_SAMPLES) -> ResourceEstimate:
    """Memory (of the whole process) and evaluations of a tolerance study of ``samples``
    samples.

    Parameters
    ----------
    samples, joints : int
        Samples drawn and joints of the design.
    figure_samples : int
        Input angles per revolution each sample is evaluated at.
    workers : int
        Processes evaluating blocks at once.
    chunk_size : int
        Samples per task; a task evaluates at most one block of them at a time.
    """
    angles = 2 * joints - 1
    held = samples * (TOLERANCE_ARRAYS * angles * FLOAT_BYTES + 3 * FLOAT_BYTES)
    block = min(samples, chunk_size, block_samples(figure_samples))
    evaluating = workers * BLOCK_ARRAYS * FLOAT_BYTES * block * figure_samples
    per_sample = held / samples
    return ResourceEstimate(
        task=f"tolerance study ({samples:,} samples of {joints} joints)",
        memory_mb=PROCESS_MB + (held + evaluating) / MB,
        solves=samples,
        lower_it=f"lower samples (each needs about {per_sample / 1024:.1f} KB)")


def sweep_estimate(points: int, joints: int, free_variables: int, samples: int,
                   solves_per_point: int, workers: int, optimising: bool,
                   arrays: bool = False, chunk_points: int = 0) -> ResourceEstimate:
    """Memory and solves of a sweep of ``points`` points over a shaft-series case.

    Each optimising worker builds the base case's NLP (``joints`` joints,
    ``free_variables`` free angles, ``samples`` quadrature angles), unless the
    sweep runs as arrays (``arrays``), which builds none; a worker of an array
    sweep holds one chunk of ``chunk_points`` points at a time.
    """
    worker_mb = (nlp_memory_mb(joints, free_variables, samples) if optimising and not arrays
                 else 0.0)
    if arrays:
        worker_mb += chunk_points * ARRAY_CHUNK_BYTES_PER_POINT / MB
    per_point = ARRAY_SWEEP_BYTES_PER_POINT if arrays else SWEEP_BYTES_PER_POINT
    return ResourceEstimate(
        task=f"sweep ({points:,} points)",
        memory_mb=points * per_point / MB + workers * worker_mb,
        solves=points * solves_per_point,
        lower_it=f"use fewer points (each needs about {per_point / 1024:g} KB) or "
                 "split the sweep into several sweep files")
