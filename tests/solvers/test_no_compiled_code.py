"""sso runs no compiler and loads no library of its own: nothing planted in a cache
folder, however it is named or whoever may write the folder, can run in its process.

Issue 33 asked that a planted, truncated or foreign library in a cache, a cache folder
others can write, and a compiler that never returns each end in the fallback or a clear
message. sso keeps no compiled code (docs/architecture.md, "The batch and compiled
code"): every solve runs CasADi's virtual machine. These tests hold that, through the
real command and the public API in fresh processes, with every such attack set up
around them at once.
"""

from __future__ import annotations

import hashlib
import os
import stat
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

# Names the removed cache gave its libraries and names a loader might look for.
PLANTED_NAMES = ("lm_native.so", "lm_batch.so", "lm_gauss_newton.so", "lm_newton.so",
                 "lm_shifted.so", "libsso.so", "sso_kernel.so")
TRUNCATED_ELF = b"\x7fELF\x02\x01\x01\x00" + b"\x00" * 8
"""The first bytes of a 64-bit ELF library and nothing more: a loader that opened it
would fail (the removed cache then ended every run with a bus error)."""
COMPILERS = ("cc", "gcc", "clang", "c++", "g++", "ld")
Snapshot = dict[str, tuple[str, int]]
"""A folder's files: name -> (sha256, mode)."""

PROGRAM = """
import pathlib, warnings
import numpy as np
import sso
warnings.simplefilter("ignore")
series = sso.ShaftSeries([30.0, 40.0, 40.0], [90.0, 90.0])
lm = sso.optimise(series, 3, beta_bounds_deg=(10.0, 40.0), solvers=("lm",), starts=1)
default = sso.optimise(series, 3, beta_bounds_deg=(10.0, 40.0))
rng = np.random.default_rng(5)
batch = sso.optimise_batch(rng.uniform(5.0, 35.0, (200, 3)), rng.uniform(0.0, 180.0, (200, 2)),
                           option=3, beta_bounds_deg=(5.0, 35.0))
maps = pathlib.Path("/proc/self/maps").read_text()
print(repr(lm.best.fun), repr(default.best.fun), int(np.count_nonzero(batch.success)))
print("MAPPED", [line.split()[-1] for line in maps.splitlines() if "planted" in line])
"""


def _plant(folder: Path) -> Snapshot:
    """The planted libraries in a folder anyone may write; their digests and modes."""
    folder.mkdir(parents=True)
    folder.chmod(0o777)
    for index, name in enumerate(PLANTED_NAMES):
        # A truncated library, a foreign one (another shape's bytes) and junk.
        data = TRUNCATED_ELF if index % 2 == 0 else os.urandom(4096)
        (folder / name).write_bytes(data)
    return _snapshot(folder)


def _snapshot(folder: Path) -> Snapshot:
    return {path.name: (hashlib.sha256(path.read_bytes()).hexdigest(),
                        stat.S_IMODE(path.stat().st_mode))
            for path in sorted(folder.iterdir())}


def _hanging_compilers(folder: Path, marker: Path) -> None:
    """Compiler commands that leave a marker and never return."""
    folder.mkdir()
    for name in COMPILERS:
        script = folder / name
        script.write_text(f"#!/bin/sh\necho \"$0 $*\" >> {marker}\nexec sleep 600\n")
        script.chmod(0o755)


def _environment(tmp_path: Path) -> tuple[dict[str, str], Path, dict[Path, Snapshot]]:
    marker = tmp_path / "compiler_ran.txt"
    compilers = tmp_path / "planted_bin"
    _hanging_compilers(compilers, marker)
    caches = (tmp_path / "planted_sso_cache", tmp_path / "planted_xdg" / "sso",
              tmp_path / "planted_home" / ".cache" / "sso")
    snapshots = {folder: _plant(folder) for folder in caches}
    environment = dict(os.environ)
    environment.update(
        SSO_CACHE_DIR=str(tmp_path / "planted_sso_cache"),
        XDG_CACHE_HOME=str(tmp_path / "planted_xdg"),
        HOME=str(tmp_path / "planted_home"),
        PATH=f"{compilers}{os.pathsep}{environment.get('PATH', '')}",
        CC=str(compilers / "cc"), CXX=str(compilers / "c++"),
        MPLBACKEND="Agg")
    return environment, marker, snapshots


def test_the_api_loads_nothing_planted_and_runs_no_compiler(tmp_path):
    environment, marker, snapshots = _environment(tmp_path)
    done = subprocess.run([sys.executable, "-c", PROGRAM], env=environment, cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    first, mapped = done.stdout.splitlines()[-2:]
    lm_fun, default_fun, batch_successes = first.split()
    # The README example reaches RE = 0 to round-off (docs/model.md, option 3).
    assert float(lm_fun) <= 1e-20 and float(default_fun) <= 1e-20
    assert int(batch_successes) >= 190  # nearly all of 200 random designs succeed
    assert mapped == "MAPPED []"
    assert not marker.exists()
    for folder, before in snapshots.items():
        assert _snapshot(folder) == before, f"{folder} was changed"


def test_the_command_loads_nothing_planted_and_runs_no_compiler(tmp_path):
    environment, marker, snapshots = _environment(tmp_path)
    done = subprocess.run([sys.executable, "-m", "sso", "run",
                           str(ROOT / "cases" / "paper_option3_exact.toml"), "--out",
                           str(tmp_path / "out"), "--no-plots", "--quiet"],
                          env=environment, cwd=tmp_path, capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    assert "Traceback" not in done.stderr
    assert (tmp_path / "out" / "paper_option3_exact" / "result.json").is_file()
    assert not marker.exists()
    for folder, before in snapshots.items():
        assert _snapshot(folder) == before, f"{folder} was changed"


def test_the_package_holds_no_c_source_no_library_and_no_code_generation():
    found = [path.relative_to(ROOT).as_posix() for path in (ROOT / "sso").rglob("*")
             if path.suffix in {".c", ".h", ".cpp", ".so", ".dylib", ".dll", ".pyd"}]
    assert found == []
    sources = list((ROOT / "sso").rglob("*.py"))
    assert len(sources) > 100  # the walk saw the package
    # CasADi's code generation, its loaders of compiled code, and running a program:
    # none is used (ctypes loads only the C library itself: malloc_trim, prctl).
    needles = ("casadi.external", "Importer(", "CodeGenerator", "generate(", "subprocess")
    offending = [(path.name, needle) for path in sources
                 for needle in needles if needle in path.read_text(encoding="utf-8")]
    assert offending == []
