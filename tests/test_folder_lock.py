"""One writer per output folder: the lock is real (flock between real processes), names
its owner's pid, and a lock file left by a killed process does not block the next one."""

from __future__ import annotations

import ast
import os
import signal
import subprocess
import sys

import pytest

from sso._folder_lock import FolderLockedError, folder_lock, lock_path

HOLD = """
import sys, time
from sso._folder_lock import folder_lock
with folder_lock(sys.argv[1], "test"):
    print("held", flush=True)
    time.sleep(60)
"""


def _holder(folder):
    process = subprocess.Popen([sys.executable, "-c", HOLD, str(folder)],
                               stdout=subprocess.PIPE, text=True)
    assert process.stdout.readline().strip() == "held"
    return process


def test_a_second_writer_is_refused_with_the_owner_s_pid(tmp_path):
    folder = tmp_path / "out"
    process = _holder(folder)
    try:
        with pytest.raises(FolderLockedError, match=f"process {process.pid} holds its lock"):
            with folder_lock(folder):
                pass
    finally:
        process.kill()
        process.wait()


def test_a_lock_left_by_a_killed_process_is_stale_and_taken_over(tmp_path):
    folder = tmp_path / "out"
    process = _holder(folder)
    os.kill(process.pid, signal.SIGKILL)
    process.wait()
    assert lock_path(folder).read_text().strip() == str(process.pid)  # the file stays
    with folder_lock(folder) as path:
        assert path.read_text().strip() == str(os.getpid())
    assert not lock_path(folder).exists()  # released: the file is gone


def test_the_lock_is_taken_again_after_release_and_nests_nowhere(tmp_path):
    folder = tmp_path / "a" / "b"
    for _ in range(3):
        with folder_lock(folder):
            assert lock_path(folder).parent == tmp_path / "a"
            with pytest.raises(FolderLockedError):
                with folder_lock(folder):
                    pass
    assert list((tmp_path / "a").iterdir()) == []


def test_racing_writers_never_hold_the_lock_together(tmp_path):
    # Many processes take and release the lock as fast as they can; each records the
    # instants it held it, and no two intervals may overlap.
    race = """
import sys, time
from sso._folder_lock import FolderLockedError, folder_lock
spans = []
deadline = time.monotonic() + 1.5
while time.monotonic() < deadline:
    try:
        with folder_lock(sys.argv[1]):
            start = time.monotonic()
            time.sleep(0.001)
            spans.append((start, time.monotonic()))
    except FolderLockedError:
        pass
print(repr(spans))
"""
    processes = [subprocess.Popen([sys.executable, "-c", race, str(tmp_path / "out")],
                                  stdout=subprocess.PIPE, text=True) for _ in range(4)]
    spans = sorted(span for process in processes
                   for span in ast.literal_eval(process.communicate(timeout=60)[0]))
    assert len(spans) > 10
    assert all(earlier[1] <= later[0] for earlier, later in zip(spans, spans[1:], strict=False))
