"""README.md is a front door: short, and every link in it and in CONTRIBUTING.md leads somewhere."""

from __future__ import annotations

import re

import pytest

from doctools.blocks import ROOT

MAX_README_LINES = 250  # issue 26: the README is the front door, the site holds the rest
LINK = re.compile(r"\]\(([^)\s]+)\)")


def test_readme_is_at_most_250_lines():
    assert len((ROOT / "README.md").read_text(encoding="utf-8").splitlines()) <= MAX_README_LINES


@pytest.mark.parametrize("page", ["README.md", "CONTRIBUTING.md"])
def test_every_relative_link_points_at_a_file_in_the_repository(page):
    text = (ROOT / page).read_text(encoding="utf-8")
    targets = [link for link in LINK.findall(text) if "://" not in link]
    assert targets, page
    for link in targets:
        path = link.split("#", 1)[0]
        assert (ROOT / path).is_file(), f"{page}: {link}"


def test_readme_links_into_every_part_of_the_site():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    for part in ("docs/getting-started.md", "docs/concepts/", "docs/tutorials/",
                 "docs/guide/", "docs/performance.md", "docs/references.md"):
        assert f"]({part}" in text, part
