"""Where batch work runs: this process, a local process pool, or a Dask cluster.

The executor is chosen by the caller and injected: dask is imported only on the
path that was given a Dask client (or a scheduler address to connect to).

A local pool never outlives its run: when the run is interrupted (Ctrl-C, or
SIGTERM, which the ``sso`` command turns into the same interruption) the workers
are killed rather than awaited, workers ignore SIGINT (the terminal sends it to
the whole process group; the parent decides), and on Linux each worker asks the
kernel to kill it when its parent dies, so even a SIGKILLed run leaves no worker
(and so no resource tracker, which exits once every process that could write to
it is gone).
"""

from __future__ import annotations

import multiprocessing
import os
import signal
import sys
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from contextlib import contextmanager
from typing import Any

# Thread counts of the numeric libraries in a worker process. One thread each, as
# Dask's nanny sets them: N busy processes with N BLAS threads each would fight
# over the cores, and multi-threaded OpenBLAS kernels round differently, so a
# pool worker and a Dask worker give the same bits only with the same setting.
WORKER_ENVIRONMENT = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1",
                      "MKL_NUM_THREADS": "1"}


def available_cores() -> int:
    """Cores this process may run on."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


def validate_workers(workers: Any) -> int:
    """Worker processes of the local pool: ``None`` means every available core.

    Raises
    ------
    ValueError
        If ``workers`` is not a whole number in ``[1, 1024]``.
    """
    if workers is None:
        return available_cores()
    if isinstance(workers, bool) or not isinstance(workers, int) or not 1 <= workers <= 1024:
        raise ValueError(f"workers = {workers!r} is outside the allowed range [1, 1024] "
                         "(a whole number of local processes)")
    return workers


def run_tasks(
    function: Callable[[Any], Any],
    tasks: Sequence[Any],
    client: Any = None,
    workers: int = 1,
) -> Iterator[tuple[int, Any, BaseException | None]]:
    """Run ``function`` on every task, yielding ``(task index, result, error)`` as each ends.

    Parameters
    ----------
    function : callable
        A top-level (importable, picklable) function of one task.
    tasks : sequence
        Picklable task descriptions.
    client : dask.distributed.Client, optional
        Run on this Dask cluster instead of locally.
    workers : int
        Local processes; with 1, or a single task, the work runs in this process
        (with this process's BLAS threads, so last-bit rounding may differ from
        the pool's and Dask's single-threaded workers).

    Yields
    ------
    (int, object, BaseException or None)
        The task's index, its result (None if it raised), and the exception it
        raised (None if it succeeded).
    """
    if client is not None:
        yield from _run_on_dask(function, tasks, client)
    elif workers == 1 or len(tasks) <= 1:
        for index, task in enumerate(tasks):
            try:
                yield index, function(task), None
            except Exception as error:  # noqa: BLE001 - reported to the caller
                yield index, None, error
    else:
        yield from _run_in_pool(function, tasks, workers)


def connect(address: str) -> Any:
    """A ``dask.distributed.Client`` connected to the scheduler at ``address``.

    Raises
    ------
    ValueError
        If dask.distributed is not installed or the scheduler cannot be reached.
    """
    try:
        from distributed import Client
    except ImportError:
        raise ValueError("scheduler: dask.distributed is not installed; install the "
                         "'dask' extra (pip install 'sso[dask]')") from None
    try:
        # distributed's Client has no annotations
        return Client(address, timeout="10s")  # type: ignore[no-untyped-call]
    except (OSError, TimeoutError) as error:
        raise ValueError(f"scheduler = {address!r} cannot be reached: {error}") from None


def _run_in_pool(function: Callable[[Any], Any], tasks: Sequence[Any],
                 workers: int) -> Iterator[tuple[int, Any, BaseException | None]]:
    # spawn: a fresh interpreter per worker, the same on every platform, and safe
    # with the threads CasADi and BLAS may have started in this process.
    executor = ProcessPoolExecutor(max_workers=min(workers, len(tasks)),
                                   mp_context=multiprocessing.get_context("spawn"),
                                   initializer=_start_worker, initargs=(os.getpid(),))
    finished = False
    try:
        # The workers start while the first tasks are submitted, and inherit this
        # environment from that moment.
        with _environment(WORKER_ENVIRONMENT):
            futures = {executor.submit(function, task): index
                       for index, task in enumerate(tasks)}
        for future in as_completed(futures):
            error = future.exception()
            yield futures[future], None if error else future.result(), error
        finished = True
    finally:
        if not finished:  # interrupted, or the caller stopped early: do not wait for work
            _kill_workers(executor)
        executor.shutdown(wait=True, cancel_futures=True)


def _start_worker(parent_pid: int) -> None:
    """Initializer of a pool worker: leave SIGINT to the parent, die with the parent."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        import ctypes

        pr_set_pdeathsig = 1
        ctypes.CDLL(None, use_errno=True).prctl(pr_set_pdeathsig, signal.SIGKILL)
    if os.getppid() != parent_pid:  # the parent died before the request took effect
        os._exit(1)


def _kill_workers(executor: ProcessPoolExecutor) -> None:
    """Kill the pool's worker processes and wait for them (at most a few seconds)."""
    # The pool keeps its processes in a private mapping; there is no public way to
    # stop running tasks.
    workers = list((getattr(executor, "_processes", None) or {}).values())
    for worker in workers:
        if worker.is_alive():
            worker.kill()
    for worker in workers:
        worker.join(timeout=5)


@contextmanager
def _environment(values: dict[str, str]) -> Iterator[None]:
    """Set environment variables the user has not set, for the duration of the block."""
    added = {name: value for name, value in values.items() if name not in os.environ}
    os.environ.update(added)
    try:
        yield
    finally:
        for name in added:
            os.environ.pop(name, None)


def _run_on_dask(function: Callable[[Any], Any], tasks: Sequence[Any],
                 client: Any) -> Iterator[tuple[int, Any, BaseException | None]]:
    from distributed import as_completed as dask_as_completed

    futures = [client.submit(function, task, pure=False) for task in tasks]
    indices = {future.key: index for index, future in enumerate(futures)}
    try:
        # distributed's as_completed has no annotations
        for future in dask_as_completed(futures):  # type: ignore[no-untyped-call]
            index = indices[future.key]
            if future.status == "finished":
                yield index, future.result(), None
            else:
                yield index, None, future.exception()
    finally:
        client.cancel([future for future in futures if not future.done()])
