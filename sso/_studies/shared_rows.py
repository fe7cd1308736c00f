"""A sweep's number columns in memory that its local pool's workers write into (Linux).

Otherwise a pool worker pickles its chunk's rows and sends them through a pipe,
and the calling process, which every worker waits on, reads, unpickles and copies
them into the sweep's columns: three passes over every number in one process,
about as long as computing them. Instead the calling process makes the number
columns once, in an anonymous memory file (``memfd_create``), and each worker
opens it (``/proc/<caller>/fd/<fd>``) and writes its chunk's columns at their place;
only the text columns travel. The columns of the sweep's result are views of that
memory (the calling process maps it). A worker writes with ``pwrite``, a call a
column, rather than through a mapping of its own: the kernel fills the file's pages
as it copies, where a mapping's first write to each 4 KiB page is a page fault
(about 28,000 faults a run on the 1,000,000-point evaluate sweep, half the cost of
the workers' output). The file has no name: it is gone when the last process holding
it ends, so even a killed sweep leaves nothing behind.

A Dask worker on the same machine writes there too; one on another machine (no
such file there) and a system without such files (not Linux) send the chunk's
rows as before: :func:`write_rows` says whether it wrote them.
"""

from __future__ import annotations

import mmap
import os
import secrets
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from sso._studies.columns import RowTable

ALIGNMENT = 64
"""Each column starts at a multiple of this many bytes (a cache line)."""


@dataclass(frozen=True)
class SharedLayout:
    """Where each number column lies in the shared memory, as a worker finds it.

    Attributes
    ----------
    name : str
        The file's name, unique to it (a random token): a worker writes only into the
        file of this name, so one on another machine, where the process number
        may be another process's, writes nothing.
    caller_pid : int
        The process holding the memory file.
    descriptor : int
        Its file descriptor in that process.
    size : int
        The file's bytes.
    length : int
        Rows of every column.
    columns : tuple of (str, str, tuple of int, int)
        Per column: its name, dtype, shape of a row and byte offset.
    """

    name: str
    caller_pid: int
    descriptor: int
    size: int
    length: int
    columns: tuple[tuple[str, str, tuple[int, ...], int], ...]


class SharedColumns:
    """Number columns of ``length`` rows in an anonymous memory file (see the module).

    Parameters
    ----------
    kinds : mapping of str to (numpy.dtype, tuple of int)
        Each column's dtype and the shape of one row.
    length : int
        Rows.
    """

    def __init__(self, kinds: Mapping[str, tuple[np.dtype, tuple[int, ...]]],
                 length: int) -> None:
        placed = []
        offset = 0
        for name, (dtype, shape) in kinds.items():
            placed.append((name, np.dtype(dtype).str, tuple(shape), offset))
            size = np.dtype(dtype).itemsize * int(np.prod(shape, dtype=np.int64)) * length
            offset += -(-size // ALIGNMENT) * ALIGNMENT
        size = max(offset, 1)
        name = f"sso-sweep-rows-{secrets.token_hex(16)}"
        self._descriptor = os.memfd_create(name, os.MFD_CLOEXEC)
        try:
            os.ftruncate(self._descriptor, size)
            memory = mmap.mmap(self._descriptor, size)
        except OSError:
            self.close()
            raise
        self.layout = SharedLayout(name, os.getpid(), self._descriptor, size, length,
                                   tuple(placed))
        self.arrays = _views(memory, self.layout)
        """The columns (they keep the memory mapped while any of them lives)."""

    def close(self) -> None:
        """Close the file (the columns stay: the mapping holds the memory)."""
        if self._descriptor >= 0:
            os.close(self._descriptor)
            self._descriptor = -1


def shared_columns(kinds: Mapping[str, tuple[np.dtype, tuple[int, ...]]],
                   length: int) -> SharedColumns | None:
    """:class:`SharedColumns`, or None where the system has no anonymous memory file."""
    if not kinds or not hasattr(os, "memfd_create") or not os.path.isdir("/proc/self/fd"):
        return None
    try:
        return SharedColumns(kinds, length)
    except OSError:
        return None


def write_rows(layout: SharedLayout, start: int, table: RowTable) -> RowTable | None:
    """Write ``table``'s number columns into rows ``start ..`` of the shared columns.

    Returns
    -------
    RowTable or None
        The table without the columns written, or None (nothing written) if the
        table lacks one of the columns or holds one of another type or width, or the
        memory cannot be opened here.
    """
    expected = {name: (np.dtype(dtype), shape) for name, dtype, shape, _ in layout.columns}
    if start + table.length > layout.length or any(
            name not in table.columns or table.columns[name].dtype != dtype
            or table.columns[name].shape[1:] != shape
            for name, (dtype, shape) in expected.items()):
        return None
    path = f"/proc/{layout.caller_pid}/fd/{layout.descriptor}"
    try:
        if not _is_file(path, layout.name):  # not that file: look before opening
            return None
        with open(path, "r+b", buffering=0) as handle:
            if (not _is_file(f"/proc/self/fd/{handle.fileno()}", layout.name)
                    or os.fstat(handle.fileno()).st_size != layout.size):
                return None
            for name, dtype, shape, offset in layout.columns:
                row_bytes = np.dtype(dtype).itemsize * int(np.prod(shape, dtype=np.int64))
                _write_column(handle.fileno(), table.columns[name], offset + start * row_bytes)
    except OSError:
        return None
    return RowTable(table.header, {name: column for name, column in table.columns.items()
                                   if name not in expected}, table.length)


def _write_column(descriptor: int, column: np.ndarray, offset: int) -> None:
    """Write ``column``'s bytes at byte ``offset`` of the file."""
    data = np.ascontiguousarray(column).data.cast("B")
    while data:
        written = os.pwrite(descriptor, data, offset)
        data, offset = data[written:], offset + written


def _is_file(link: str, name: str) -> bool:
    """Whether ``link`` (a /proc file descriptor) is the anonymous memory file ``name``."""
    return os.readlink(link) == f"/memfd:{name} (deleted)"


def _views(memory: mmap.mmap, layout: SharedLayout) -> dict[str, np.ndarray]:
    return {name: _view(memory, layout.length, dtype, shape, offset)
            for name, dtype, shape, offset in layout.columns}


def _view(memory: mmap.mmap, length: int, dtype: str, shape: tuple[int, ...],
          offset: int) -> np.ndarray:
    width = int(np.prod(shape, dtype=np.int64))
    return np.frombuffer(memory, dtype=dtype, count=length * width,
                         offset=offset).reshape((length, *shape))
