"""``sso run`` of a shaft-series case loads only the modules that case needs.

Each module an ``sso run`` process imports is paid at every cold start (the
performance target "sso run --no-plots cold start <= 1.5x bare casadi +
scipy.optimize imports", ``benchmarks/cold_start.py``). These tests run the real
command in a fresh process and list what it imported; each module guarded here was
once on this path and is not needed by it, for the reason given beside it.
"""

import gc
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from sso._cli import main
from sso._cli.app import COMMAND_GC_THRESHOLD
from sso._cli.solve import _interruption_behind
from sso._interrupts import Interrupted

CASES = Path(__file__).resolve().parents[2] / "cases"
CASE = CASES / "paper_option3_exact.toml"
MECHANISM_ANALYSIS = CASES / "mechanisms" / "fourbar_crank2.toml"
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
    # sweeps and tolerance studies
    "sso._studies": "sso sweep and sso tolerance only",
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


def test_a_command_run_in_process_gives_back_the_callers_collector_thresholds(tmp_path):
    # main() raises the youngest generation's threshold while a command runs and must
    # leave the settings of a caller that runs it in its own process as it found them
    before = gc.get_threshold()
    try:
        gc.set_threshold(1234, 11, 12)
        assert main(["evaluate", str(CASE), "--out", str(tmp_path), "--quiet",
                     "--no-plots"]) == 0
        assert gc.get_threshold() == (1234, 11, 12)
    finally:
        gc.set_threshold(*before)


COUNTING = """
import gc, sys
import sso._cli.app as app
app.COMMAND_GC_THRESHOLD = int(sys.argv[1])
collections = [0, 0, 0]
gc.callbacks.append(lambda phase, info: phase == "start"
                    and collections.__setitem__(info["generation"],
                                                collections[info["generation"]] + 1))
code = app.main(sys.argv[2:])
print("COLLECTIONS=" + ",".join(map(str, collections)))
sys.exit(code)
"""


def collections_of_run(threshold: int, folder: Path) -> list[int]:
    """Collections of each generation while ``sso run --no-plots`` of the case runs
    in a fresh process, the command's threshold set to ``threshold``."""
    completed = subprocess.run(
        [sys.executable, "-c", COUNTING, str(threshold), "run", str(CASE), "--out",
         str(folder), "--quiet", "--no-plots"],
        capture_output=True, text=True, timeout=300, cwd=folder)
    assert completed.returncode == 0, completed.stdout + completed.stderr
    counted = re.search(r"^COLLECTIONS=(.*)$", completed.stdout, re.MULTILINE)
    assert counted, completed.stdout
    return [int(count) for count in counted.group(1).split(",")]


def test_a_cold_run_collects_far_less_often_than_at_pythons_default(tmp_path):
    # benchmarks/cold_start.py: at Python's default of 700 the collections were about
    # 6% of the run's CPU time, most of them walking the namespaces of modules being
    # imported
    default = collections_of_run(700, tmp_path)
    raised = collections_of_run(COMMAND_GC_THRESHOLD, tmp_path)
    assert default[0] >= 50  # the imports of CasADi, SciPy and sso allocate that much
    assert sum(raised) <= sum(default) / 5


IMPORT_STACK = """
import json, sys, traceback
from sso._cli import main
stacks = []


def hook(event, arguments):
    if event == "import" and arguments[0] == "scipy.optimize" \
            and "scipy.optimize" not in sys.modules:
        stacks.append([frame.name for frame in traceback.extract_stack()])


sys.addaudithook(hook)
code = main(sys.argv[1:])
print("STACKS=" + json.dumps(stacks))
sys.exit(code)
"""


def test_scipy_is_imported_before_the_solve_near_the_top_of_the_stack(tmp_path):
    # Imported inside the solve (sso/_solvers/slsqp.py), SciPy's import made CPython 3.11
    # free and map again one 16 KiB chunk of its frame stack about 15,000 times (strace:
    # 15,094 munmap calls of 16384 bytes; 14,000 page faults, a tenth of the run's CPU
    # time; CPython issue gh-142183): sso run imports it first, a few calls below main()
    completed = subprocess.run(
        [sys.executable, "-c", IMPORT_STACK, "run", str(CASE), "--out", str(tmp_path),
         "--quiet", "--no-plots"], capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert completed.returncode == 0, completed.stdout + completed.stderr
    stacks = json.loads(re.search(r"^STACKS=(.*)$", completed.stdout, re.MULTILINE).group(1))
    (stack,) = stacks
    assert "import_solvers_for" in stack
    assert "solve" not in stack and "run_parsed_case" not in stack


def test_a_mechanism_analysis_imports_no_solver_library(tmp_path):
    # an analysis runs no solver: sso run must not import SciPy or CasADi for it
    completed = subprocess.run(
        [sys.executable, "-c", WRAPPER, "run", str(MECHANISM_ANALYSIS), "--out", str(tmp_path),
         "--quiet", "--no-plots"], capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert completed.returncode == 0, completed.stdout + completed.stderr
    modules = set(json.loads(re.search(r"^MODULES=(.*)$", completed.stdout,
                                       re.MULTILINE).group(1)))
    assert "sso._run.mechanism_run" in modules
    assert not {"scipy", "casadi"} & modules


def test_an_interruption_behind_an_extension_modules_import_error_is_found():
    # pybind11 turns an exception raised while a module initialises (a signal's
    # Interrupted during SciPy's HiGHS bindings) into ImportError("initialization failed")
    try:
        try:
            raise Interrupted("signal 15")
        except Interrupted as interrupted:
            raise ImportError("initialization failed") from interrupted
    except ImportError as error:
        found = _interruption_behind(error)
    assert isinstance(found, Interrupted) and str(found) == "signal 15"
    looped = ImportError("no interruption")
    looped.__context__ = ValueError("its context")
    looped.__context__.__context__ = looped
    assert _interruption_behind(looped) is None
