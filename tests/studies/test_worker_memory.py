"""Workers keep the memory their tasks free (sso._studies.worker_memory).

Real processes and the real allocator: a task allocates and frees 40 arrays of 0.4
to 1.2 MB (32 MB, as a chunk of an array sweep does) a few times, then counts the
page faults (``getrusage``) of doing it again. An allocator that gave the memory
back takes every page again (one fault a 4 KiB page, about 7,800 here, measured in
a fresh interpreter with glibc's defaults: the control below); one that kept it
takes none.
"""

from __future__ import annotations

import multiprocessing
import resource
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

from sso._studies.execution import run_tasks
from sso._studies.worker_memory import glibc_allocator

ARRAYS = 40
POINTS = 50_000
PAGES = sum(POINTS * (1 + index % 3) * 8 for index in range(ARRAYS)) // 4096
"""Pages the arrays take: 7,812."""

pytestmark = pytest.mark.skipif(not glibc_allocator(), reason="the allocator set is glibc's")


def faults_of_a_chunk_again(_: object = None) -> int:
    """Page faults of allocating and freeing the arrays once more, after three times."""

    def chunk() -> float:
        arrays = [np.ones(POINTS * (1 + index % 3)) for index in range(ARRAYS)]
        return sum(float(array[0]) for array in arrays)

    for _ in range(3):
        chunk()
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    chunk()
    return resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before


def test_a_fresh_process_with_the_default_allocator_takes_the_pages_again():
    # The control: without keep_freed_memory every page is taken again.
    with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn")) as pool:
        assert pool.submit(faults_of_a_chunk_again).result() > PAGES // 2


def test_a_pool_worker_keeps_what_its_tasks_free():
    faults = [value for _, value, _ in run_tasks(faults_of_a_chunk_again, [0, 1], workers=2)]
    assert len(faults) == 2 and max(faults) < PAGES // 100
