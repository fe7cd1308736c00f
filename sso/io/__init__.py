"""Files in and out: case files, result JSON, CSV, Markdown/HTML reports and plots.

One module per job:

* :mod:`sso.io.case` reads and validates TOML case files into :class:`Case`;
* :mod:`sso.io.document` runs a case through the public API into a result document
  (the dictionary saved as ``result.json``);
* :mod:`sso.io.report` renders every other format from that document alone;
* :mod:`sso.io.atomic` writes files atomically.

Nothing here imports CasADi, SciPy or matplotlib at module level.
"""

# The planar-mechanism case kinds register themselves with sso.io.case on import.
from sso.io import mechanism_case as _mechanism_case  # noqa: E402,F401
