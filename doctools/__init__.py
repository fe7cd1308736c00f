"""Tools that build and check the documentation site (not part of the sso package).

``hooks`` is the MkDocs hook module named in ``mkdocs.yml``; the other modules each
do one job: the Markdown code-block runner (``blocks``), the API and case-file
reference pages (``api_pages``, ``case_reference``), the concept figures
(``figures``), the downloadable notebook (``notebook``) and the link checker of the
built site (``linkcheck``).
"""
