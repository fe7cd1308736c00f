"""The distribution that installs the ``sso`` package: its name and its version.

The import name is ``sso``; the distribution is published under a different,
unambiguous name, because ``sso`` is taken on the public package index.
"""

DISTRIBUTION_NAME = "shaft-series-optimisation"

VERSION = "0.1.0"
"""The package's version (``sso.__version__``); the build reads it from here."""


def installed_version() -> str:
    """Version of the installed distribution.

    Returns
    -------
    str
        The version recorded in the installed distribution's metadata, or
        :data:`VERSION` when the package runs from a source tree that is not
        installed (the two agree when it is: the build reads :data:`VERSION`).
    """
    from importlib import metadata  # 0.1 s to import: only when asked

    try:
        return metadata.version(DISTRIBUTION_NAME)
    except metadata.PackageNotFoundError:
        return VERSION
