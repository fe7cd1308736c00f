"""A worker process's allocator set to keep the memory its chunks free (glibc).

A chunk of an array sweep allocates its arrays afresh (tens of MB at 50,000 points)
and frees them when it ends. glibc's ``malloc`` gives memory above a threshold back
to the kernel as soon as it is freed (arrays above ``M_MMAP_THRESHOLD`` are mapped
and unmapped one by one; a free top of the heap above ``M_TRIM_THRESHOLD`` is
trimmed), so the next chunk takes it again, one page fault and one zeroed page per
4 KiB: measured on the 1,000,000-point evaluate sweep, about 127,000 page faults a
run in the two pool workers, against about 13,500 in one process whose long-lived
heap happens to hold the memory, and the workers' compute per point 45% above that
of one process. Dask's nanny makes it worse on purpose (it starts its workers with
``MALLOC_TRIM_THRESHOLD_=65536``, to give memory back early).

A worker therefore keeps what it frees, up to :data:`KEPT_FREE_BYTES` (more than a
chunk's peak): :func:`keep_freed_memory`, called once in each pool worker and in
each Dask worker before its first sweep task. The calling process's allocator is
left as it is. Elsewhere than glibc nothing is changed.
"""

from __future__ import annotations

import ctypes
import os

M_TRIM_THRESHOLD = -1
M_MMAP_THRESHOLD = -3
"""``mallopt`` parameters (glibc's ``malloc.h``)."""
MAPPED_ABOVE_BYTES = 32 * 2**20
"""Allocations above this are mapped apart and unmapped when freed (glibc's largest
setting): a chunk's arrays, at most a few MB each, stay on the heap."""
KEPT_FREE_BYTES = 64 * 2**20
"""Free memory at the top of the heap kept rather than given back: above a chunk's
peak (measured with tracemalloc on three joints: 38 MB optimising 50,000 points,
17 MB evaluating 50,000, 35 MB evaluating the 100,000 of a Dask task)."""

_kept = False


def keep_freed_memory() -> bool:
    """Set this process's allocator to keep freed memory (see the module); once.

    Returns
    -------
    bool
        Whether the allocator is so set (False where it is not glibc's).
    """
    global _kept
    if _kept:
        return True
    if not glibc_allocator():
        return False
    try:
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError):
        return False
    mallopt.argtypes = [ctypes.c_int, ctypes.c_int]
    mallopt.restype = ctypes.c_int
    _kept = bool(mallopt(M_MMAP_THRESHOLD, MAPPED_ABOVE_BYTES)
                 and mallopt(M_TRIM_THRESHOLD, KEPT_FREE_BYTES))
    return _kept


def glibc_allocator() -> bool:
    """Whether this process's C library (and so its ``malloc``) is glibc."""
    try:
        return (os.confstr("CS_GNU_LIBC_VERSION") or "").startswith("glibc")
    except (ValueError, OSError):  # no such name on this system: not glibc
        return False
