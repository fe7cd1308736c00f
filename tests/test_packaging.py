"""The package as a published distribution: name, licence, type marker, entry points."""

import subprocess
import sys
import tomllib
from importlib import metadata
from pathlib import Path

import sso
from sso._distribution import DISTRIBUTION_NAME, distribution_version, installed_version

ROOT = Path(__file__).resolve().parents[1]
PROJECT = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))


def test_distribution_name_differs_from_the_import_name_and_is_the_one_installed():
    # "sso" on the public package index is an unrelated package (checked when the
    # name was chosen); the import name stays sso.
    assert PROJECT["project"]["name"] == DISTRIBUTION_NAME == "shaft-series-optimisation"
    assert PROJECT["project"]["scripts"] == {"sso": "sso._cli:main"}
    version = PROJECT["tool"]["setuptools"]["dynamic"]["version"]
    assert version == {"attr": "sso._distribution.VERSION"}


def test_installed_version_is_the_package_version():
    try:
        recorded = metadata.version(DISTRIBUTION_NAME)
    except metadata.PackageNotFoundError:
        recorded = None  # running from a source tree that is not installed
    assert installed_version() == (recorded or sso.__version__) == sso.__version__


def test_the_version_read_from_the_metadata_headers_is_the_full_parses():
    # reference: importlib.metadata's own e-mail parse of each installed distribution
    names = {distribution.metadata["Name"] for distribution in metadata.distributions()}
    assert len(names) > 20
    for name in sorted(names):
        assert distribution_version(name) == metadata.version(name), name
    assert distribution_version("no-such-distribution-sso-test") is None


def test_licence_type_marker_and_urls_ship():
    licence = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert licence.startswith("MIT License\n\nCopyright (c) 2026 the sso developers\n")
    assert PROJECT["project"]["license"] == "MIT"
    assert PROJECT["project"]["license-files"] == ["LICENSE"]
    assert (ROOT / "sso" / "py.typed").is_file()
    assert "py.typed" in PROJECT["tool"]["setuptools"]["package-data"]["sso"]
    assert set(PROJECT["project"]["urls"]) >= {"Homepage", "Documentation", "Issues"}
    assert "Typing :: Typed" in PROJECT["project"]["classifiers"]


def test_python_m_sso_is_the_sso_command(tmp_path):
    version = subprocess.run([sys.executable, "-m", "sso", "--version"], cwd=tmp_path,
                             capture_output=True, text=True, timeout=60, check=False)
    assert version.returncode == 0, version.stderr
    assert version.stdout.strip() == f"sso {sso.__version__}"
    bad = subprocess.run([sys.executable, "-m", "sso", "fly"], cwd=tmp_path,
                         capture_output=True, text=True, timeout=60, check=False)
    assert bad.returncode == 2
    assert "invalid choice: 'fly'" in bad.stderr and "Traceback" not in bad.stderr


def test_readme_quick_start_installs_and_tests_as_ci_does():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    assert ('python3 -m venv .venv && .venv/bin/pip install -e ".[test,dask,parquet]" && '
            ".venv/bin/sso run cases/paper_option3_exact.toml") in readme
    assert "python3 -m venv .venv\n" in ci
    assert '.venv/bin/pip install --quiet -e ".[test,dask,parquet]"\n' in ci
    assert readme.count("\n.venv/bin/python -m pytest -q\n") == 1
    assert ci.endswith("\n.venv/bin/python -m pytest -q\n")
