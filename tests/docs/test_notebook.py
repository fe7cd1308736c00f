"""The downloadable notebook is the tutorial page, cell for cell."""

from __future__ import annotations

import json

from doctools.blocks import ROOT, read_blocks
from doctools.notebook import NOTEBOOKS, notebook_text


def test_each_notebook_has_the_pages_code_and_output_in_order():
    for page in NOTEBOOKS:
        path = ROOT / "docs" / page
        document = json.loads(notebook_text(path))
        assert document["nbformat"] == 4
        code = [cell for cell in document["cells"] if cell["cell_type"] == "code"]
        blocks = [block for block in read_blocks(path) if block.language == "python"]
        assert ["".join(cell["source"]) for cell in code] == [block.text for block in blocks]
        for cell, block in zip(code, blocks, strict=True):
            shown = block.output.text + "\n" if block.output else None
            assert ("".join(cell["outputs"][0]["text"]) if cell["outputs"] else None) == shown
        prose = "".join("".join(cell["source"]) for cell in document["cells"]
                        if cell["cell_type"] == "markdown")
        assert prose.startswith("# ")
