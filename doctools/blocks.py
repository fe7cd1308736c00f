"""Run the code blocks of a Markdown page and compare what they print with the page.

A page is read as a notebook: its fenced blocks run in order, in one namespace, in a
working folder of their own that holds the repository's ``cases/``, ``sweeps/`` and the papers'
tables, ``tests/data/reference/`` (as a clone has them). What a block
means follows from its info string:

``python``
    Executed; ``__name__`` is ``"__main__"`` so guarded code runs too.
``output``
    What the block just above printed, exactly (a line may hold ``...``, which
    matches any text within that line, for values that change from run to run such
    as wall times). Numbers therefore match to the digits shown.
``console``
    Lines starting with ``$ `` are commands (``\\`` continues a line); the lines up to
    the next command are what it prints, compared as an ``output`` block is. The
    command must exit with status 0.
``bash``
    Commands without shown output. Every command must be of a known kind:
    ``sso``/``python -m sso`` commands are run, the others are checked as their kind
    allows (see :func:`classify`), and an unknown command fails.
``toml`` whose first line is ``# NAME.toml``
    Written to ``NAME.toml`` in the working folder, for the blocks after it.

Every other block (``text``, plain ``toml`` snippets, diagrams) is shown only.
"""

from __future__ import annotations

import argparse
import contextlib
import glob
import io
import os
import re
import shlex
import subprocess
import sys
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
FENCE = re.compile(r"^(?P<indent>[ \t]*)(?P<fence>`{3,}|~{3,})(?P<info>[^`\n]*)$")
FILE_BLOCK = re.compile(r"^#\s*(?P<name>[\w.-]+\.toml)\s*$")
RUN_LANGUAGES = ("python", "console", "bash")
# The repository's folders a page may read, linked into its working folder.
SHARED_FOLDERS = ("cases", "sweeps", "tests/data/reference")
ELLIPSIS = "..."


@dataclass
class Block:
    """One fenced code block of a Markdown page.

    Attributes
    ----------
    path : Path
        The page.
    line : int
        1-based line of the opening fence.
    language : str
        First word of the info string (``""`` if none).
    text : str
        The block's content, its indentation removed.
    output : Block or None
        The ``output`` block that follows it, if any.
    """

    path: Path
    line: int
    language: str
    text: str
    end_line: int
    output: Block | None = None

    @property
    def label(self) -> str:
        """``page.md:LINE``, relative to the repository root."""
        try:
            shown = self.path.resolve().relative_to(ROOT).as_posix()
        except ValueError:
            shown = self.path.name
        return f"{shown}:{self.line}"

    @property
    def runs(self) -> bool:
        """Whether the runner executes (or writes) this block."""
        return self.language in RUN_LANGUAGES or self.file_name is not None

    @property
    def file_name(self) -> str | None:
        """The file a ``toml`` block declares with its ``# NAME.toml`` first line."""
        if self.language != "toml":
            return None
        first = self.text.split("\n", 1)[0]
        match = FILE_BLOCK.match(first)
        return match.group("name") if match else None


def read_blocks(path: Path, text: str | None = None) -> list[Block]:
    """Every fenced block of the page at ``path``, with output blocks attached to their code."""
    lines = (path.read_text(encoding="utf-8") if text is None else text).split("\n")
    blocks: list[Block] = []
    index = 0
    while index < len(lines):
        match = FENCE.match(lines[index])
        if not match:
            index += 1
            continue
        indent, fence = len(match.group("indent")), match.group("fence")
        language = (match.group("info").strip().split() or [""])[0]
        body = []
        end = index + 1
        while end < len(lines) and not (lines[end].strip().startswith(fence)
                                         and not lines[end].strip().strip(fence[0])):
            body.append(lines[end][indent:] if lines[end][:indent].strip() == "" else lines[end])
            end += 1
        blocks.append(Block(path, index + 1, language, "\n".join(body), end + 1))
        index = end + 1
    attached: list[Block] = []
    for block in blocks:
        previous = attached[-1] if attached else None
        if (block.language == "output" and previous is not None
                and previous.language == "python" and previous.output is None
                and _only_blank_between(lines, previous.end_line, block.line)):
            previous.output = block
            continue
        attached.append(block)
    return attached


def _only_blank_between(lines: list[str], after: int, before: int) -> bool:
    return all(not line.strip() for line in lines[after:before - 1])


# ---------------------------------------------------------------- comparing output


def line_matches(expected: str, actual: str) -> bool:
    """Whether ``actual`` is ``expected`` with each ``...`` standing for any text.

    In a line with ``...``, runs of spaces count as one, so a table column whose
    value varies in width still matches.
    """
    expected, actual = expected.rstrip(), actual.rstrip()
    if ELLIPSIS not in expected:
        return expected == actual
    expected, actual = re.sub(" +", " ", expected), re.sub(" +", " ", actual)
    pattern = ".*".join(re.escape(part) for part in expected.split(ELLIPSIS))
    return re.fullmatch(pattern, actual) is not None


def output_matches(expected: str, actual: str) -> bool:
    """Whether ``actual`` matches ``expected`` line by line (trailing blank lines ignored)."""
    expected_lines = expected.rstrip("\n").split("\n") if expected.strip() else []
    actual_lines = actual.rstrip("\n").split("\n") if actual.strip() else []
    return len(expected_lines) == len(actual_lines) and all(
        line_matches(want, got) for want, got in zip(expected_lines, actual_lines, strict=True))


class OutputMismatch(AssertionError):
    """A block printed something other than what the page shows."""

    def __init__(self, block: Block, expected: str, actual: str) -> None:
        self.actual = actual
        super().__init__(f"{block.label}: the page shows\n{expected}\n--- the code printed\n"
                         f"{actual}")


# ---------------------------------------------------------------- shell commands


def _shell_commands(text: str) -> Iterator[str]:
    """The commands of a shell block: continuation lines joined, split at ``&&`` and ``;``."""
    joined = re.sub(r"\\\n\s*", " ", text)
    for line in joined.split("\n"):
        line = line.split(" #", 1)[0].strip() if not line.lstrip().startswith("#") else ""
        for command in re.split(r"&&|;", line):
            if command.strip():
                yield command.strip()


SSO_PROGRAMS = ("sso", ".venv/bin/sso")
PYTHONS = ("python", "python3", ".venv/bin/python")


def classify(command: str) -> str:
    """What kind of command a documented shell command is.

    Returns
    -------
    str
        ``"sso"`` (run by the runner), ``"install"`` (a virtual environment or a pip
        install: what ``.ci/run`` does on a fresh clone), ``"tests"`` (the test
        command itself), ``"benchmark"`` (a module of ``benchmarks/``: timing is not
        run in tests; the module must exist), ``"docs"`` (an ``mkdocs`` command: CI
        builds the site) or ``"unknown"``.
    """
    words = shlex.split(command)
    if not words:
        return "unknown"
    program, rest = words[0], words[1:]
    if program in SSO_PROGRAMS or (program in PYTHONS and rest[:2] == ["-m", "sso"]):
        return "sso"
    if program in PYTHONS and rest[:2] == ["-m", "venv"]:
        return "install"
    if program.endswith("pip") or (program in PYTHONS and rest[:2] == ["-m", "pip"]):
        return "install"
    if program in PYTHONS and rest[:2] == ["-m", "pytest"]:
        return "tests"
    if program in PYTHONS and rest and (rest[0].startswith("benchmarks/") or (
            rest[0] == "-m" and len(rest) > 1 and rest[1].startswith("benchmarks."))):
        return "benchmark"
    if program.endswith("mkdocs") or (program in PYTHONS and rest[:2] == ["-m", "mkdocs"]):
        return "docs"
    return "unknown"


def sso_arguments(command: str, folder: Path) -> list[str]:
    """The arguments after ``sso`` of an sso command, file patterns expanded in ``folder``."""
    words = shlex.split(command)
    words = words[3:] if words[0] in PYTHONS else words[1:]
    expanded: list[str] = []
    for word in words:
        if any(character in word for character in "*?["):
            matches = sorted(glob.glob(word, root_dir=folder))
            if not matches:
                raise AssertionError(f"{word!r} matches no file")
            expanded += matches
        else:
            expanded.append(word)
    return expanded


def benchmark_exists(command: str) -> bool:
    """Whether the benchmark a command names is in ``benchmarks/``."""
    words = shlex.split(command)[1:]
    target = words[1].replace(".", "/") + ".py" if words[0] == "-m" else words[0]
    return (ROOT / target).is_file()


# ---------------------------------------------------------------- running a page


@dataclass
class PageRun:
    """The state of one page while its blocks run: namespace and working folder."""

    path: Path
    folder: Path
    namespace: dict[str, Any] = field(default_factory=dict)
    done: int = 0

    def __post_init__(self) -> None:
        self.folder.mkdir(parents=True, exist_ok=True)
        for shared in SHARED_FOLDERS:
            link = self.folder / shared
            if not link.exists():
                link.parent.mkdir(parents=True, exist_ok=True)
                link.symlink_to(ROOT / shared, target_is_directory=True)
        self.namespace.update(__name__="__main__", __file__=str(self.folder / "page.py"))


@contextlib.contextmanager
def _inside(folder: Path) -> Iterator[None]:
    before = Path.cwd()
    os.chdir(folder)
    try:
        yield
    finally:
        os.chdir(before)


def run_sso(arguments: list[str], folder: Path, timeout_s: float = 600) -> tuple[int, str]:
    """Run ``python -m sso ARGUMENTS`` in ``folder``; exit status and standard output."""
    environment = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=os.pathsep.join(
        [str(ROOT), os.environ.get("PYTHONPATH", "")]).rstrip(os.pathsep))
    done = subprocess.run([sys.executable, "-m", "sso", *arguments], cwd=folder,
                          capture_output=True, text=True, timeout=timeout_s, env=environment)
    if done.returncode != 0:
        raise AssertionError(f"sso {' '.join(arguments)} exited {done.returncode}:\n"
                             f"{done.stdout}\n{done.stderr}")
    return done.returncode, done.stdout


def run_block(block: Block, run: PageRun) -> str:
    """Run one block in its page's state; what it printed (python, console) or ``""``.

    Raises
    ------
    AssertionError
        If the block fails, an output differs from the page, or a shell command is of
        no known kind.
    """
    if block.file_name is not None:
        (run.folder / block.file_name).write_text(block.text + "\n", encoding="utf-8")
        return ""
    if block.language == "python":
        return _run_python(block, run)
    if block.language == "console":
        return _run_console(block, run)
    if block.language == "bash":
        for command in _shell_commands(block.text):
            _check_command(block, command, run)
    return ""


def _run_python(block: Block, run: PageRun) -> str:
    captured = io.StringIO()
    code = compile(block.text, block.label, "exec")
    with _inside(run.folder), contextlib.redirect_stdout(captured):
        exec(code, run.namespace)  # noqa: S102 - the documentation's own examples
    printed = captured.getvalue()
    if block.output is not None and not output_matches(block.output.text, printed):
        raise OutputMismatch(block, block.output.text, printed)
    return printed


def _run_console(block: Block, run: PageRun) -> str:
    printed_all = []
    for command, expected in _console_steps(block.text):
        kind = classify(command)
        if kind != "sso":
            raise AssertionError(f"{block.label}: a console block runs sso commands only, "
                                 f"not {command!r}")
        _, printed = run_sso(sso_arguments(command, run.folder), run.folder)
        if not output_matches(expected, printed):
            raise OutputMismatch(block, expected, printed)
        printed_all.append(f"$ {command}\n{printed}")
    return "".join(printed_all)


def _console_steps(text: str) -> list[tuple[str, str]]:
    steps: list[tuple[str, list[str]]] = []
    lines = text.split("\n")
    index = 0
    while index < len(lines):
        line = lines[index]
        if line.startswith("$ "):
            command = line[2:]
            while command.endswith("\\") and index + 1 < len(lines):
                index += 1
                command = command[:-1] + " " + lines[index].strip()
            steps.append((command, []))
        elif steps:
            steps[-1][1].append(line)
        index += 1
    return [(command, "\n".join(output)) for command, output in steps]


def _check_command(block: Block, command: str, run: PageRun) -> None:
    kind = classify(command)
    if kind == "sso":
        run_sso(sso_arguments(command, run.folder), run.folder)
    elif kind == "benchmark":
        if not benchmark_exists(command):
            raise AssertionError(f"{block.label}: {command!r} names no benchmark")
    elif kind == "docs":
        if not (ROOT / "mkdocs.yml").is_file():
            raise AssertionError(f"{block.label}: {command!r} but no mkdocs.yml")
    elif kind in ("install", "tests"):
        pass  # exactly what .ci/run does on a fresh clone
    else:
        raise AssertionError(f"{block.label}: unknown command {command!r}; document it in "
                             "a text block or teach doctools.blocks.classify its kind")


# ---------------------------------------------------------------- updating a page


def updated_page(path: Path, folder: Path) -> str:
    """The page with every output (``output`` block, console output) as the code prints it now.

    A shown line that still matches (its ``...`` included) is kept as written.
    """
    text = path.read_text(encoding="utf-8")
    lines = text.split("\n")
    run = PageRun(path, folder)
    replacements: list[tuple[int, int, str]] = []
    for block in read_blocks(path, text):
        if not block.runs:
            continue
        if block.language == "python" and block.output is not None:
            try:
                printed = _run_python(block, run)
            except OutputMismatch as mismatch:
                printed = mismatch.actual
            new = _merge(block.output.text, printed)
            replacements.append((block.output.line, block.output.end_line, new))
        elif block.language == "console":
            pieces = []
            for command, expected in _console_steps(block.text):
                _, printed = run_sso(sso_arguments(command, run.folder), run.folder)
                pieces.append(f"$ {command}\n{_merge(expected, printed)}")
            replacements.append((block.line, block.end_line, "\n".join(pieces)))
        else:
            run_block(block, run)
    for start, end, new in reversed(replacements):
        indent = re.match(r"[ \t]*", lines[start - 1]).group(0)  # type: ignore[union-attr]
        body = [indent + line if line else line for line in new.rstrip("\n").split("\n")]
        lines[start:end - 1] = body
    return "\n".join(lines)


# What changes from run to run in sso's own output: the time column of a run summary
# (the number before the report folder) and a sweep's rate.
WALL_TIMES = (
    (re.compile(r"(?<= )\d+\.\d+(?= +results/)"), lambda found: ELLIPSIS.ljust(len(found))),
    (re.compile(r"computed in [\d.]+ s, [\d.]+ points/s"),
     lambda found: "computed in ... points/s"),
)


def with_wall_times_elided(line: str) -> str:
    """``line`` with every wall time of sso's output replaced by ``...``."""
    for pattern, replacement in WALL_TIMES:
        line = pattern.sub(lambda match, swap=replacement: swap(match.group(0)), line)
    return line


def _merge(expected: str, printed: str) -> str:
    """What the code printed, keeping each shown line (``...`` included) that still matches.

    Lines are paired in order, blank lines aside, so a shown ``...`` survives a blank
    line added or removed around it.
    """
    want = [line for line in expected.rstrip("\n").split("\n") if line.strip()]
    got = [with_wall_times_elided(line) for line in printed.rstrip("\n").split("\n")]
    if len(want) != sum(1 for line in got if line.strip()):
        return "\n".join(got)
    kept = iter(want)
    return "\n".join(line if not line.strip() else (
        old if line_matches(old := next(kept), line) else line) for line in got)


def main(arguments: list[str] | None = None) -> int:
    """``python -m doctools.blocks --update PAGE...``: rewrite the pages' shown output."""
    parser = argparse.ArgumentParser(description=main.__doc__)
    parser.add_argument("pages", nargs="+", type=Path)
    parser.add_argument("--update", action="store_true",
                        help="rewrite each page's shown output from what the code prints")
    options = parser.parse_args(arguments)
    import tempfile

    for page in options.pages:
        with tempfile.TemporaryDirectory() as folder:
            if options.update:
                page.write_text(updated_page(page, Path(folder)), encoding="utf-8")
                print(f"updated {page}")
            else:
                run = PageRun(page, Path(folder))
                for block in read_blocks(page):
                    if block.runs:
                        run_block(block, run)
                print(f"{page}: every block ran as shown")
    return 0


if __name__ == "__main__":
    sys.exit(main())
