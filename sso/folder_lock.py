"""One writer per output folder: a lock file beside the folder, holding its owner's pid.

The lock is the kernel's (``flock``) on the file ``.sso-lock-<folder name>`` in the
folder's parent. It lives beside the folder because a report folder is replaced
whole (a new folder renamed into its place), which would take a lock inside it
along. The kernel releases the lock when its owner ends, however it ends, so a lock
file a killed run left behind is stale by construction: the next run takes it over,
with no guess from a pid that the system may have given to another process since.
The pid in the file only names the owner in the message of a refused run.

A holder removes the file when it lets go; a process that opened the file just
before that finds, once it holds the lock, that the path names another file (or
none) and starts again, so two processes never both hold a folder.
"""

from __future__ import annotations

import errno
import fcntl
import os
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

LOCK_PREFIX = ".sso-lock-"


class FolderInUseError(BlockingIOError):
    """The folder is being written by another process (or thread)."""


# Lock file -> (owning thread, nesting depth, descriptor) of the locks this process holds.
_HELD: dict[Path, tuple[int, int, int]] = {}
_HELD_GUARD = threading.Lock()


def lock_path(folder: str | os.PathLike[str]) -> Path:
    """The lock file of ``folder``: ``.sso-lock-<name>`` beside it.

    Two spellings of one folder (relative, absolute, through a symbolic link) name
    one lock file.
    """
    resolved = Path(os.path.realpath(folder))
    return resolved.parent / f"{LOCK_PREFIX}{resolved.name}"


@contextmanager
def folder_locked(folder: str | os.PathLike[str]) -> Iterator[None]:
    """Hold the lock of ``folder`` for the block, or refuse at once.

    The lock is re-entrant within one thread (a run that holds its folder may call
    :func:`sso.files.replace_folder`, which takes it again). The folder's parent
    must exist.

    Raises
    ------
    FolderInUseError
        If another process, or another thread of this one, holds the lock; the
        message names the folder and the owner's pid.
    OSError
        If the lock file cannot be created (the parent is missing or read-only).
    """
    path = lock_path(folder)
    me = threading.get_ident()
    with _HELD_GUARD:
        held = _HELD.get(path)
        if held is not None and held[0] == me:
            _HELD[path] = (me, held[1] + 1, held[2])
            nested = True
        else:
            nested = False
    if nested:
        try:
            yield
        finally:
            with _HELD_GUARD:
                owner, depth, descriptor = _HELD[path]
                _HELD[path] = (owner, depth - 1, descriptor)
        return
    if held is not None:
        raise FolderInUseError(_in_use(folder, str(os.getpid())))
    descriptor = _acquire(path, folder)
    with _HELD_GUARD:
        _HELD[path] = (me, 1, descriptor)
    try:
        yield
    finally:
        with _HELD_GUARD:
            del _HELD[path]
        path.unlink(missing_ok=True)  # still holding it: nobody else can be using the file
        os.close(descriptor)


def _acquire(path: Path, folder: str | os.PathLike[str]) -> int:
    """A descriptor of ``path`` with its lock held and this process's pid written in."""
    while True:
        descriptor = os.open(path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
        try:
            fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError as error:
            owner = _read_owner(descriptor)
            os.close(descriptor)
            if error.errno in (errno.EWOULDBLOCK, errno.EAGAIN):
                raise FolderInUseError(_in_use(folder, owner)) from None
            raise
        try:
            current = os.stat(path).st_ino
        except FileNotFoundError:
            current = None
        if current != os.fstat(descriptor).st_ino:  # its holder removed it meanwhile
            os.close(descriptor)
            continue
        os.ftruncate(descriptor, 0)
        os.pwrite(descriptor, f"{os.getpid()}\n".encode("ascii"), 0)
        return descriptor


def _read_owner(descriptor: int) -> str:
    try:
        text = os.pread(descriptor, 32, 0).decode("ascii", "replace").strip()
    except OSError:
        return ""
    return text if text.isdigit() else ""


def _in_use(folder: str | os.PathLike[str], owner: str) -> str:
    by = f"sso process {owner}" if owner else "another sso process"
    return (f"{os.fspath(folder)} is being written by {by} (its lock is "
            f"{lock_path(folder).name} beside it); wait until that run ends, or choose "
            "another folder")
