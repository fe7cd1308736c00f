"""Issue 34, items 1 and 2, reproduced as the issue writes them with the ``sso`` command
in real processes: a lock file that is a symbolic link to another file, and a folder
manifest (``sso-files.json``) that names a folder, a link or a path out of the folder.
Each ends in exit 2 with a message naming what is wrong, and the files aimed at keep
their bytes."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
CASE = ROOT / "cases" / "paper_option1_exact.toml"  # its case name: paper_option1_exact
NOTES = b"notes of another user\nnot to be overwritten\n"


def sso(*arguments: object, cwd: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "sso", *map(str, arguments)], cwd=cwd,
                          capture_output=True, text=True, timeout=600)


def sweep_file(folder: Path) -> Path:
    path = folder / "mysweep.toml"
    path.write_text(f'name = "mysweep"\ncase = "{CASE}"\naction = "evaluate"\n\n'
                    '[axes]\ninput_speed_rpm = [10, 20]\n')
    return path


@pytest.mark.parametrize("command", ["run", "sweep"])
def test_a_lock_file_that_is_a_link_is_refused_and_its_target_kept(tmp_path, command):
    notes = tmp_path / "notes.txt"
    notes.write_bytes(NOTES)
    out = tmp_path / "out"
    out.mkdir()
    name = "paper_option1_exact" if command == "run" else "mysweep"
    (out / f".sso-lock-{name}").symlink_to(notes)
    given = CASE if command == "run" else sweep_file(tmp_path)
    done = sso(command, given, "--out", out, "--no-plots", "--quiet",
               *(("--workers", 1) if command == "sweep" else ()), cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    assert "Traceback" not in done.stderr
    assert f"lock file {out / f'.sso-lock-{name}'}" in done.stderr
    assert f"is a symbolic link (to {notes})" in done.stderr
    assert notes.read_bytes() == NOTES
    assert (out / f".sso-lock-{name}").is_symlink()  # left as it was
    assert not (out / name).exists()  # nothing written


@pytest.mark.parametrize(("planted", "said"), [
    ("hard link", "a file with 2 names"),
    ("other contents", "holding something other than a pid"),
    ("folder", "is a folder"),
])
def test_a_lock_name_taken_by_anything_but_sso_s_lock_file_is_refused(tmp_path, planted, said):
    notes = tmp_path / "notes.txt"
    notes.write_bytes(NOTES)
    out = tmp_path / "out"
    out.mkdir()
    lock = out / ".sso-lock-paper_option1_exact"
    if planted == "hard link":
        os.link(notes, lock)
    elif planted == "other contents":
        lock.write_bytes(NOTES)
    else:
        lock.mkdir()
    done = sso("run", CASE, "--out", out, "--no-plots", "--quiet", cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    assert "Traceback" not in done.stderr
    assert said in done.stderr and "not a lock file sso made" in done.stderr
    assert notes.read_bytes() == NOTES
    assert not (out / "paper_option1_exact").exists()


def test_a_lock_file_of_a_killed_run_holding_its_pid_is_still_taken(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / ".sso-lock-paper_option1_exact").write_bytes(b"4194303\n")  # a dead owner's pid
    done = sso("run", CASE, "--out", out, "--no-plots", "--quiet", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert not (out / ".sso-lock-paper_option1_exact").exists()


@pytest.fixture
def report_folder(tmp_path):
    """A case's report folder written by ``sso run`` (manifest, result.json, reports)."""
    done = sso("run", CASE, "--out", tmp_path / "runs", "--no-plots", "--quiet",
               "--formats", "json,md", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    return tmp_path / "runs" / "paper_option1_exact"


def _list_in_manifest(folder: Path, name: str) -> None:
    manifest = folder / "sso-files.json"
    document = json.loads(manifest.read_text())
    manifest.write_text(json.dumps({**document, "files": [*document["files"], name]}))


def _snapshot(folder: Path) -> dict[str, bytes]:
    return {str(path.relative_to(folder)): path.read_bytes()
            for path in sorted(folder.rglob("*")) if path.is_file()}


@pytest.mark.parametrize(("folder", "said"), [
    ("sub", "lists 'sub', a name sso never writes"),
    ("plots.png", "plots.png is a folder, where sso writes a file plots.png into a case report"),
])
def test_a_manifest_naming_a_folder_deletes_nothing(report_folder, tmp_path, folder, said):
    # The reproduction: "sub" in the manifest, the user's sub/s.txt, then
    # sso report result.json --out (the same folder); and a folder under a name that
    # sso gives its files.
    (report_folder / folder).mkdir()
    (report_folder / folder / "s.txt").write_bytes(NOTES)
    _list_in_manifest(report_folder, folder)
    before = _snapshot(report_folder)
    done = sso("report", report_folder / "result.json", "--out", report_folder, cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    assert "Traceback" not in done.stderr
    assert said in done.stderr and "nothing was deleted" in done.stderr
    assert _snapshot(report_folder) == before


def test_a_manifest_naming_a_user_s_file_deletes_nothing(report_folder, tmp_path):
    (report_folder / "notes.txt").write_bytes(NOTES)
    _list_in_manifest(report_folder, "notes.txt")
    done = sso("report", report_folder / "result.json", "--out", report_folder, cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    assert "lists 'notes.txt', a name sso never writes (its files end in .json, .csv, .md, " \
           ".html, .png, .parquet)" in done.stderr
    assert (report_folder / "notes.txt").read_bytes() == NOTES


@pytest.mark.parametrize("entry", ["../notes.txt", "/etc/hostname", "sub/s.txt", os.pardir, ""])
def test_a_manifest_naming_a_path_out_of_the_folder_is_refused(report_folder, tmp_path,
                                                                entry):
    notes = tmp_path / "runs" / "notes.txt"
    notes.write_bytes(NOTES)
    _list_in_manifest(report_folder, entry)
    before = _snapshot(report_folder)
    done = sso("report", report_folder / "result.json", "--out", report_folder, cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    assert "Traceback" not in done.stderr
    assert f"lists {entry!r}, which is not a file name in the folder" in done.stderr
    assert _snapshot(report_folder) == before
    assert notes.read_bytes() == NOTES


def test_a_manifest_naming_a_link_deletes_nothing(report_folder, tmp_path):
    notes = tmp_path / "notes.txt"
    notes.write_bytes(NOTES)
    (report_folder / "link.md").symlink_to(notes)
    _list_in_manifest(report_folder, "link.md")
    done = sso("report", report_folder / "result.json", "--out", report_folder, cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    assert "link.md, which sso did not write" in done.stderr
    assert (report_folder / "link.md").is_symlink() and notes.read_bytes() == NOTES
