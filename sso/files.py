"""Atomic file writes: a temporary file in the target's folder, then ``os.replace``."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

TEMPORARY_PREFIX = ".sso-tmp-"


def write_bytes_atomic(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` so that readers see the old file or the whole new one.

    The data go to a temporary file in the same folder (same file system), are
    flushed to disk, and the file is renamed over ``path``. On any error the
    temporary file is removed and ``path`` is left as it was.

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
    descriptor, temporary_name = tempfile.mkstemp(prefix=TEMPORARY_PREFIX,
                                                  suffix=f"-{target.name}", dir=target.parent)
    try:
        with os.fdopen(descriptor, "wb") as handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        os.chmod(temporary_name, 0o644)
        os.replace(temporary_name, target)
    except BaseException:
        Path(temporary_name).unlink(missing_ok=True)
        raise
    return target


def write_text_atomic(path: str | os.PathLike[str], text: str) -> Path:
    """Write ``text`` as UTF-8 atomically (see :func:`write_bytes_atomic`)."""
    return write_bytes_atomic(path, text.encode("utf-8"))
