"""MkDocs hooks of the sso site (named in ``mkdocs.yml``).

* ``on_config``: every public name of ``sso.__all__`` (and every public method of a
  public class) must have a docstring; each one missing is a warning, which the
  strict build (``mkdocs build --strict``, as CI runs it) turns into a failure.
* ``on_files``: adds the generated pages and files: one API page per public name and
  the API index, the case-file reference (from the case schema), the concept figures
  and the downloadable notebook.
* ``on_page_markdown``: fills the Performance page and the Sweeps at scale page from
  their recorded benchmark runs (``doctools.performance``, ``doctools.scaling``);
  runs every code block of a tutorial page and stops the build if one raises or
  prints other than the page shows (set ``SSO_DOCS_RUN_TUTORIALS=0`` to skip this
  while previewing).
"""

from __future__ import annotations

import logging
import os
import sys
import tempfile
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from mkdocs.exceptions import PluginError  # noqa: E402
from mkdocs.structure.files import File, Files  # noqa: E402

from doctools import (  # noqa: E402
    api_pages,
    blocks,
    case_reference,
    figures,
    notebook,
    performance,
    scaling,
)

log = logging.getLogger("mkdocs.hooks.sso")
TUTORIALS = "tutorials/"
PERFORMANCE = "performance.md"
SCALING = "scaling.md"


def on_config(config: Any) -> Any:
    """Check every public docstring, and list every API page in the navigation.

    A public name without a docstring is a warning (a failure in a strict build).
    The API entry of the navigation (``reference/api/index.md``) becomes a section
    holding the index and one page per public name.
    """
    for name in api_pages.missing_docstrings():
        log.warning("%s has no docstring: every public name needs one", name)
    config["nav"] = _with_api_pages(config["nav"])
    return config


def _with_api_pages(nav: Any) -> Any:
    index = f"{api_pages.API_FOLDER}/index.md"
    if isinstance(nav, list):
        return [_with_api_pages(item) for item in nav]
    if isinstance(nav, dict):
        return {title: ([index, *({f"sso.{public.name}": public.page}
                                  for public in api_pages.public_names())]
                        if value == index else _with_api_pages(value))
                for title, value in nav.items()}
    return nav


def on_files(files: Files, config: Any) -> Files:
    """Add the generated pages, figures and notebook to the site."""
    for public in api_pages.public_names():
        files.append(File.generated(config, public.page, content=api_pages.page(public)))
    files.append(File.generated(config, f"{api_pages.API_FOLDER}/index.md",
                                content=api_pages.index_page()))
    files.append(File.generated(config, "reference/case-files.md",
                                content=case_reference.page()))
    for name, image in figures.all_figures().items():
        files.append(File.generated(config, f"{figures.FOLDER}/{name}", content=image))
    for page, target in notebook.NOTEBOOKS.items():
        source = Path(config["docs_dir"]) / page
        files.append(File.generated(config, target, content=notebook.notebook_text(source)))
    return files


def on_page_markdown(markdown: str, page: Any, config: Any, files: Files) -> str:
    """Fill the Performance and Sweeps at scale pages from their recorded runs; run a
    tutorial page's blocks.

    A tutorial block that fails or prints other than the page shows stops the build.
    """
    if page.file.src_uri == PERFORMANCE:
        return performance.page_with_section(markdown, performance.load())
    if page.file.src_uri == SCALING:
        return scaling.page_with_section(markdown, scaling.load())
    if not page.file.src_uri.startswith(TUTORIALS) or os.environ.get(
            "SSO_DOCS_RUN_TUTORIALS", "1") == "0":
        return markdown
    path = Path(page.file.abs_src_path)
    with tempfile.TemporaryDirectory() as folder:
        run = blocks.PageRun(path, Path(folder))
        for block in blocks.read_blocks(path, markdown):
            if not block.runs:
                continue
            try:
                blocks.run_block(block, run)
            except BaseException as error:  # any failure of the example stops the build
                raise PluginError(f"tutorial {block.label} failed: {error}") from error
    return markdown
