"""Issue 34, items 7 (second half) and 10: what went wrong said in the user's words,
exit 2, nothing of theirs changed. Each test is the issue's reproduction, run as the
``sso`` command in a real process on real files; the messages were before: a
``_csv.Error`` traceback, "File exists", "is a file, not a folder", "[Errno 17] File
exists", "[Errno 21] Is a directory" and "about 0 MB ... above the memory limit of 0
MB"."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
CASE = ROOT / "cases" / "paper_option1_exact.toml"


def sso(*arguments: object, cwd: Path) -> subprocess.CompletedProcess[str]:
    done = subprocess.run([sys.executable, "-m", "sso", *map(str, arguments)], cwd=cwd,
                          capture_output=True, text=True, timeout=600)
    assert "Traceback" not in done.stderr, done.stderr
    return done


@pytest.fixture
def swept(tmp_path):
    """A finished sweep of three points in ``tmp_path/out/s`` (with Parquet parts)."""
    pytest.importorskip("pyarrow")
    (tmp_path / "s.toml").write_text(f'name = "s"\ncase = "{CASE}"\naction = "evaluate"\n\n'
                                     "[axes]\ninput_speed_rpm = [10, 20, 30]\n")
    done = sso("sweep", "s.toml", "--out", "out", "--workers", 1, "--parquet", "--no-plots",
               "--quiet", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    return tmp_path / "out" / "s"


def resume(folder: Path, *extra: str) -> subprocess.CompletedProcess[str]:
    return sso("sweep", "s.toml", "--out", "out", "--workers", 1, "--resume", "--no-plots",
               "--quiet", *extra, cwd=folder.parents[1])


def test_resume_with_a_cell_longer_than_131072_characters_names_the_file_and_line(swept):
    csv_path = swept / "sweep.csv"
    lines = csv_path.read_bytes().split(b"\n")
    cells = lines[2].split(b",")
    cells[-2] = b"x" * 140_000  # the warnings cell of point 1, on line 3
    lines[2] = b",".join(cells)
    csv_path.write_bytes(b"\n".join(lines))
    before = csv_path.read_bytes()
    done = resume(swept)
    assert done.returncode == 2
    assert done.stderr == (f"error: s.toml: resume: {Path('out/s/sweep.csv')} line 3 holds a "
                           "cell longer than 131,072 characters, which sso never writes: the "
                           "file is damaged or not this sweep's; use another out_dir, or "
                           "delete the folder to run the sweep afresh\n")
    assert csv_path.read_bytes() == before


def test_sweep_parquet_replaced_by_a_file_is_named(swept):
    parts = swept / "sweep.parquet"
    for part in parts.iterdir():
        part.unlink()
    parts.rmdir()
    parts.write_bytes(b"my own file\n")
    for extra in (("--parquet",), ()):
        done = resume(swept, *extra)
        assert done.returncode == 2
        assert done.stderr == (f"error: s.toml: {Path('out/s')}: sweep.parquet is a file where "
                               "sso writes a folder of that name; nothing was deleted. Choose "
                               "another folder (--out), or move it out\n")
        assert parts.read_bytes() == b"my own file\n"


def test_sweep_csv_replaced_by_a_folder_is_named(swept):
    (swept / "sweep.csv").unlink()
    (swept / "sweep.csv").mkdir()
    (swept / "sweep.csv" / "mine.txt").write_bytes(b"kept\n")
    done = resume(swept)
    assert done.returncode == 2
    assert done.stderr == (f"error: s.toml: {Path('out/s')}: sweep.csv is a folder, where sso "
                           "writes a file sweep.csv into a sweep (sso-files.json lists that "
                           "name); sso deletes only the regular files it writes; nothing was "
                           "deleted. Choose another folder (--out), or move it out\n")
    assert (swept / "sweep.csv" / "mine.txt").read_bytes() == b"kept\n"


def test_out_on_a_loop_of_symbolic_links_says_so(tmp_path):
    (tmp_path / "loop").symlink_to("loop")
    said = "loop is a symbolic link that leads nowhere (a loop of links), not a folder"
    done = sso("run", CASE, "--out", "loop", "--no-plots", "--quiet", cwd=tmp_path)
    assert done.returncode == 2
    assert done.stderr == ("error: paper_option1_exact: cannot write the report into "
                           f"{Path('loop/paper_option1_exact')}: {said}; choose a folder\n")
    assert sso("run", CASE, "--out", tmp_path / "out", "--no-plots", "--quiet", "--formats",
               "json", cwd=tmp_path).returncode == 0
    result = tmp_path / "out" / "paper_option1_exact" / "result.json"
    done = sso("report", result, "--out", "loop", cwd=tmp_path)
    assert done.returncode == 2
    assert done.stderr == (f"error: {result}: cannot write the report: {said}; choose a "
                           "folder for the case report\n")
    assert (tmp_path / "loop").is_symlink() and str((tmp_path / "loop").readlink()) == "loop"


@pytest.mark.parametrize("command", ["sweep", "tolerance"])
def test_a_memory_limit_of_0_0001_mb_is_said_as_given_with_what_the_work_needs(tmp_path,
                                                                               command):
    (tmp_path / "s.toml").write_text(f'name = "s"\ncase = "{CASE}"\naction = "evaluate"\n\n'
                                     "[axes]\ninput_speed_rpm = [10, 20, 30]\n")
    given = "s.toml" if command == "sweep" else CASE
    done = sso(command, given, "--memory-limit", "0.0001", "--workers", 1, "--no-plots",
               "--quiet", cwd=tmp_path)
    assert done.returncode == 2
    assert "above the memory limit of 0.0001 MB (the limit is in MB: 4,096, the default, " \
           "is 4 GB)" in done.stderr
    assert "raise the limit to at least " in done.stderr
    assert "about 0 MB" not in done.stderr and "of 0 MB" not in done.stderr
    assert not (tmp_path / "results").exists()
