"""The folder of compiled libraries, kept within a size bound.

A library's name hashes the package's code (:mod:`sso._solvers.lm_native`), so every
upgrade of sso, and every shape a user solves, adds a library; nothing else ever
removes one. After each build the folder's libraries are held to
:data:`sso._limits.COMPILED_CACHE_BYTES`, the least recently used removed first (a
load from the cache marks a library used). Only files sso writes there are touched:
libraries named ``sso-lm-*.so`` and the partial builds ``.building-*.so`` that a
killed build leaves behind (once :data:`ABANDONED_BUILD_S` old, so a build still
under way elsewhere is never removed).
"""

from __future__ import annotations

import os
import stat
import time
from pathlib import Path

LIBRARY_PATTERN = "sso-lm-*.so"
"""The names of the libraries sso writes into the cache folder."""

PARTIAL_PATTERN = ".building-*.so"
"""The names of the partial builds sso writes there before renaming them."""

ABANDONED_BUILD_S = 3600.0
"""Age, s, past which a partial build is one a killed process left behind (a build
takes seconds; its compiler is stopped after :data:`sso._solvers.lm_native.COMPILE_TIMEOUT_S`)."""


def mark_used(library: Path) -> None:
    """Record that ``library`` was loaded now (its modification time), so that pruning
    keeps it before the libraries used less recently; a folder that cannot be written
    keeps its times."""
    try:
        os.utime(library)
    except OSError:
        pass


def prune(folder: Path, kept: Path, limit_bytes: int) -> list[Path]:
    """Remove the least recently used libraries of ``folder`` until the rest take at most
    ``limit_bytes``, never ``kept`` (the library just built), and the partial builds
    older than :data:`ABANDONED_BUILD_S`.

    Parameters
    ----------
    folder : Path
        The cache folder.
    kept : Path
        The library that stays whatever its size.
    limit_bytes : int
        Most bytes the libraries may take together, ``kept`` included.

    Returns
    -------
    list of Path
        The files removed. A file another process removed or replaced meanwhile, or
        one that cannot be removed, is left as it is and not listed.
    """
    now = time.time()
    removed: list[Path] = []
    libraries: list[tuple[float, int, Path]] = []
    for path in folder.glob(PARTIAL_PATTERN):
        status = _status(path)
        if status is not None and now - status.st_mtime > ABANDONED_BUILD_S and _remove(path):
            removed.append(path)
    for path in folder.glob(LIBRARY_PATTERN):
        status = _status(path)
        if status is not None:
            libraries.append((status.st_mtime, status.st_size, path))
    total = sum(size for _, size, _ in libraries)
    for _, size, path in sorted(libraries):
        if total <= limit_bytes:
            break
        if path != kept and _remove(path):
            removed.append(path)
            total -= size
    return removed


def _status(path: Path) -> os.stat_result | None:
    """``path``'s own status, None when it is gone or not a regular file (a link is
    never followed)."""
    try:
        status = path.lstat()
    except OSError:
        return None
    return status if stat.S_ISREG(status.st_mode) else None


def _remove(path: Path) -> bool:
    """Remove ``path``; False when it cannot be (gone already, or not allowed)."""
    try:
        path.unlink()
    except OSError:
        return False
    return True
