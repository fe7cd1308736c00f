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
    return distribution_version(DISTRIBUTION_NAME) or VERSION


def distribution_version(name: str) -> str | None:
    """Version of the installed distribution ``name``; None if it is not installed (or
    its metadata records no version).

    The ``Version`` field of its core metadata, as ``importlib.metadata.version`` gives
    it, read from the metadata's header lines alone: the e-mail parse of the whole file
    (numpy's and matplotlib's carry their long description, tens of kilobytes) took a
    few milliseconds a package at every ``sso run``.
    """
    from importlib import metadata

    try:
        distribution = metadata.distribution(name)
    except metadata.PackageNotFoundError:
        return None
    text = distribution.read_text("METADATA") or distribution.read_text("PKG-INFO") or ""
    for line in text.splitlines():
        if not line.strip():
            break  # the end of the header lines
        field, _, value = line.partition(":")
        if field.strip().lower() == "version":
            return value.strip()
    return None
