"""sso.files.replace_folder: a report folder is replaced whole, or not at all."""

from __future__ import annotations

import pytest

from sso.files import replace_folder


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
