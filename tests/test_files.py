"""sso._files: a reader sees the old file or the whole new one, never a part, and no
temporary file is left behind unless the process itself is killed.

Interruptions are real: a child process is stopped by a real signal while it sits
between writing its temporary file and renaming it over the target.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from sso._files import (
    TEMPORARY_PREFIX,
    nameless_temporaries,
    write_bytes_atomic,
    write_text_atomic,
)

ROOT = Path(__file__).resolve().parents[1]
OLD = b"old contents\n"
NEW_PIECE, NEW_COPIES = b"new contents ", 100_000  # 1.3 MB: not one small block
NEW = NEW_PIECE * NEW_COPIES


def test_writes_and_replaces_whole_files(tmp_path):
    target = tmp_path / "result.json"
    assert write_bytes_atomic(target, OLD) == target
    assert target.read_bytes() == OLD
    write_bytes_atomic(str(target), NEW)
    assert target.read_bytes() == NEW
    assert [path.name for path in tmp_path.iterdir()] == ["result.json"]


def test_text_is_written_as_utf8(tmp_path):
    target = write_text_atomic(tmp_path / "report.md", "β = 15.84°\n")
    assert target.read_bytes() == "β = 15.84°\n".encode()


def test_new_file_is_readable_by_others(tmp_path):
    # mkstemp creates 0600 files; a report must be readable like any other file.
    target = write_bytes_atomic(tmp_path / "table.csv", b"a,b\n")
    assert target.stat().st_mode & 0o777 == 0o644


def test_failed_write_leaves_the_old_file_and_no_temporary(tmp_path):
    target = tmp_path / "result.json"
    target.write_bytes(OLD)
    with pytest.raises(TypeError):
        write_bytes_atomic(target, "text, not bytes")  # type: ignore[arg-type]
    assert target.read_bytes() == OLD
    assert [path.name for path in tmp_path.iterdir()] == ["result.json"]


def test_missing_folder_raises_and_creates_nothing(tmp_path):
    with pytest.raises(FileNotFoundError):
        write_bytes_atomic(tmp_path / "missing" / "result.json", OLD)
    assert list(tmp_path.iterdir()) == []


def _child_paused_before_rename(target: Path) -> subprocess.Popen[str]:
    """A real process writing NEW over ``target`` that pauses after fsync (data written,
    not yet renamed) and says so on stdout."""
    script = textwrap.dedent(f"""
        import os, sys, time
        import sso._files
        real_fsync = os.fsync
        def fsync_then_pause(descriptor):
            real_fsync(descriptor)
            print("written", flush=True)
            time.sleep(5)
        sso._files.os.fsync = fsync_then_pause
        sso._files.write_bytes_atomic({str(target)!r}, {NEW_PIECE!r} * {NEW_COPIES})
    """)
    environment = {**os.environ, "PYTHONPATH": str(ROOT)}
    child = subprocess.Popen(
        [sys.executable, "-c", script],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=environment,
    )
    assert child.stdout is not None
    assert child.stdout.readline().strip() == "written", child.stderr.read() if child.stderr else ""
    return child


def test_interrupted_write_leaves_the_old_file_and_cleans_up(tmp_path):
    target = tmp_path / "result.json"
    target.write_bytes(OLD)
    child = _child_paused_before_rename(target)
    temporaries = [path for path in tmp_path.iterdir() if path.name.startswith(TEMPORARY_PREFIX)]
    if nameless_temporaries(tmp_path):  # caught mid-write: the data have no name yet
        assert temporaries == []
    else:  # caught mid-write: the data sit in the one marked temporary file
        assert len(temporaries) == 1 and temporaries[0].read_bytes() == NEW
    child.send_signal(signal.SIGINT)  # Ctrl-C
    child.communicate(timeout=30)
    assert child.returncode != 0
    # Nameless: KeyboardInterrupt inside the write, the old file stays. Named: Ctrl-C
    # waits until the named file is renamed (sso._files holds it), so the new one is whole.
    assert target.read_bytes() == (OLD if nameless_temporaries(tmp_path) else NEW)
    assert [path.name for path in tmp_path.iterdir()] == ["result.json"]


def test_killed_write_leaves_the_old_file(tmp_path):
    target = tmp_path / "result.json"
    target.write_bytes(OLD)
    child = _child_paused_before_rename(target)
    child.send_signal(signal.SIGKILL)  # no clean-up can run
    child.communicate(timeout=30)
    assert child.returncode == -signal.SIGKILL
    assert target.read_bytes() == OLD
    # A kill leaves nothing where the temporary file has no name while it is written
    # (O_TMPFILE); elsewhere only the marked temporary file, never a partial target.
    leftovers = sorted(path.name for path in tmp_path.iterdir() if path != target)
    if nameless_temporaries(tmp_path):
        assert leftovers == []
    else:
        assert len(leftovers) == 1 and leftovers[0].startswith(TEMPORARY_PREFIX)
