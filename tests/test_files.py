"""Atomic writes: a file is either its old or its new content, never half of one."""

import pytest

from sso.files import TEMPORARY_PREFIX, write_bytes_atomic, write_text_atomic


def test_atomic_write_replaces_whole_files(tmp_path):
    target = tmp_path / "result.json"
    write_text_atomic(target, "old")
    write_text_atomic(target, "new")
    assert target.read_text() == "new"
    assert [path.name for path in tmp_path.iterdir()] == ["result.json"]


def test_failed_atomic_write_keeps_the_old_file_and_no_temporary(tmp_path):
    target = tmp_path / "result.json"
    write_text_atomic(target, "old")
    with pytest.raises(TypeError):
        write_bytes_atomic(target, "not bytes")  # type: ignore[arg-type]
    assert target.read_text() == "old"
    assert not list(tmp_path.glob(f"{TEMPORARY_PREFIX}*"))
