"""Atomic writes: a file is either its old or its new content, never half of one."""

import pytest

from sso.files import (
    TEMPORARY_PREFIX,
    replace_folder,
    write_bytes_atomic,
    write_text_atomic,
)


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


def test_a_report_folder_is_replaced_whole(tmp_path):
    folder = tmp_path / "report"
    replace_folder(folder, {"report.md": b"old", "polar.png": b"old plot"})
    written = replace_folder(folder, {"report.md": b"new"})
    assert written == [folder / "report.md"]
    assert sorted(path.name for path in folder.iterdir()) == ["report.md"]  # no old plot
    assert (folder / "report.md").read_bytes() == b"new"
    assert sorted(path.name for path in tmp_path.iterdir()) == ["report"]  # no temporary


def test_a_failed_replacement_keeps_the_old_folder_and_leaves_no_temporary(tmp_path):
    folder = tmp_path / "report"
    replace_folder(folder, {"report.md": b"old"})
    with pytest.raises(TypeError):
        replace_folder(folder, {"report.md": b"new", "speeds.csv": "not bytes"})  # type: ignore[dict-item]
    assert (folder / "report.md").read_bytes() == b"old"
    assert sorted(path.name for path in tmp_path.iterdir()) == ["report"]


def test_a_folder_with_other_files_is_not_replaced(tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    (tmp_path / "cases").mkdir()
    with pytest.raises(ValueError, match="holds cases, notes.txt, which is not a report file"):
        replace_folder(tmp_path, {"report.md": b"new"})
    assert (tmp_path / "notes.txt").read_text() == "mine"
