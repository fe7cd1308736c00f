"""The repository stands alone: no file reads or names a path outside it.

A clone with nothing beside it must install, run its cases and pass its tests, so no
tracked text file may point above the repository root (a ``../`` path that climbs out,
a parent-folder path component in quotes), name the project's former neighbour folder, or
name an absolute path on a developer's machine.
"""

import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = next(folder for folder in Path(__file__).resolve().parents
            if (folder / "pyproject.toml").is_file())
SKIPPED_FOLDERS = {".git", ".venv", "__pycache__", ".pytest_cache", ".hypothesis",
                   "build", "results", ".mypy_cache", ".ruff_cache"}
PARENT = "." * 2
# Built from pieces so that this file does not name what it looks for.
NEIGHBOUR = re.compile(re.escape(PARENT + "/" + "shared") + r"|(?<![\w/.-])shared/"
                       r"(?:spec|reference|seeds)\b" + r"|/\s*[\"']" + "shared" + r"[\"']")
ABSOLUTE = re.compile(r"(?<![\w.~-])/(?:" + "work" + r"|home|root)/")
CLIMB = re.compile(r"(?<![\w.])(?:\.\./)+[\w.-]*")
QUOTED_PARENT = re.compile("[\"']" + re.escape(PARENT) + "[\"']")
FILE_ANCESTOR = re.compile(r"__file__\)(?:\.resolve\(\)|\.absolute\(\))?\.parents\[(\d+)\]")


def repository_files(root: Path) -> list[Path]:
    """Tracked and untracked (not ignored) files of ``root``; a plain walk without git."""
    if (root / ".git").exists() and shutil.which("git"):
        listing = subprocess.run(
            ["git", "-C", str(root), "ls-files", "--cached", "--others", "--exclude-standard",
             "-z"], capture_output=True, check=True).stdout.decode()
        return sorted(root / name for name in listing.split("\0")
                      if name and (root / name).is_file())
    return sorted(path for path in root.rglob("*") if path.is_file()
                  and not SKIPPED_FOLDERS & set(path.relative_to(root).parts)
                  and not any(part.endswith(".egg-info") for part in path.parts))


def _text(path: Path) -> str | None:
    data = path.read_bytes()
    if b"\0" in data[:8192]:
        return None
    return data.decode("utf-8", errors="replace")


def _climbs_out(root: Path, path: Path, relative: str) -> bool:
    target = (path.parent / relative).resolve()
    return not target.is_relative_to(root.resolve())


def outside_references(root: Path) -> list[str]:
    """Every line of a text file under ``root`` that reads or names a path outside it.

    Returns
    -------
    list of str
        ``"file:line: reason: text"``, one per offending match; empty when clean.
    """
    found = []
    for path in repository_files(root):
        text = _text(path)
        if text is None:
            continue
        name = path.relative_to(root).as_posix()
        for number, line in enumerate(text.splitlines(), start=1):
            reasons = []
            if NEIGHBOUR.search(line):
                reasons.append("names the folder beside the repository")
            if ABSOLUTE.search(line):
                reasons.append("names an absolute path on a machine")
            if any(_climbs_out(root, path, match.group()) for match in CLIMB.finditer(line)):
                reasons.append("a relative path climbs above the repository root")
            if path.suffix == ".py" and QUOTED_PARENT.search(line):
                reasons.append("joins a parent-folder path component")
            depth = len(path.relative_to(root).parts)
            if any(int(match.group(1)) >= depth for match in FILE_ANCESTOR.finditer(line)):
                reasons.append("an ancestor of __file__ lies above the repository root")
            found.extend(f"{name}:{number}: {reason}: {line.strip()}" for reason in reasons)
    return found


def test_no_file_reads_or_names_a_path_outside_the_repository():
    assert outside_references(ROOT) == []


def test_the_scan_finds_paths_planted_in_a_copy(tmp_path):
    copy = tmp_path / "copy"
    for path in repository_files(ROOT):
        target = copy / path.relative_to(ROOT)
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(path, target)
    # The copy has no .git folder: this also runs the plain walk, which must agree.
    assert outside_references(copy) == []

    planted = {
        "tests/planted_neighbour.py":
            "TABLE = 'tests/" + PARENT + "/" + PARENT + "/shared/x.csv'\n",
        "docs/planted_absolute.md": "See /" + "work/notes/model.md for details.\n",
        "planted_climb.toml": 'case = "' + PARENT + '/elsewhere/case.toml"\n',
        "sso/planted_join.py": "FOLDER = HERE / '" + PARENT + "' / 'data'\n",
        "tests/planted_join.py": "TABLES = ROOT.parent / 'shar" + "ed' / 'reference'\n",
        "tests/kinematics/planted_ancestor.py": "DATA = Path(__" + "file__).resolve().parents[3]\n",
    }
    for name, text in planted.items():
        (copy / name).parent.mkdir(parents=True, exist_ok=True)
        (copy / name).write_text(text, encoding="utf-8")
    found = outside_references(copy)
    assert {line.split(":")[0] for line in found} == set(planted)
    assert any("folder beside" in line for line in found)
    assert any("absolute path" in line for line in found)
    assert any("climbs above" in line for line in found)
    assert any("parent-folder path component" in line for line in found)
    assert any("ancestor of __file__" in line for line in found)


@pytest.mark.parametrize("line", ["18.17 .. 34.40 rpm", "benchmarks/work_precision.py",
                                  'name = "../escape"', "docs/../README.md"])
def test_paths_inside_the_repository_pass(tmp_path, line):
    (tmp_path / "pyproject.toml").write_text("", encoding="utf-8")
    (tmp_path / "tests").mkdir()
    (tmp_path / "tests" / "case.md").write_text(line + "\n", encoding="utf-8")
    assert outside_references(tmp_path) == []
