"""``report.html``: the report blocks as one self-contained HTML page.

Images are embedded as base64 data URIs; an interactive 3D view carries its own
renderer inline (:mod:`sso._reports.view3d`), so the page asks no host for anything;
every string is passed through :func:`html.escape`. Each table sits in a box that scrolls sideways
(``overflow-x: auto``), so a wide table never widens the page.
"""

from __future__ import annotations

import base64
import html
from collections.abc import Mapping, Sequence

from sso._reports.summary import Block, Heading, Image, Paragraph, Scene, Table

STYLE = """
body { font-family: system-ui, sans-serif; max-width: 70rem; margin: 2rem auto; padding: 0 1rem;
       color: #222; }
.table { overflow-x: auto; margin: 0.5rem 0 1rem; }
table { border-collapse: collapse; }
th, td { border: 1px solid #bbb; padding: 0.25rem 0.6rem; text-align: left; vertical-align: top; }
th { background: #eee; }
td { font-variant-numeric: tabular-nums; }
figure { margin: 1rem 0; }
img { max-width: 100%; height: auto; border: 1px solid #ddd; }
"""


def render_html(blocks: Sequence[Block], images: Mapping[str, bytes]) -> str:
    """HTML text of the report.

    Parameters
    ----------
    blocks : sequence of Block
        The report content.
    images : mapping of str to bytes
        PNG bytes of each image block's file.
    """
    title = next((block.text for block in blocks if isinstance(block, Heading)), "SSO report")
    body = []
    style = STYLE
    for block in blocks:
        if isinstance(block, Heading):
            body.append(f"<h{block.level}>{_escape(block.text)}</h{block.level}>")
        elif isinstance(block, Paragraph):
            body.append(f"<p>{_escape(block.text)}</p>")
        elif isinstance(block, Table):
            header = "".join(f"<th>{_escape(cell)}</th>" for cell in block.header)
            rows = "".join("<tr>" + "".join(f"<td>{_escape(cell)}</td>" for cell in row) + "</tr>"
                           for row in block.rows)
            body.append(f'<div class="table"><table><thead><tr>{header}</tr></thead>'
                        f"<tbody>{rows}</tbody></table></div>")
        elif isinstance(block, Image):
            data = base64.b64encode(images[block.file_name]).decode("ascii")
            body.append(f'<figure><img src="data:image/png;base64,{data}" '
                        f'alt="{_escape(block.caption)}"><figcaption>{_escape(block.caption)}'
                        "</figcaption></figure>")
        elif isinstance(block, Scene):
            from sso._reports.view3d import VIEW_STYLE, scene_html

            style = STYLE + VIEW_STYLE
            body.append(scene_html(block.scene, block.caption, f"sso-view-{len(body)}"))
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<title>{_escape(title)}</title>\n<style>{style}</style>\n</head>\n<body>\n"
            + "\n".join(body) + "\n</body>\n</html>\n")


def _escape(text: str) -> str:
    return html.escape(text, quote=True)
