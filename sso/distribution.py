"""The distribution that installs the ``sso`` package: its name and its version.

The import name is ``sso``; the distribution is published under a different,
unambiguous name, because ``sso`` is taken on the public package index.
"""

from importlib import metadata

import sso

DISTRIBUTION_NAME = "shaft-series-optimisation"


def installed_version() -> str:
    """Version of the installed distribution.

    Returns
    -------
    str
        The version recorded in the installed distribution's metadata, or
        ``sso.__version__`` when the package runs from a source tree that is not
        installed (the two agree when it is: the build reads ``sso.__version__``).
    """
    try:
        return metadata.version(DISTRIBUTION_NAME)
    except metadata.PackageNotFoundError:
        return sso.__version__
