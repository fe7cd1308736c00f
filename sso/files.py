"""Atomic writes (a file via a temporary file and ``os.replace``; a whole report folder
via a temporary sibling folder swapped into place) and guarded reads of input files."""

from __future__ import annotations

import os
import shutil
import signal
import stat
import tempfile
from collections.abc import Mapping
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
    if not nameless_temporaries(target.parent):
        return _write_named_temporary(target, data)
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


_NAMELESS_BY_DEVICE: dict[int, bool] = {}


def nameless_temporaries(folder: str | os.PathLike[str]) -> bool:
    """Whether :func:`write_bytes_atomic` writes into ``folder`` with no temporary name.

    It needs ``O_TMPFILE`` and a link from ``/proc/self/fd``; some kernels and
    sandboxes refuse the link (EXDEV), and the write then goes through a named
    ``.sso-tmp-*`` file, which a SIGKILL in that instant leaves behind (a later
    sweep in the same folder removes it). Probed once per file system.

    Raises
    ------
    OSError
        If ``folder`` does not exist or cannot be read.
    """
    device = os.stat(folder).st_dev
    if device not in _NAMELESS_BY_DEVICE:
        _NAMELESS_BY_DEVICE[device] = _probe_nameless(folder)
    return _NAMELESS_BY_DEVICE[device]


def _probe_nameless(folder: str | os.PathLike[str]) -> bool:
    try:
        descriptor = os.open(folder, os.O_TMPFILE | os.O_WRONLY, 0o644)
    except (AttributeError, OSError):
        return False
    probe = Path(folder) / f"{TEMPORARY_PREFIX}{os.urandom(6).hex()}-probe"
    try:
        os.link(f"/proc/self/fd/{descriptor}", probe, follow_symlinks=True)
    except OSError:
        return False
    else:
        probe.unlink()
        return True
    finally:
        os.close(descriptor)


def _write_all(descriptor: int, data: bytes) -> None:
    os.fchmod(descriptor, 0o644)
    view = memoryview(data)
    while view:
        view = view[os.write(descriptor, view):]
    os.fsync(descriptor)


def _write_named_temporary(target: Path, data: bytes) -> Path:
    # Ctrl-C and SIGTERM wait until the named temporary file is renamed or removed, so
    # an interrupted run never leaves one (only SIGKILL can).
    held = _hold_interrupts()
    try:
        descriptor, temporary_name = tempfile.mkstemp(prefix=TEMPORARY_PREFIX,
                                                      suffix=f"-{target.name}",
                                                      dir=target.parent)
        try:
            try:
                _write_all(descriptor, data)
            finally:
                os.close(descriptor)
            os.replace(temporary_name, target)
        except BaseException:
            Path(temporary_name).unlink(missing_ok=True)
            raise
    finally:
        if held is not None:
            signal.pthread_sigmask(signal.SIG_SETMASK, held)
    return target


def _hold_interrupts() -> set[int | signal.Signals] | None:
    """Block SIGINT and SIGTERM in this thread; the previous mask, or None where the
    system cannot block signals."""
    if not hasattr(signal, "pthread_sigmask"):
        return None
    return signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})


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


REPORT_SUFFIXES = (".json", ".csv", ".md", ".html", ".png")
"""Files a report folder may hold for :func:`replace_folder` to replace it."""


def check_report_folder(path: str | os.PathLike[str]) -> Path:
    """``path`` as a Path, if it is missing or a folder holding report files only.

    Raises
    ------
    ValueError
        If ``path`` is a file, or a folder holding a subfolder or a file whose
        suffix is not one of :data:`REPORT_SUFFIXES`.
    """
    target = Path(path)
    if target.exists():
        if not target.is_dir():
            raise ValueError(f"{target} is a file, not a report folder")
        foreign = sorted(entry.name for entry in target.iterdir()
                         if not entry.is_file() or entry.suffix not in REPORT_SUFFIXES)
        if foreign:
            raise ValueError(f"{target} holds {', '.join(foreign[:3])}"
                             f"{' and more' if len(foreign) > 3 else ''}, which is not a "
                             f"report file ({', '.join(REPORT_SUFFIXES)}); choose an empty or "
                             "new folder for the report")
    return target


def replace_folder(path: str | os.PathLike[str], files: Mapping[str, bytes]) -> list[Path]:
    """Make ``path`` a folder holding exactly ``files``, never losing the old one on failure.

    The files are written (and flushed to disk) into a new temporary folder beside
    ``path``; then the old folder is renamed aside, the new one renamed into its
    place, and only then is the old one deleted. Whatever fails before the second
    rename leaves ``path`` as it was; readers never see a half-written folder.

    Parameters
    ----------
    path : path-like
        The report folder; its parent is created if missing.
    files : mapping of str to bytes
        File name (no folders) to complete contents.

    Returns
    -------
    list of pathlib.Path
        The files now in ``path``.

    Raises
    ------
    ValueError
        If ``path`` exists and holds anything but report files (a subfolder, or
        a file whose suffix is not one of :data:`REPORT_SUFFIXES`): it is not a
        report folder, and replacing it would delete what its owner keeps there.
    OSError
        If the folder cannot be written; ``path`` is then left as it was.
    """
    target = check_report_folder(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f"{TEMPORARY_PREFIX}new-", suffix=f"-{target.name}",
                                    dir=target.parent))
    try:
        for name, data in files.items():
            with open(staging / name, "wb") as handle:
                handle.write(data)
                handle.flush()
                os.fsync(handle.fileno())
            os.chmod(staging / name, 0o644)
        os.chmod(staging, 0o755)
        if target.exists():
            aside = Path(tempfile.mkdtemp(prefix=f"{TEMPORARY_PREFIX}old-",
                                          suffix=f"-{target.name}", dir=target.parent))
            os.replace(target, aside)  # onto the empty folder just made: atomic on POSIX
            try:
                os.replace(staging, target)
            except BaseException:
                os.replace(aside, target)
                raise
            shutil.rmtree(aside, ignore_errors=True)
        else:
            os.replace(staging, target)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    return [target / name for name in files]
