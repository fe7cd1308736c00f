"""Check the built site: every internal link and image points at a file (and anchor) that exists.

``python -m doctools.linkcheck SITE`` reads every HTML file under ``SITE`` and
reports each ``href``/``src`` that points inside the site at a missing file or at a
missing ``id`` on an existing page; it exits 1 when it finds any. Links to other
hosts (``http:``, ``https:``, ``mailto:``) are not followed: the check is of the
site itself. The theme's ``404.html`` is served at whatever address was not found,
so its links are written from the site's root and are not checked here.
"""

from __future__ import annotations

import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

EXTERNAL_SCHEMES = ("http", "https", "mailto", "data", "javascript", "tel")
NOT_FOUND_PAGE = "404.html"


class _Page(HTMLParser):
    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.links: list[str] = []
        self.ids: set[str] = set()

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        values = dict(attrs)
        for name in ("id", "name"):
            if values.get(name) and (name == "id" or tag == "a"):
                self.ids.add(str(values[name]))
        for name in ("href", "src"):
            value = values.get(name)
            if value and not (tag == "link" and values.get("rel") in ("preconnect",)):
                self.links.append(value)


def _parse(path: Path) -> _Page:
    page = _Page()
    page.feed(path.read_text(encoding="utf-8", errors="replace"))
    return page


def broken_links(site: Path) -> list[str]:
    """Every broken internal link of the site under ``site``, as ``page: link (why)``."""
    site = site.resolve()
    pages = {path: _parse(path) for path in sorted(site.rglob("*.html"))}
    broken = []
    for path, page in pages.items():
        if path == site / NOT_FOUND_PAGE:
            continue
        for link in page.links:
            parts = urlsplit(link)
            if parts.scheme in EXTERNAL_SCHEMES or parts.netloc:
                continue
            target = path if not parts.path else (path.parent / unquote(parts.path)).resolve()
            if target.is_dir():
                target = target / "index.html"
            where = f"{path.relative_to(site)}: {link}"
            if not target.is_relative_to(site):
                broken.append(f"{where} (outside the site)")
            elif not target.is_file():
                broken.append(f"{where} (no such file)")
            elif parts.fragment and target.suffix == ".html":
                ids = pages[target].ids if target in pages else _parse(target).ids
                if unquote(parts.fragment) not in ids:
                    broken.append(f"{where} (no anchor #{parts.fragment})")
    return broken


def main(arguments: list[str] | None = None) -> int:
    """Check the site folder given as the one argument; exit 1 if any link is broken."""
    site = Path((arguments if arguments is not None else sys.argv[1:])[0])
    pages = list(site.rglob("*.html"))
    if not pages:
        print(f"{site}: no HTML page to check", file=sys.stderr)
        return 1
    broken = broken_links(site)
    for line in broken:
        print(line)
    print(f"{len(pages)} pages checked, {len(broken)} broken internal links")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
