"""What every case run records besides its result: its warnings, the package versions
and when (:class:`CaseRun`, the base of every case run's result)."""

from __future__ import annotations

import importlib.util
import platform
import re
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path

from sso._display import Readable
from sso._distribution import distribution_version, installed_version
from sso._record import Record

VERSIONED_PACKAGES = ("casadi", "scipy", "numpy", "matplotlib")


@dataclass(frozen=True, eq=False, repr=False, kw_only=True)
class CaseRun(Record, Readable):
    """What every case run's result records besides its case and its result.

    Attributes
    ----------
    warnings : tuple of str
        The case's and the run's warnings, each once.
    versions : dict of str to str
        Python, sso, CasADi, IPOPT, SciPy, NumPy, matplotlib.
    created_utc : str
        When the run ended (ISO 8601, UTC).
    """

    warnings: tuple[str, ...]
    versions: dict[str, str]
    created_utc: str


def package_versions() -> dict[str, str]:
    """Versions of Python, sso, CasADi, its bundled IPOPT, SciPy, NumPy and matplotlib.

    Read from the installed distributions' metadata, so nothing is imported.
    """
    versions = {"python": platform.python_version(), "sso": installed_version()}
    for package in VERSIONED_PACKAGES:
        versions[package] = distribution_version(package) or "not installed"
    versions["ipopt"] = bundled_ipopt_version()
    return versions


def bundled_ipopt_version() -> str:
    """Version of the IPOPT library bundled with CasADi, read from its files.

    CasADi ships IPOPT's ``IpoptConfig.h`` (``#define IPOPT_VERSION "x.y.z"``) and
    ``libipopt.so.x.y.z``; neither needs CasADi to be imported.
    """
    spec = importlib.util.find_spec("casadi")
    if spec is None or not spec.submodule_search_locations:
        return "unknown: casadi is not installed"
    folder = Path(list(spec.submodule_search_locations)[0])
    header = folder / "include" / "coin-or" / "IpoptConfig.h"
    if header.is_file():
        found = re.search(r'#define\s+IPOPT_VERSION\s+"([^"]+)"',
                          header.read_text(errors="replace"))
        if found:
            return found.group(1)
    for library in sorted(folder.glob("libipopt*")):
        found = re.search(r"(\d+\.\d+\.\d+)", library.name)
        if found:
            return found.group(1)
    return "unknown: no IPOPT version found in casadi's files"


def created_utc() -> str:
    """The time now, UTC, to the second (ISO 8601), as a run records it."""
    return datetime.now(UTC).isoformat(timespec="seconds")
