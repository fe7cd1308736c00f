"""Case files: the TOML schema engine and one module per case kind.

* :mod:`sso._cases.schema` reads a TOML case file and checks every key against the
  schema of its ``kind`` (messages with line numbers and "did you mean");
* :mod:`sso._cases.shaft_series` is the shaft-series kind (:class:`Case`);
* :mod:`sso._cases.column` is the steering-column kind;
* :mod:`sso._cases.mechanism` is the planar-mechanism kinds, one per registered
  linkage, and the four-bar design.

Each kind registers itself when its module is imported, and a case imports only the
module of its own kind (:data:`sso._cases.schema.KIND_MODULES`); importing this
package imports none of them. Nothing here imports CasADi, SciPy or matplotlib at
module level.
"""
