"""Where batch work runs: in this process, or in a real spawned process pool.

Tasks are standard-library functions (importable in a spawned worker): ``math.sqrt``
has a known value and a known failure (ValueError for a negative number), and
``os.getenv`` / ``os.getpid`` show which process ran a task and with what environment.
"""

from __future__ import annotations

import math
import os

import pytest
from processes import alive

from sso._studies.execution import (
    WORKER_ENVIRONMENT,
    available_cores,
    run_tasks,
    validate_workers,
)


def test_validate_workers():
    assert validate_workers(None) == available_cores() >= 1
    assert validate_workers(3) == 3
    for bad in (0, 1025, 2.0, True, "4"):
        with pytest.raises(ValueError) as caught:
            validate_workers(bad)
        assert str(caught.value) == (
            f"workers = {bad!r} is outside the allowed range "
            "[1, 1024] (a whole number of local processes)"
        )


def test_one_worker_runs_here_and_reports_failures_in_order():
    results = list(run_tasks(math.sqrt, [4.0, -1.0, 2.25], workers=1))
    assert [(index, value) for index, value, _ in results] == [
        (0, 2.0),
        (1, None),
        (2, 1.5),
    ]
    assert isinstance(results[1][2], ValueError) and results[0][2] is None
    ((_, pid, _),) = run_tasks(lambda _: os.getpid(), [None], workers=1)
    assert pid == os.getpid()


def test_a_pool_runs_in_other_processes_with_one_blas_thread():
    names = [name for name in WORKER_ENVIRONMENT if name not in os.environ]
    results = sorted(run_tasks(os.getenv, [*names, "PATH"], workers=2), key=lambda r: r[0])
    assert [value for _, value, _ in results] == ["1"] * len(names) + [os.environ["PATH"]]
    assert all(name not in os.environ for name in names)  # the parent is left as it was
    pids = {value for _, value, _ in run_tasks(_pid_task, [0, 1, 2, 3], workers=2)}
    assert os.getpid() not in pids and 1 <= len(pids) <= 2


def _pid_task(_: int) -> int:
    return os.getpid()


def test_a_pool_reports_a_failing_task_and_finishes_the_others():
    results = sorted(run_tasks(math.sqrt, [9.0, -4.0, 16.0], workers=2), key=lambda r: r[0])
    assert [value for _, value, _ in results] == [3.0, None, 4.0]
    assert isinstance(results[1][2], ValueError)


def test_a_pool_is_kept_for_the_next_run_and_replaced_after_an_interruption():
    first = {pid for _, pid, _ in run_tasks(_pid_task, [0, 1, 2, 3], workers=2)}
    again = {pid for _, pid, _ in run_tasks(_pid_task, [0, 1, 2, 3], workers=2)}
    assert again <= first and all(alive(pid) for pid in first)  # the same, idle workers
    stopped = run_tasks(_pid_task, [0, 1, 2, 3], workers=2)
    next(stopped)
    stopped.close()  # the caller stops early: the workers are killed, not kept
    assert not any(alive(pid) for pid in first)
    after = {pid for _, pid, _ in run_tasks(_pid_task, [0, 1, 2, 3], workers=2)}
    assert not after & first
    other = {pid for _, pid, _ in run_tasks(_pid_task, [0, 1, 2, 3], workers=3)}
    assert not other & after  # another number of workers: another pool
