"""sso._files.replace_folder: a report folder is replaced whole, or not at all, and sso
deletes or replaces only the files it wrote there (its manifest, sso-files.json, lists
them); a folder that cannot be renamed (a link, a mount point, the working folder) has
its files replaced one by one, and a path too deep for recursion is made level by level.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from sso._files import FOLDER_MANIFEST, check_report_folder, make_folders, replace_folder

REPORT = "case report"


def names(folder: Path) -> list[str]:
    return sorted(entry.name for entry in folder.iterdir())


def listed(folder: Path) -> dict[str, object]:
    return dict(json.loads((folder / FOLDER_MANIFEST).read_text()))


def test_a_report_folder_is_replaced_whole_with_its_manifest(tmp_path):
    folder = tmp_path / "report"
    replace_folder(folder, {"report.md": b"old", "polar.png": b"old plot"}, REPORT)
    written = replace_folder(folder, {"report.md": b"new"}, REPORT)
    assert written == [folder / "report.md"]
    assert names(folder) == ["report.md", FOLDER_MANIFEST]  # no old plot
    assert (folder / "report.md").read_bytes() == b"new"
    assert listed(folder) == {"written_by": "sso", "kind": REPORT, "files": ["report.md"]}
    assert names(tmp_path) == ["report"]  # no temporary folder


def test_a_failed_replacement_keeps_the_old_folder_and_leaves_no_temporary(tmp_path):
    folder = tmp_path / "report"
    replace_folder(folder, {"report.md": b"old"}, REPORT)
    with pytest.raises(TypeError):
        replace_folder(folder, {"report.md": b"new", "speeds.csv": "not bytes"},  # type: ignore[dict-item]
                       REPORT)
    assert (folder / "report.md").read_bytes() == b"old"
    assert names(tmp_path) == ["report"]


def test_a_folder_with_files_sso_did_not_write_is_refused_with_their_names(tmp_path):
    # The reproduction: a project folder holding a result.json and the user's
    # notes, measurements, photo and configuration, whose suffixes are a report's.
    project = tmp_path / "myproject"
    project.mkdir()
    mine = {"thesis.md": b"notes\n", "measurements.csv": b"t,x\n",
            "photo_of_rig.png": b"\x89PNG", "config.json": b"{}\n", "result.json": b"{}"}
    for name, data in mine.items():
        (project / name).write_bytes(data)
    (project / "cases").mkdir()
    with pytest.raises(ValueError, match="holds cases, config.json, measurements.csv, "
                       "photo_of_rig.png, result.json, thesis.md, which sso did not write "
                       f"\\(it has no {FOLDER_MANIFEST}\\)"):
        replace_folder(project, {"report.md": b"new"}, REPORT)
    assert {name: (project / name).read_bytes() for name in mine} == mine
    assert names(tmp_path) == ["myproject"]


def test_a_file_added_to_a_report_folder_is_never_deleted(tmp_path):
    folder = tmp_path / "report"
    replace_folder(folder, {"report.md": b"old"}, REPORT)
    (folder / "notes.txt").write_text("mine")
    with pytest.raises(ValueError, match=f"holds notes.txt, which sso did not write "
                       f"\\(they are not in its {FOLDER_MANIFEST}\\)"):
        replace_folder(folder, {"report.md": b"new"}, REPORT)
    assert (folder / "notes.txt").read_text() == "mine"
    assert (folder / "report.md").read_bytes() == b"old"


def test_a_folder_of_another_kind_is_not_replaced(tmp_path):
    folder = tmp_path / "paper_option1_paper"
    replace_folder(folder, {"sweep.csv": b"point\n0\n", "sweep.json": b"{}"}, "sweep")
    with pytest.raises(ValueError, match="holds a sweep written by sso: a case report and a "
                       "sweep never share a folder"):
        replace_folder(folder, {"report.md": b"new"}, REPORT)
    assert names(folder) == [FOLDER_MANIFEST, "sweep.csv", "sweep.json"]


def test_adopted_names_count_as_sso_files(tmp_path):
    (tmp_path / "result.json").write_bytes(b"{}")
    replace_folder(tmp_path / ".", {"result.json": b"{ }", "report.md": b"new"}, REPORT,
                   adopt=("result.json",))
    assert names(tmp_path) == ["report.md", "result.json", FOLDER_MANIFEST]


def test_a_manifest_that_is_not_sso_s_protects_nothing(tmp_path):
    (tmp_path / FOLDER_MANIFEST).write_text('{"written_by": "someone", "files": ["a.txt"]}')
    (tmp_path / "a.txt").write_text("mine")
    with pytest.raises(ValueError, match="holds a.txt, which sso did not write"):
        check_report_folder(tmp_path, REPORT)


def test_a_file_in_place_of_the_folder_is_refused(tmp_path):
    (tmp_path / "report").write_text("mine")
    with pytest.raises(ValueError, match="is a file, not a folder"):
        replace_folder(tmp_path / "report", {"report.md": b"new"}, REPORT)
    assert (tmp_path / "report").read_text() == "mine"


def test_a_linked_folder_has_its_files_replaced_in_the_link_s_target(tmp_path):
    target = tmp_path / "disk" / "report"
    replace_folder(target, {"report.md": b"old", "old.png": b"plot"}, REPORT)
    link = tmp_path / "report"
    link.symlink_to(target, target_is_directory=True)
    replace_folder(link, {"report.md": b"new"}, REPORT)
    assert link.is_symlink() and names(target) == ["report.md", FOLDER_MANIFEST]
    assert (target / "report.md").read_bytes() == b"new"
    assert listed(target)["files"] == ["report.md"]
    assert names(tmp_path) == ["disk", "report"] and names(tmp_path / "disk") == ["report"]


def test_the_working_folder_has_its_files_replaced_in_place(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    replace_folder(".", {"report.md": b"old"}, REPORT)
    before = os.stat(tmp_path).st_ino
    replace_folder(".", {"report.md": b"new"}, REPORT)
    assert os.stat(tmp_path).st_ino == before  # not renamed from under the process
    assert names(tmp_path) == ["report.md", FOLDER_MANIFEST]
    assert Path("report.md").read_bytes() == b"new"


MOUNTED = """
import sys
from pathlib import Path
from sso._files import replace_folder
folder = Path(sys.argv[1])
replace_folder(folder, {"report.md": b"old", "old.png": b"plot"}, "case report")
replace_folder(folder, {"report.md": b"new"}, "case report")
print(sorted(entry.name for entry in folder.iterdir()), (folder / "report.md").read_text(),
      sorted(entry.name for entry in folder.parent.iterdir()))
"""


def test_a_mount_point_has_its_files_replaced_in_place(tmp_path):
    # A real tmpfs mounted on the report folder, in a private mount namespace
    # (unshare: no privilege needed, nothing left mounted).
    folder = tmp_path / "mounted"
    folder.mkdir()
    try:
        probe = subprocess.run(["unshare", "-rm", "mount", "-t", "tmpfs", "none", str(folder)],
                               capture_output=True, timeout=30)
    except FileNotFoundError:
        pytest.skip("needs unshare")
    if probe.returncode != 0:
        pytest.skip("this system allows no private mount namespace")
    script = tmp_path / "mounted.py"
    script.write_text(MOUNTED)
    completed = subprocess.run(
        ["unshare", "-rm", "sh", "-c", 'mount -t tmpfs none "$1" && exec "$2" "$3" "$1"',
         "sh", str(folder), sys.executable, str(script)],
        capture_output=True, text=True, timeout=120,
        env={**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])})
    assert completed.returncode == 0, completed.stderr
    assert completed.stdout.split("\n")[0] == (
        f"['report.md', '{FOLDER_MANIFEST}'] new ['mounted', 'mounted.py']")


def test_a_path_too_long_for_the_system_is_refused_and_leaves_nothing(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(OSError, match="File name too long"):
        make_folders(Path(*["q"] * 2100))  # 4,199 characters
    assert names(tmp_path) == []
