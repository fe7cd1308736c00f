"""Atomic file writes (a temporary file in the target's folder, then ``os.replace``)
and guarded reads of input files."""

from __future__ import annotations

import os
import stat
import tempfile
from pathlib import Path

from sso.limits import MAX_INPUT_FILE_BYTES

TEMPORARY_PREFIX = ".sso-tmp-"


def write_bytes_atomic(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` so that readers see the old file or the whole new one.

    The data go to a temporary file in the same folder (same file system), are
    flushed to disk, and the file is renamed over ``path``. On any error the
    temporary file is removed and ``path`` is left as it was. Where the system
    allows (Linux), the temporary file has no name while it is written, so a
    process killed mid-write (SIGKILL) leaves nothing behind; it is named
    (``.sso-tmp-*``) only for the instant between linking and renaming it.

    Parameters
    ----------
    path : path-like
        Target file; its folder must exist.
    data : bytes
        Complete new contents.

    Returns
    -------
    pathlib.Path
        The target path.
    """
    target = Path(path)
    try:
        descriptor = os.open(target.parent, os.O_TMPFILE | os.O_WRONLY, 0o644)
    except (AttributeError, OSError):  # no O_TMPFILE here, or not on this file system
        return _write_named_temporary(target, data)
    try:
        _write_all(descriptor, data)
        temporary = target.parent / f"{TEMPORARY_PREFIX}{os.urandom(6).hex()}-{target.name}"
        try:
            os.link(f"/proc/self/fd/{descriptor}", temporary, follow_symlinks=True)
        except OSError:
            return _write_named_temporary(target, data)
        try:
            os.replace(temporary, target)
        except BaseException:
            temporary.unlink(missing_ok=True)
            raise
    finally:
        os.close(descriptor)
    return target


def _write_all(descriptor: int, data: bytes) -> None:
    os.fchmod(descriptor, 0o644)
    view = memoryview(data)
    while view:
        view = view[os.write(descriptor, view):]
    os.fsync(descriptor)


def _write_named_temporary(target: Path, data: bytes) -> Path:
    descriptor, temporary_name = tempfile.mkstemp(prefix=TEMPORARY_PREFIX,
                                                  suffix=f"-{target.name}", dir=target.parent)
    try:
        try:
            _write_all(descriptor, data)
        finally:
            os.close(descriptor)
        os.replace(temporary_name, target)
    except BaseException:
        Path(temporary_name).unlink(missing_ok=True)
        raise
    return target


def remove_stale_temporaries(folder: str | os.PathLike[str]) -> list[Path]:
    """Delete temporary files a killed writer left in ``folder``; returns them.

    Only for a folder no other process is writing into (a sweep's own folder).
    """
    stale = sorted(Path(folder).glob(f"{TEMPORARY_PREFIX}*"))
    for path in stale:
        path.unlink(missing_ok=True)
    return stale


def write_text_atomic(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` as UTF-8 atomically (see :func:`write_bytes_atomic`)."""
    return write_bytes_atomic(path, text.encode("utf-8"))


def read_input_bytes(path: str | os.PathLike[str],
                     limit_bytes: int = MAX_INPUT_FILE_BYTES) -> bytes:
    """Read a user's input file, refusing what cannot be a small regular file.

    The path is checked before it is opened: a FIFO would block the open, and a
    device such as ``/dev/zero`` would be read until memory runs out. Symbolic
    links to regular files are followed.

    Parameters
    ----------
    path : path-like
        The file.
    limit_bytes : int
        Largest size accepted, bytes (default :data:`sso.limits.MAX_INPUT_FILE_BYTES`).

    Returns
    -------
    bytes
        The file's contents.

    Raises
    ------
    ValueError
        Saying why, without the path: the system's reason it cannot be read, or
        that it is a folder, not a regular file, or larger than the limit.
    """
    try:
        status = os.stat(path)
        if stat.S_ISDIR(status.st_mode):
            raise ValueError("it is a folder")
        if not stat.S_ISREG(status.st_mode):
            raise ValueError("it is not a regular file (a FIFO, device or socket is refused "
                             "unread)")
        if status.st_size > limit_bytes:
            raise ValueError(f"it has {status.st_size} bytes; at most {limit_bytes} are read")
        with open(path, "rb") as handle:
            data = handle.read(limit_bytes + 1)
    except OSError as error:
        raise ValueError(str(error.strerror or error)) from None
    if len(data) > limit_bytes:
        raise ValueError(f"it has more than {limit_bytes} bytes; at most {limit_bytes} are read")
    return data
