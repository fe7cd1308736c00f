"""The link checker of the built site finds broken internal links, anchors and images."""

from __future__ import annotations

from doctools.linkcheck import broken_links, main


def _site(tmp_path):
    (tmp_path / "guide").mkdir()
    (tmp_path / "index.html").write_text(
        '<html><body><h1 id="top">sso</h1>'
        '<a href="guide/">guide</a> <a href="guide/index.html#usage">usage</a>'
        '<a href="#top">top</a> <a href="https://example.org/x">out</a>'
        '<img src="figures/a.png"></body></html>')
    (tmp_path / "figures").mkdir()
    (tmp_path / "figures" / "a.png").write_bytes(b"\x89PNG")
    (tmp_path / "guide" / "index.html").write_text(
        '<html><body><h2 id="usage">Usage</h2><a href="../index.html">home</a></body></html>')
    return tmp_path


def test_a_whole_site_has_no_broken_link(tmp_path):
    assert broken_links(_site(tmp_path)) == []
    assert main([str(tmp_path)]) == 0


def test_missing_page_anchor_and_image_are_each_reported(tmp_path):
    site = _site(tmp_path)
    (site / "guide" / "index.html").write_text(
        '<html><body><a href="../missing.html">x</a><a href="../index.html#nowhere">y</a>'
        '<img src="../figures/b.png"><a href="../../outside.html">z</a></body></html>')
    assert broken_links(site) == [
        "guide/index.html: ../missing.html (no such file)",
        "guide/index.html: ../index.html#nowhere (no anchor #nowhere)",
        "guide/index.html: ../figures/b.png (no such file)",
        "guide/index.html: ../../outside.html (outside the site)",
        "index.html: guide/index.html#usage (no anchor #usage)",
    ]
    assert main([str(site)]) == 1


def test_an_empty_folder_is_not_a_site(tmp_path):
    assert main([str(tmp_path)]) == 1
