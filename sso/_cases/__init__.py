"""Case files: the TOML schema engine and one module per case kind.

* :mod:`sso._cases.schema` reads a TOML case file and checks every key against the
  schema of its ``kind`` (messages with line numbers and "did you mean");
* :mod:`sso._cases.shaft_series` is the shaft-series kind (:class:`Case`);
* :mod:`sso._cases.mechanism` is the planar-mechanism kinds, one per registered
  linkage, and the four-bar design.

Importing this package registers every kind. Nothing here imports CasADi, SciPy or
matplotlib at module level.
"""

# Each kind registers itself with sso._cases.schema when its module is imported.
from sso._cases import column as _column  # noqa: F401
from sso._cases import mechanism as _mechanism  # noqa: F401
from sso._cases import shaft_series as _shaft_series  # noqa: F401
