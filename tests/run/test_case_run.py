"""What every case run records besides its result: the versions and when.

Reference values: the installed distributions' own metadata (importlib.metadata) and
the version string CasADi's bundled IPOPT prints in its banner.
"""

from __future__ import annotations

import importlib.metadata
import platform
from datetime import UTC, datetime

import sso
from sso._run.case_run import created_utc, package_versions


def test_the_versions_are_the_installed_distributions():
    versions = package_versions()
    assert versions["python"] == platform.python_version()
    assert versions["sso"] == sso.__version__
    for name in ("casadi", "scipy", "numpy", "matplotlib"):
        assert versions[name] == importlib.metadata.version(name)


def test_the_ipopt_version_is_the_one_casadi_runs(capfd):
    import casadi

    x = casadi.SX.sym("x")
    solver = casadi.nlpsol("s", "ipopt", {"x": x, "f": (x - 1) ** 2})
    solver(x0=0.0)
    banner = capfd.readouterr().out
    assert f"Ipopt version {package_versions()['ipopt']}," in banner


def test_the_time_is_utc_to_the_second():
    stamp = datetime.fromisoformat(created_utc())
    assert stamp.tzinfo == UTC and stamp.microsecond == 0
    assert abs((datetime.now(UTC) - stamp).total_seconds()) < 60.0
