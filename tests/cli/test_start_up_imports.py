"""``sso run`` of a shaft-series case loads only the modules that case needs.

Each module an ``sso run`` process imports is paid at every cold start (the
performance target "sso run --no-plots cold start <= 1.5x bare casadi +
scipy.optimize imports", ``benchmarks/cold_start.py``). These tests run the real
command in a fresh process and list what it imported; each module guarded here was
once on this path and is not needed by it, for the reason given beside it.
"""

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

CASE = Path(__file__).resolve().parents[2] / "cases" / "paper_option3_exact.toml"
# Runs the real command in this process and prints every module it imported.
WRAPPER = """
import json, sys
from sso._cli import main
code = main(sys.argv[1:])
print("MODULES=" + json.dumps(sorted(sys.modules)))
sys.exit(code)
"""
NEVER_ON_A_SHAFT_SERIES_RUN = {
    # pyarrow and pandas: only sweeps' --parquet and SweepResult.frame() read or write them
    "pyarrow": "parquet output only",
    "pandas": "parquet output and SweepResult.frame() only",
    # dask: only sweeps and tolerance studies on a Dask cluster
    "dask": "Dask sweeps only",
    "distributed": "Dask sweeps only",
    # each case kind's modules are imported for a case of that kind only
    # (sso._cases.schema.KIND_MODULES; the column stack was most of sso's own imports)
    "sso._cases.column": "column cases only",
    "sso._column": "column cases only",
    "sso._run.column": "column cases only",
    "sso._cases.mechanism": "mechanism cases only",
    "sso._linkages": "mechanism cases only",
    "sso._run.mechanism_run": "mechanism cases only",
    # sweeps and tolerance studies, and the compiled batch kernel of optimise_batch
    "sso._studies": "sso sweep and sso tolerance only",
    "sso._solvers.lm_native": "optimise_batch only",
}


def modules_of_run(*arguments: str, folder: Path) -> set[str]:
    """Every module ``sso run CASE --out folder *arguments`` imported; it must succeed."""
    completed = subprocess.run(
        [sys.executable, "-c", WRAPPER, "run", str(CASE), "--out", str(folder), "--quiet",
         *arguments], capture_output=True, text=True, timeout=300, cwd=folder)
    assert completed.returncode == 0, completed.stdout + completed.stderr
    listed = re.search(r"^MODULES=(.*)$", completed.stdout, re.MULTILINE)
    assert listed, completed.stdout
    return set(json.loads(listed.group(1)))


def loaded_from(modules: set[str], packages: dict[str, str]) -> dict[str, str]:
    """The guarded packages (or any module inside them) found among ``modules``."""
    return {package: reason for package, reason in packages.items()
            if any(name == package or name.startswith(package + ".") for name in modules)}


@pytest.mark.parametrize("plots", [False, True], ids=["no-plots", "plots"])
def test_a_shaft_series_run_imports_no_other_kind_and_no_optional_library(tmp_path, plots):
    # the README's first command runs this case with plots; the cold-start target without
    modules = modules_of_run(*([] if plots else ["--no-plots"]), folder=tmp_path)
    # the run did solve: the solvers and the shaft-series run are loaded
    assert {"casadi", "scipy.optimize", "sso._run.shaft_series", "sso._solvers.slsqp"} <= modules
    assert loaded_from(modules, NEVER_ON_A_SHAFT_SERIES_RUN) == {}
    # matplotlib draws the plots and nothing else: --no-plots never imports it
    assert ("matplotlib" in modules) is plots
