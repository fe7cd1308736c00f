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

The lock file is opened without following a symbolic link (``O_NOFOLLOW``), and
only a regular file with one name whose contents are a pid (or nothing) is taken
for a lock: a link or any other file under the lock's name, which another user of a
shared folder may have put there to aim sso at a file of theirs or a victim's, is
refused and left unchanged.
"""

from __future__ import annotations

import fcntl
import os
import stat
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from sso._files import make_folders

LOCK_PREFIX = ".sso-lock-"
ATTEMPTS = 20
_LARGEST_LOCK_BYTES = 32  # a pid and its newline
_OPEN_FLAGS = os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_NOCTTY | os.O_CLOEXEC


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
        If a live process holds the lock (the message names its pid), or the lock's
        name is taken by something that is not a lock file sso made (a symbolic
        link, a folder, a file with other contents or a second name): it is left
        unchanged; or if the lock file cannot be opened (the system's reason).
    ValueError
        If a level of the lock file's folder is a file or a link leading nowhere.
    OSError
        If the lock file's folder cannot be created.
    """
    path = lock_path(folder)
    make_folders(path.parent)  # level by level: an --out of thousands of parts is no recursion
    for _ in range(ATTEMPTS):
        descriptor = _open_lock_file(path, folder)
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


def _open_lock_file(path: Path, folder: str | os.PathLike[str]) -> int:
    """A descriptor of the lock file ``path`` (created if missing), if it is one sso made.

    Raises
    ------
    FolderLockedError
        Naming what is there instead; nothing is written.
    """
    refused = (f"the lock file {path} of {folder} is {{what}}, not a lock file sso made; "
               "sso writes nothing through it. Remove it if it is not needed, or choose "
               "another folder")
    try:
        descriptor = os.open(path, _OPEN_FLAGS, 0o644)
    except OSError as error:
        if os.path.islink(path):
            raise FolderLockedError(refused.format(
                what=f"a symbolic link (to {os.readlink(path)})")) from None
        if os.path.isdir(path):
            raise FolderLockedError(refused.format(what="a folder")) from None
        raise FolderLockedError(f"{folder}: cannot open its lock file {path}: "
                                f"{error.strerror or error}") from None
    status = os.fstat(descriptor)
    what = None
    if not stat.S_ISREG(status.st_mode):
        what = "not a regular file (a FIFO, device or socket)"
    elif status.st_nlink != 1:
        what = f"a file with {status.st_nlink} names (a hard link to another file)"
    elif status.st_size > _LARGEST_LOCK_BYTES or not _holds_a_pid(descriptor):
        what = f"a file of {status.st_size} bytes holding something other than a pid"
    if what is not None:
        os.close(descriptor)
        raise FolderLockedError(refused.format(what=what))
    return descriptor


def _holds_a_pid(descriptor: int) -> bool:
    """Whether the file holds nothing, or a pid and its newline (what sso writes)."""
    text = os.pread(descriptor, _LARGEST_LOCK_BYTES + 1, 0)
    return text == b"" or (text.endswith(b"\n") and text[:-1].isdigit())


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
