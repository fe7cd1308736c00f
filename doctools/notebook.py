"""The downloadable notebook: a tutorial page written as a Jupyter notebook (nbformat 4).

Prose becomes Markdown cells, each ``python`` block a code cell, and the ``output``
block under it (checked against what the code prints by the tests) the cell's
output. Other blocks stay in the Markdown cells as shown. The notebook is generated
at each build from the page, so it cannot drift from the page the tests run.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from doctools.blocks import read_blocks

# Page (inside docs/) -> the notebook the site offers for download.
NOTEBOOKS = {"tutorials/steering-column.md": "tutorials/steering-column.ipynb"}


def _markdown_cell(lines: list[str]) -> dict[str, Any] | None:
    text = "\n".join(lines).strip("\n")
    if not text.strip():
        return None
    return {"cell_type": "markdown", "metadata": {}, "source": text.splitlines(keepends=True)}


def notebook(page: Path) -> dict[str, Any]:
    """The notebook of ``page`` as a JSON-ready dict."""
    lines = page.read_text(encoding="utf-8").split("\n")
    cells: list[dict[str, Any]] = []
    position = 0
    count = 0
    for block in read_blocks(page):
        if block.language != "python":
            continue
        prose = _markdown_cell(lines[position:block.line - 1])
        if prose:
            cells.append(prose)
        count += 1
        outputs = []
        end = block.end_line
        if block.output is not None:
            outputs.append({"output_type": "stream", "name": "stdout",
                            "text": (block.output.text + "\n").splitlines(keepends=True)})
            end = block.output.end_line
        cells.append({"cell_type": "code", "execution_count": count, "metadata": {},
                      "outputs": outputs, "source": block.text.splitlines(keepends=True)})
        position = end
    rest = _markdown_cell(lines[position:])
    if rest:
        cells.append(rest)
    return {
        "cells": cells,
        "metadata": {
            "kernelspec": {"display_name": "Python 3", "language": "python", "name": "python3"},
            "language_info": {"name": "python"},
        },
        "nbformat": 4,
        "nbformat_minor": 5,
    }


def notebook_text(page: Path) -> str:
    """The notebook of ``page`` as the ``.ipynb`` file's text."""
    return json.dumps(notebook(page), indent=1, ensure_ascii=False) + "\n"
