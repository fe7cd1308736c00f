"""The API reference covers the public API: a page and a docstring for every name of sso.__all__."""

from __future__ import annotations

import sso
from doctools import api_pages


def test_every_public_name_has_a_page_pointing_at_its_definition():
    names = api_pages.public_names()
    assert [public.name for public in names] == list(sso.__all__)
    pages = [public.page for public in names]
    assert len(set(pages)) == len(pages)  # no two names share a page
    for public in names:
        text = api_pages.page(public)
        assert f"# sso.{public.name}\n" in text
        assert f"::: {public.target}\n" in text
        module_name, _, attribute = public.target.rpartition(".")
        module = __import__(module_name, fromlist=[attribute])
        assert getattr(module, attribute) is getattr(sso, public.name)


def test_index_links_every_page():
    index = api_pages.index_page()
    for public in api_pages.public_names():
        link = public.page.removeprefix(api_pages.API_FOLDER + "/")
        assert f"[`sso.{public.name}`]({link})" in index


def test_every_public_name_and_method_has_a_docstring():
    assert api_pages.missing_docstrings() == []


def test_a_missing_docstring_is_found(monkeypatch):
    # The check the strict build relies on finds a public function without a docstring.
    def undocumented() -> None:
        pass

    monkeypatch.setattr(sso, "__all__", [*sso.__all__, "undocumented_example"])
    monkeypatch.setattr(sso, "undocumented_example", undocumented, raising=False)
    assert api_pages.missing_docstrings() == ["sso.undocumented_example"]
