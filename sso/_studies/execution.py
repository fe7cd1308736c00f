"""Where batch work runs: this process, a local process pool, or a Dask cluster.

The executor is chosen by the caller and injected: dask is imported only on the
path that was given a Dask client (or a scheduler address to connect to).

A local pool's workers are forked from a fork server (POSIX): one fresh,
single-threaded interpreter per calling process, started with the first pool and
holding the sweep worker's modules (numpy and sso) already imported, so a pool
starts in milliseconds instead of an interpreter and its imports per worker (about
a second of CPU each); elsewhere the workers are spawned. The fork server lives as
long as the calling process and exits with it.

A local pool that ends its run normally is kept, idle, for the next run of the
same process with the same workers and environment (a notebook running sweep after
sweep starts its workers once). When a run is interrupted (Ctrl-C, or
SIGTERM, which the ``sso`` command turns into the same interruption) its workers
are killed rather than awaited, workers ignore SIGINT (the terminal sends it to
the whole process group; the parent decides), and each worker ends with its
caller: a forked worker watches the caller and exits the moment it is gone (a
spawned one asks the kernel to kill it when its parent dies, on Linux), so even a
SIGKILLed run leaves no worker (the fork server exits once its caller and its
workers are gone, and the resource tracker once every process that could write to
it is gone).
"""

from __future__ import annotations

import ctypes
import logging
import math
import multiprocessing
import os
import select
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from contextlib import contextmanager
from functools import partial
from typing import Any

from sso._limits import NO_WORKER_TIMEOUT_S, NO_WORKER_TIMEOUT_VARIABLE
from sso._studies.dask_handshake import check_dask_scheduler
from sso._studies.worker_memory import keep_freed_memory

# Thread counts of the numeric libraries in a worker process. One thread each, as
# Dask's nanny sets them: N busy processes with N BLAS threads each would fight
# over the cores, and multi-threaded OpenBLAS kernels round differently, so a
# pool worker and a Dask worker give the same bits only with the same setting.
DASK_POLL_S = 1.0
"""How often a Dask run checks that its cluster still has a worker, s."""
DASK_IDLE_S = 0.02
"""Longest wait for a Dask task to end between looks at the cluster's workers, s."""
CALLER_POLL_S = 0.2
"""How often a forked pool worker looks for its caller where it cannot wait for it, s."""
MAX_NO_WORKER_TIMEOUT_S = 1e6

WORKER_ENVIRONMENT = {"OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1",
                      "MKL_NUM_THREADS": "1"}
WORKER_PRELOAD = ["sso._studies.worker", "sso._studies.parquet_output", "sso._cases.schema",
                  "sso._cases.shaft_series", "numpy.ma"]
"""Modules the fork server imports once, so no pool worker imports them again: a
sweep's worker, its output, the case reader that checks a sweep's axis values, and
the part of numpy that ``numpy.unique`` imports on its first call."""


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
    elif not runs_in_pool(client, workers, len(tasks)):
        for index, task in enumerate(tasks):
            try:
                yield index, function(task), None
            except Exception as error:  # noqa: BLE001 - reported to the caller
                yield index, None, error
    else:
        yield from _run_in_pool(function, tasks, workers)


def parallelism(client: Any, workers: int) -> int:
    """Tasks that can run at once: the Dask cluster's threads, or the local workers."""
    if client is None:
        return workers
    threads: int = sum(client.nthreads().values())
    return max(1, threads)


def runs_in_pool(client: Any, workers: int, tasks: int) -> bool:
    """Whether :func:`run_tasks` runs ``tasks`` tasks in a local pool (not on Dask,
    not in this process)."""
    return client is None and workers > 1 and tasks > 1


def connect(address: str) -> Any:
    """A ``dask.distributed.Client`` connected to the scheduler at ``address``.

    A ``tcp://`` address is first checked to be a Dask scheduler from the first
    bytes it sends (:func:`sso._studies.dask_handshake.check_dask_scheduler`), so
    that a service that is not Dask ends in a clear error, not in distributed's
    reading of its bytes.

    Raises
    ------
    ValueError
        If dask.distributed is not installed, the scheduler cannot be reached, or
        the address is not a Dask scheduler's.
    """
    try:
        from distributed import Client
    except ImportError:
        raise ValueError("scheduler: dask.distributed is not installed; install the "
                         "'dask' extra (pip install 'sso[dask]')") from None
    check_dask_scheduler(address)
    try:
        # distributed's Client has no annotations
        return Client(address, timeout="10s")  # type: ignore[no-untyped-call]
    except (OSError, TimeoutError) as error:
        raise ValueError(f"scheduler = {address!r} cannot be reached: {error}") from None


def pool_context() -> Any:
    """The multiprocessing context of local pools: a fork server where there is one.

    Never plain fork: this process may run threads (CasADi's, BLAS's) that a fork
    would copy in the middle of their work. The fork server is a fresh interpreter
    that runs no thread; it imports :data:`WORKER_PRELOAD` once.
    """
    if "forkserver" not in multiprocessing.get_all_start_methods():
        return multiprocessing.get_context("spawn")
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload(WORKER_PRELOAD)
    return context


def _run_in_pool(function: Callable[[Any], Any], tasks: Sequence[Any],
                 workers: int) -> Iterator[tuple[int, Any, BaseException | None]]:
    key, executor = _take_pool(workers)
    finished = False
    try:
        with _environment(WORKER_ENVIRONMENT):
            futures = {executor.submit(function, task): index
                       for index, task in enumerate(tasks)}
        for future in as_completed(futures):
            error = future.exception()
            yield futures[future], None if error else future.result(), error
        finished = True
    finally:
        # The pool's private flag: a worker was lost, the pool takes no more work.
        if finished and not getattr(executor, "_broken", False):
            _keep_pool(key, executor)
        else:  # interrupted, stopped early or broken: do not wait for work
            _kill_workers(executor)
            executor.shutdown(wait=True, cancel_futures=True)


_IDLE_POOL: dict[tuple[Any, ...], ProcessPoolExecutor] = {}
"""The local pool of the last run that ended normally, idle, kept for the next run
of this process that asks for the same (at most one)."""


def _take_pool(workers: int) -> tuple[tuple[Any, ...], ProcessPoolExecutor]:
    """A pool of ``workers`` processes with this process's environment of now, for one
    run: the idle pool, if it is such a pool, else a new one.

    A pool kept between runs holds idle workers (each waiting for a task, and each
    ending with this process), so a process running sweep after sweep starts its
    workers once, and they keep the solvers they built.
    """
    context = pool_context()
    with _environment(WORKER_ENVIRONMENT):
        environment = dict(os.environ)
    key = (os.getpid(), workers, context.get_start_method(),
           tuple(sorted(environment.items())))
    if key in _IDLE_POOL:
        return key, _IDLE_POOL.pop(key)
    # The workers (and the fork server, when the first pool starts it) start while
    # the first tasks are submitted; each takes this process's environment of now.
    with _environment(WORKER_ENVIRONMENT):
        return key, ProcessPoolExecutor(
            max_workers=workers, mp_context=context, initializer=_start_worker,
            initargs=(os.getpid(), context.get_start_method() == "spawn", environment))


def _keep_pool(key: tuple[Any, ...], executor: ProcessPoolExecutor) -> None:
    """Keep ``executor`` idle for the next run (shutting down the pool kept before)."""
    for earlier in _IDLE_POOL.values():
        earlier.shutdown(wait=True)
    _IDLE_POOL.clear()
    _IDLE_POOL[key] = executor


def _start_worker(caller_pid: int, spawned: bool, environment: dict[str, str]) -> None:
    """Initializer of a pool worker: the caller's environment; leave SIGINT to the
    caller; die with the caller; keep the memory its tasks free
    (:func:`sso._studies.worker_memory.keep_freed_memory`).

    A spawned worker is the caller's child: the kernel kills it when its parent
    dies. A forked worker is the fork server's child, and the fork server lives as
    long as any of its children does, so the worker watches the caller itself
    (:func:`_exit_with`). A forked worker keeps the fork server's numeric
    libraries, loaded with one thread each.
    """
    os.environ.clear()
    os.environ.update(environment)
    keep_freed_memory()
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    parent = os.getppid()
    if sys.platform.startswith("linux"):
        pr_set_pdeathsig = 1
        ctypes.CDLL(None, use_errno=True).prctl(pr_set_pdeathsig, signal.SIGKILL)
    if os.getppid() != (caller_pid if spawned else parent):  # died before the request
        os._exit(1)
    if not spawned:
        _exit_with(caller_pid)


def _exit_with(caller_pid: int) -> None:
    """End this process as soon as process ``caller_pid`` ends (a watching thread)."""
    def wait_for_exit() -> None:
        try:
            descriptor = os.pidfd_open(caller_pid)
        except (AttributeError, OSError) as error:  # no pidfd here: look every 0.2 s
            if isinstance(error, ProcessLookupError):
                os._exit(1)
            while _running(caller_pid):
                time.sleep(CALLER_POLL_S)
        else:
            select.select([descriptor], [], [])  # readable once the process has ended
        os._exit(1)

    threading.Thread(target=wait_for_exit, name="sso-caller-watch", daemon=True).start()


def _running(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


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


class NoWorkersError(RuntimeError):
    """The Dask cluster had no worker for longer than the set time."""


def no_worker_timeout_s() -> float:
    """:data:`sso._limits.NO_WORKER_TIMEOUT_S`, or the environment's replacement.

    Raises
    ------
    ValueError
        If the environment variable is not a number in ``(0, 1e6]``.
    """
    text = os.environ.get(NO_WORKER_TIMEOUT_VARIABLE)
    if text is None:
        return NO_WORKER_TIMEOUT_S
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not 0.0 < value <= MAX_NO_WORKER_TIMEOUT_S:
        raise ValueError(f"{NO_WORKER_TIMEOUT_VARIABLE} = {text!r} is outside the allowed "
                         f"range (0, {MAX_NO_WORKER_TIMEOUT_S:g}] s")
    return value


def _quiet_lost_gathers() -> None:
    """Drop asyncio's report of a gather that distributed gave up when its tasks were
    cancelled (``AllExit``, "Task exception was never retrieved"): a result lost with
    its worker and then cancelled, as a run without workers ends. It is no error of
    the run, and the user would read it as a crash."""
    class _LostGathers(logging.Filter):
        def filter(self, record: logging.LogRecord) -> bool:
            error = record.exc_info[1] if record.exc_info else None
            return type(error).__name__ != "AllExit"

    logger = logging.getLogger("asyncio")
    if not any(isinstance(item, logging.Filter) and type(item).__name__ == "_LostGathers"
               for item in logger.filters):
        logger.addFilter(_LostGathers())


def _in_dask_worker(function: Callable[[Any], Any], task: Any) -> Any:
    """``function(task)`` in a Dask worker that keeps the memory its tasks free
    (:func:`sso._studies.worker_memory.keep_freed_memory`)."""
    keep_freed_memory()
    return function(task)


def _run_on_dask(function: Callable[[Any], Any], tasks: Sequence[Any],
                 client: Any) -> Iterator[tuple[int, Any, BaseException | None]]:
    from distributed import as_completed as dask_as_completed

    limit_s = no_worker_timeout_s()
    _quiet_lost_gathers()
    # One graph: cheaper than a submit each.
    futures = client.map(partial(_in_dask_worker, function), tasks, pure=False)
    indices = {future.key: index for index, future in enumerate(futures)}
    # Each result is fetched by distributed's event loop as its task ends, not by a
    # call of this thread that waits for the fetch (a round trip each: about half of
    # what a task costs this process). An error arrives as (type, error, traceback).
    # distributed's as_completed has no annotations
    completed: Any = dask_as_completed(  # type: ignore[no-untyped-call]
        futures, with_results=True, raise_errors=False)
    checked = alone_since = None
    try:
        while not completed.is_empty():
            batch = completed.next_batch(block=False)
            for future, result in batch:
                index = indices[future.key]
                if future.status == "error":
                    yield index, None, result[1]
                elif future.status == "finished":
                    yield index, result, None
                else:  # lost with its worker: computed again
                    completed.add(future)  # waited for again
            now = time.monotonic()
            if batch:
                alone_since = None
            elif checked is None or now - checked >= DASK_POLL_S:
                checked = now
                if client.scheduler_info().get("workers"):
                    alone_since = None
                elif alone_since is None:
                    alone_since = now
                elif now - alone_since > limit_s:
                    raise NoWorkersError(
                        f"the Dask scheduler at {client.scheduler.address} has had no worker "
                        f"for {limit_s:g} s ({completed.count()} of {len(futures)} tasks not "
                        "done); start workers for it (dask worker ADDRESS) and run the same "
                        f"command with --resume (wait longer: {NO_WORKER_TIMEOUT_VARIABLE}"
                        "=SECONDS)")
            else:  # wait for the next task to end (as_completed notifies its condition)
                with completed.thread_condition:
                    if not completed.has_ready():
                        completed.thread_condition.wait(timeout=DASK_IDLE_S)
    finally:
        completed.clear()
        client.cancel([future for future in futures if not future.done()])
