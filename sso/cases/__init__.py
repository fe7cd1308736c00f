"""Case files: the TOML schema and one module per case kind.

One module per job:

* :mod:`sso.cases.schema` reads and validates TOML case files into :class:`Case`;
* :mod:`sso.run.document` runs a case through the public API into a result document
  (the dictionary saved as ``result.json``);
* :mod:`sso.reports.writer` renders every other format from that document alone;
* :mod:`sso.files` writes files atomically.

Nothing here imports CasADi, SciPy or matplotlib at module level.
"""

# The planar-mechanism and 3D-column case kinds register themselves with
# sso.cases.schema on import.
from sso.cases import column as _column  # noqa: E402,F401
from sso.cases import mechanism as _mechanism  # noqa: E402,F401
