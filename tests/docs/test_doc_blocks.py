"""Every code block of README.md and docs/ runs, and prints what the page shows.

Each runnable block (see doctools.blocks) is one test, named by its page and line.
The blocks of a page run in order in one namespace and one working folder, as a
reader running the page top to bottom would; a block selected alone runs the
blocks above it first. ``python -m doctools.blocks --update PAGE`` rewrites a
page's shown output from what the code prints now.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from doctools.blocks import ROOT, Block, PageRun, read_blocks, run_block

PAGES = [ROOT / "README.md", ROOT / "CONTRIBUTING.md", *sorted((ROOT / "docs").rglob("*.md"))]
BLOCKS = [block for page in PAGES for block in read_blocks(page) if block.runs]
_RUNS: dict[Path, tuple[PageRun, list[Block], set[int]]] = {}


def _page_state(block: Block, tmp_path_factory: pytest.TempPathFactory
                ) -> tuple[PageRun, list[Block], set[int]]:
    if block.path not in _RUNS:
        folder = tmp_path_factory.mktemp(block.path.stem)
        runnable = [each for each in read_blocks(block.path) if each.runs]
        _RUNS[block.path] = (PageRun(block.path, folder), runnable, set())
    return _RUNS[block.path]


@pytest.mark.parametrize("block", BLOCKS, ids=[block.label for block in BLOCKS])
def test_block_runs_and_prints_what_the_page_shows(block: Block,
                                                   tmp_path_factory: pytest.TempPathFactory):
    run, runnable, finished = _page_state(block, tmp_path_factory)
    for earlier in runnable:
        if earlier.line >= block.line:
            break
        if earlier.line not in finished:
            run_block(earlier, run)
            finished.add(earlier.line)
    run_block(block, run)
    finished.add(block.line)


def test_every_page_is_collected():
    # The pages the site builds from and the README: nothing under docs/ is skipped.
    assert ROOT / "README.md" in PAGES
    assert {page.name for page in PAGES} >= {"model.md", "column.md", "robust.md"}
