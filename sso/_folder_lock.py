"""One writer per output folder: a lock file beside the folder, holding its owner's pid.

The lock is an advisory ``flock`` on ``<parent>/.sso-lock-<folder name>``, taken
without waiting. The kernel drops it when its owner ends, however it ends
(SIGKILL included), so a lock file left by a dead process is stale by
construction: the next writer takes the lock and writes its own pid over the old
one; no pid is ever guessed alive or dead. The file lies beside the folder, not
inside it, so a writer may replace the whole folder (:func:`sso._files.replace_folder`)
while it holds the lock.

The lock file is removed when its owner releases the lock. A second writer may
have opened the old file just before; it then holds a lock on a file that no
longer has the name, sees that the name now points elsewhere (or nowhere) and
tries again, so two writers never both believe they hold the folder.
"""

from __future__ import annotations

import fcntl
import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from sso._files import make_folders

LOCK_PREFIX = ".sso-lock-"
ATTEMPTS = 20


class FolderLockedError(ValueError):
    """Another live process writes into the folder (its pid is in the message)."""


def lock_path(folder: str | os.PathLike[str]) -> Path:
    """The lock file of ``folder``: beside it, named after it."""
    target = Path(folder)
    return target.parent / f"{LOCK_PREFIX}{target.name}"


@contextmanager
def folder_lock(folder: str | os.PathLike[str], purpose: str = "write") -> Iterator[Path]:
    """Hold the lock of ``folder`` for the block; its parent folder is created if missing.

    Parameters
    ----------
    folder : path-like
        The output folder (it need not exist yet).
    purpose : str
        What the lock is for, in words, for the message a second writer gets.

    Yields
    ------
    pathlib.Path
        The lock file.

    Raises
    ------
    FolderLockedError
        If a live process holds the lock (the message names its pid).
    OSError
        If the lock file cannot be created.
    """
    path = lock_path(folder)
    make_folders(path.parent)  # level by level: an --out of thousands of parts is no recursion
    for _ in range(ATTEMPTS):
        descriptor = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(descriptor, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            owner = _owner(descriptor)
            os.close(descriptor)
            raise FolderLockedError(
                f"{folder} is in use: process {owner} holds its lock {path.name} to "
                f"{purpose} there; wait for it to end, or choose another folder") from None
        if _names_this_file(path, descriptor):
            break
        os.close(descriptor)  # the owner before us removed the file: take the new one
    else:
        raise FolderLockedError(f"{folder}: its lock {path.name} kept changing hands; try again")
    try:
        os.ftruncate(descriptor, 0)
        os.write(descriptor, f"{os.getpid()}\n".encode("ascii"))
        yield path
    finally:
        # Unlink before unlocking: a writer waiting on this file then finds it nameless.
        if _names_this_file(path, descriptor):
            path.unlink(missing_ok=True)
        os.close(descriptor)


def _names_this_file(path: Path, descriptor: int) -> bool:
    """Whether ``path`` still names the file open at ``descriptor``."""
    try:
        named = os.stat(path)
    except FileNotFoundError:
        return False
    opened = os.fstat(descriptor)
    return (named.st_dev, named.st_ino) == (opened.st_dev, opened.st_ino)


def _owner(descriptor: int) -> str:
    """The pid the lock's owner wrote into the file, or words saying it is unknown."""
    text = os.pread(descriptor, 32, 0).decode("ascii", "replace").strip()
    return text if text.isdigit() else "(pid not yet written)"
