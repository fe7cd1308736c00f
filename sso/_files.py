"""Atomic writes (a file via a temporary file and ``os.replace``; a whole report folder
via a temporary sibling folder swapped into place), the manifest of the files sso
wrote into a folder (sso replaces nothing else), and guarded reads of input files."""

from __future__ import annotations

import errno
import json
import os
import re
import shutil
import stat
import tempfile
from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path

from sso._interrupts import interrupts_held
from sso._limits import MAX_INPUT_FILE_BYTES

TEMPORARY_PREFIX = ".sso-tmp-"


@dataclass(frozen=True)
class StreamedFile:
    """A file's contents given as the chunks ``chunks()`` yields, written as they come,
    so that a large file (a study's table) is never held whole in memory.

    ``chunks`` is called afresh for each write (a failed folder swap may write again).
    """

    chunks: Callable[[], Iterator[bytes]]


FileContents = bytes | StreamedFile
"""What a file written by :func:`write_bytes_atomic` or :func:`replace_folder` holds."""


def write_bytes_atomic(path: str | os.PathLike[str], data: FileContents) -> Path:
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
    data : bytes or StreamedFile
        Complete new contents (a :class:`StreamedFile`: written chunk by chunk).

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


def _write_all(descriptor: int, data: FileContents) -> None:
    os.fchmod(descriptor, 0o644)
    for chunk in _chunks(data):
        view = memoryview(chunk)
        while view:
            view = view[os.write(descriptor, view):]
    os.fsync(descriptor)


def _chunks(data: FileContents) -> Iterator[bytes]:
    if isinstance(data, StreamedFile):
        yield from data.chunks()
    else:
        yield data


def _write_named_temporary(target: Path, data: FileContents) -> Path:
    # Ctrl-C and SIGTERM wait until the named temporary file is renamed or removed, so
    # an interrupted run never leaves one (only SIGKILL can).
    with interrupts_held():
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
    return target


def remove_stale_temporaries(folder: str | os.PathLike[str]) -> list[Path]:
    """Delete temporary files a killed writer left in ``folder``; returns them.

    Only for a folder no other process is writing into (a sweep's own folder).
    """
    stale = sorted(Path(entry.path) for entry in os.scandir(folder)
                   if entry.name.startswith(TEMPORARY_PREFIX)
                   and entry.is_file(follow_symlinks=False))
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
        Largest size accepted, bytes (default :data:`sso._limits.MAX_INPUT_FILE_BYTES`).

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


WRITTEN_SUFFIXES = (".json", ".csv", ".md", ".html", ".png", ".parquet")
"""How the name of every file (and folder) sso writes into an output folder ends: a
manifest listing any other name is not sso's (it would have sso delete, say, a
user's notes.txt)."""

FOLDER_MANIFEST = "sso-files.json"
"""The file in which a folder sso writes lists the files sso wrote there (and what
the folder holds: a case's report, a sweep, a tolerance study)."""

# Names mkdtemp gives the staging folders of replace_folder (8 random characters).
_STAGING = re.compile(rf"{re.escape(TEMPORARY_PREFIX)}(?:new|old)-[a-z0-9_]{{8}}-(?P<name>.+)")
# What a rename of a folder meets where the folder cannot move: a mount point (EBUSY),
# another file system (EXDEV), a parent this user may not change (EACCES, EPERM),
# the working directory or one above it (EINVAL, EBUSY).
_CANNOT_MOVE = frozenset({errno.EBUSY, errno.EXDEV, errno.EACCES, errno.EPERM, errno.EINVAL})


def make_folders(path: str | os.PathLike[str]) -> Path:
    """Create ``path`` and its missing parents, one level at a time.

    Unlike ``Path.mkdir(parents=True)`` it does not recurse, so a path of thousands
    of parts is made, or fails with the system's reason (``File name too long``);
    on failure the folders it made are removed again.

    Raises
    ------
    ValueError
        If a level exists and is not a folder (a file, a symbolic link that leads
        nowhere or in a loop): the message says which and what it is.
    OSError
        If a level cannot be created (nothing new is left behind).
    """
    target = Path(path)
    missing = []
    for folder in (target, *target.parents):
        if folder.is_dir():
            break
        if os.path.lexists(folder):
            raise ValueError(f"{folder} {not_a_folder(folder)}; choose a folder")
        missing.append(folder)
    made: list[Path] = []
    try:
        for folder in reversed(missing):
            try:
                folder.mkdir()
            except FileExistsError:  # made meanwhile by another process
                if not folder.is_dir():
                    raise ValueError(f"{folder} {not_a_folder(folder)}; choose a "
                                     "folder") from None
            else:
                made.append(folder)
    except BaseException:
        for folder in reversed(made):
            try:
                folder.rmdir()
            except OSError:  # another process wrote into it meanwhile: it stays
                break
        raise
    return target


def not_a_folder(path: str | os.PathLike[str]) -> str:
    """What ``path``, which exists but is no folder, is, in words: "is a file, not a
    folder", "is a symbolic link that leads nowhere (...)"."""
    if os.path.islink(path):
        try:
            os.stat(path)
        except OSError as error:
            why = ("a loop of links" if error.errno == errno.ELOOP
                   else f"to {os.readlink(path)}, which is missing")
            return f"is a symbolic link that leads nowhere ({why}), not a folder"
        return f"is a symbolic link to a file ({os.readlink(path)}), not a folder"
    if os.path.isfile(path):
        return "is a file, not a folder"
    return "is not a folder (a FIFO, device or socket)"


def sso_files(path: str | os.PathLike[str]) -> tuple[str | None, frozenset[str]]:
    """What the folder ``path`` holds by its manifest: (kind, names of sso's files).

    ``(None, empty)`` when the folder has no readable manifest written by sso.

    Raises
    ------
    ValueError
        If the manifest lists an entry that is not a plain name in the folder (a
        path into a subfolder or out of the folder, ``.``, ``..``, an empty name), or
        a name not ending in one of :data:`WRITTEN_SUFFIXES`: sso never writes one,
        so the manifest is not sso's as written.
    """
    try:
        data = json.loads(read_input_bytes(Path(path) / FOLDER_MANIFEST))
    except (ValueError, UnicodeDecodeError, RecursionError):
        return None, frozenset()
    if (not isinstance(data, dict) or data.get("written_by") != "sso"
            or not isinstance(data.get("kind"), str) or not isinstance(data.get("files"), list)
            or not all(isinstance(name, str) for name in data["files"])):
        return None, frozenset()
    for name in data["files"]:
        if not _plain_name(name):
            why = "which is not a file name in the folder"
        elif not name.endswith(WRITTEN_SUFFIXES):
            why = f"a name sso never writes (its files end in {', '.join(WRITTEN_SUFFIXES)})"
        else:
            continue
        raise ValueError(f"{Path(path) / FOLDER_MANIFEST} lists {name!r}, {why}; sso lists "
                         "only the files it writes there, and nothing was deleted. Choose "
                         "another folder (--out), or remove that entry")
    return data["kind"], frozenset(data["files"])


def _plain_name(name: str) -> bool:
    """Whether ``name`` names an entry of a folder itself (no path, not . or ..)."""
    return (name not in ("", os.curdir, os.pardir) and os.sep not in name
            and (os.altsep is None or os.altsep not in name) and "\0" not in name)


def _check_written_names(names: Iterable[str]) -> None:
    """Raise ValueError unless each of ``names`` is a plain name ending as sso's files do."""
    bad = [name for name in names if not _plain_name(name) or name == FOLDER_MANIFEST
           or name.startswith(TEMPORARY_PREFIX) or not name.endswith(WRITTEN_SUFFIXES)]
    if bad:
        raise ValueError(f"file names {bad!r} cannot be written into an output folder (plain "
                         f"names ending in {', '.join(WRITTEN_SUFFIXES)})")


def check_report_folder(path: str | os.PathLike[str], kind: str,
                        adopt: tuple[str, ...] = (), folders: tuple[str, ...] = ()) -> Path:
    """``path`` as a Path, if sso may write a ``kind`` folder there.

    It may if ``path`` is missing, an empty folder, or a folder whose every entry is
    a regular file sso wrote there for the same kind (listed in its
    :data:`FOLDER_MANIFEST`), a temporary file of an interrupted write
    (``.sso-tmp-*``), one of ``adopt``, or a folder named in ``folders`` that the
    manifest lists. Nothing else is ever replaced or deleted: the manifest naming a
    folder sso does not write there, or a link, does not make it sso's.

    Parameters
    ----------
    path : path-like
        The folder.
    kind : str
        What sso writes there: ``"case report"``, ``"sweep"``, ``"tolerance study"``.
    adopt : tuple of str
        Names to treat as sso's even if unlisted (``sso report`` reading the
        ``result.json`` it will write again).
    folders : tuple of str
        Names of the folders sso writes into a ``kind`` folder (a sweep's
        ``sweep.parquet``); every other name it writes is a regular file.

    Raises
    ------
    ValueError
        If ``path`` is a file; if its manifest says it holds another kind (a sweep
        where a case's report would go) or lists an entry that is not a plain name;
        if a name sso writes as a file is a folder there, or one it writes as a
        folder is a file; or naming every entry that sso did not write (a folder, a
        link, a file missing from the manifest). Nothing is deleted.
    """
    target = Path(path)
    if not target.is_dir():
        if os.path.lexists(target):
            raise ValueError(f"{target} {not_a_folder(target)}; choose a folder for the {kind}")
        return target
    entries = list(os.scandir(target))
    if not entries:
        return target
    found_kind, listed = sso_files(target)
    if found_kind is not None and found_kind != kind:
        raise ValueError(f"{target} holds a {found_kind} written by sso: a {kind} and a "
                         f"{found_kind} never share a folder. Choose another folder (--out), "
                         f"or delete this one if the {found_kind} is no longer needed")
    own = listed | set(adopt) | {FOLDER_MANIFEST}
    misshapen = [_misshapen(entry, kind, folders, entry.name in listed) for entry in entries
                 if entry.name in own and not entry.is_symlink()]
    if any(misshapen):
        raise ValueError(f"{target}: {next(text for text in misshapen if text)}; nothing was "
                         "deleted. Choose another folder (--out), or move it out")
    foreign = sorted(entry.name for entry in entries
                     if entry.is_symlink()
                     or not (entry.is_file() or (entry.is_dir() and entry.name in folders))
                     or not (entry.name in own or entry.name.startswith(TEMPORARY_PREFIX)))
    if foreign:
        shown_names = ", ".join(foreign[:8]) + (f" and {len(foreign) - 8} more"
                                                if len(foreign) > 8 else "")
        why = ("they are not in its " + FOLDER_MANIFEST if found_kind is not None
               else "it has no " + FOLDER_MANIFEST)
        raise ValueError(f"{target} holds {shown_names}, which sso did not write ({why}); "
                         "sso replaces only its own files. Choose another folder (--out), "
                         "or move those files out")
    return target


def _misshapen(entry: os.DirEntry[str], kind: str, folders: tuple[str, ...],
               listed: bool) -> str | None:
    """Why the entry sso lists (or adopts) is not what sso writes under its name, or None."""
    if entry.name in folders and not entry.is_dir():
        return f"{entry.name} is a file where sso writes a folder of that name"
    if entry.name not in folders and entry.is_dir():
        return (f"{entry.name} is a folder, where sso writes a file {entry.name} into a "
                f"{kind}{f' ({FOLDER_MANIFEST} lists that name)' if listed else ''}; sso "
                "deletes only the regular files it writes")
    if not (entry.is_dir() or entry.is_file()):
        return f"{entry.name} is not a regular file (a FIFO, device or socket)"
    return None


def claim_folder(path: str | os.PathLike[str], kind: str, names: tuple[str, ...],
                 folders: tuple[str, ...] = ()) -> Path:
    """Check ``path`` (:func:`check_report_folder`), create it, and add ``names`` to its
    manifest, before a writer that fills the folder over time (a sweep) writes them;
    ``folders`` are those of ``names`` it writes as folders.

    The caller holds the folder's lock (:func:`sso._folder_lock.folder_lock`) over
    the claim and the writes.

    Raises
    ------
    ValueError
        As :func:`check_report_folder`.
    """
    _check_written_names(names)
    target = check_report_folder(path, kind, folders=folders)
    make_folders(target)
    _, listed = sso_files(target)
    write_bytes_atomic(target / FOLDER_MANIFEST, _manifest(kind, listed | set(names)))
    return target


def _manifest(kind: str, names: Iterable[str]) -> bytes:
    document = {"written_by": "sso", "kind": kind, "files": sorted(set(names))}
    return (json.dumps(document, indent=2) + "\n").encode("utf-8")


def replace_folder(path: str | os.PathLike[str], files: Mapping[str, FileContents], kind: str,
                   adopt: tuple[str, ...] = ()) -> list[Path]:
    """Make ``path`` a folder holding exactly ``files`` (and their manifest), never
    losing the old one on failure and never a file sso did not write.

    The caller holds the folder's lock (:func:`sso._folder_lock.folder_lock`;
    :func:`sso.write_report` takes it). The files and the manifest are written (and
    flushed to disk) into a new temporary folder beside ``path``; then the old
    folder is renamed aside, the new one renamed into its place, and only then is
    the old one deleted: readers never see a half-written folder. Where the folder
    cannot be renamed (a symbolic link to a folder, a mount point, the working
    directory or one above it, a parent that may not change), its files are
    replaced one by one instead, each atomically, the manifest always listing every
    file present. Ctrl-C and SIGTERM wait until the folder is consistent.

    Parameters
    ----------
    path : path-like
        The folder; its parents are created if missing.
    files : mapping of str to bytes or StreamedFile
        File name (no folders) to complete contents (a :class:`StreamedFile`'s
        chunks are written as they come).
    kind : str
        What the folder holds (see :func:`check_report_folder`).
    adopt : tuple of str
        Names in the folder to treat as sso's (see :func:`check_report_folder`).

    Returns
    -------
    list of pathlib.Path
        The files now in ``path`` (the manifest not counted).

    Raises
    ------
    ValueError
        As :func:`check_report_folder` (nothing is touched), or for a file name
        that is not a plain name.
    OSError
        If the folder cannot be written; ``path`` is then left as it was.
    """
    names = list(files)
    _check_written_names(names)
    target = check_report_folder(path, kind, adopt)
    make_folders(target.parent)
    _remove_stale_staging(target)
    contents = {**files, FOLDER_MANIFEST: _manifest(kind, names)}
    if target.is_dir() and not _movable(target):
        _replace_files(target, contents)
    else:
        try:
            _swap(target, contents)
        except OSError as error:
            if error.errno not in _CANNOT_MOVE or not target.is_dir():
                raise
            _replace_files(target, contents)
    return [target / name for name in names]


def _movable(folder: Path) -> bool:
    """Whether renaming ``folder`` moves what its users expect: not a link, not a
    mount point, not the working directory or a folder above it."""
    if folder.is_symlink() or os.path.ismount(folder):
        return False
    here = os.path.realpath(os.getcwd())
    there = os.path.realpath(folder)
    return not (here == there or here.startswith(there.rstrip(os.sep) + os.sep))


def _swap(target: Path, contents: Mapping[str, FileContents]) -> None:
    staging = Path(tempfile.mkdtemp(prefix=f"{TEMPORARY_PREFIX}new-", suffix=f"-{target.name}",
                                    dir=target.parent))
    try:
        for name, data in contents.items():
            with open(staging / name, "wb") as handle:
                for chunk in _chunks(data):
                    handle.write(chunk)
                handle.flush()
                os.fsync(handle.fileno())
            os.chmod(staging / name, 0o644)
        os.chmod(staging, 0o755)
        with interrupts_held():
            if target.exists():
                aside = Path(tempfile.mkdtemp(prefix=f"{TEMPORARY_PREFIX}old-",
                                              suffix=f"-{target.name}", dir=target.parent))
                try:
                    os.replace(target, aside)  # onto the empty folder just made: atomic
                except BaseException:
                    aside.rmdir()
                    raise
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


def _replace_files(target: Path, contents: Mapping[str, FileContents]) -> None:
    """Replace the files of ``target`` one by one; its manifest lists every file present
    at every moment (first the old and the new, last the new only)."""
    kind = json.loads(b"".join(_chunks(contents[FOLDER_MANIFEST])))["kind"]
    present = {entry.name for entry in os.scandir(target)} - {FOLDER_MANIFEST}
    with interrupts_held():
        write_bytes_atomic(target / FOLDER_MANIFEST, _manifest(kind, present | set(contents)))
        for name, data in contents.items():
            if name != FOLDER_MANIFEST:
                write_bytes_atomic(target / name, data)
        for name in present - set(contents):
            (target / name).unlink(missing_ok=True)
        write_bytes_atomic(target / FOLDER_MANIFEST, contents[FOLDER_MANIFEST])


def _remove_stale_staging(target: Path) -> None:
    """Delete the staging folders of ``target`` that a killed writer left beside it
    (only SIGKILL can; the caller holds the folder's lock, so no writer is alive)."""
    for entry in os.scandir(target.parent):
        match = _STAGING.fullmatch(entry.name)
        if (match and match["name"] == target.name and entry.is_dir(follow_symlinks=False)
                and entry.stat(follow_symlinks=False).st_uid == os.geteuid()):
            shutil.rmtree(entry.path, ignore_errors=True)
