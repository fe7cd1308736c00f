"""sweep.parquet: a part per chunk, one schema, read back by pandas as the rows of the sweep.

Reference: the sweep's own rows (``result.rows``, which ``sweep.csv`` holds too); the
Parquet parts must hold the same values, column for column.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import sso
from sso._studies.element_columns import gathered
from sso._studies.parquet_output import PARQUET_NAME
from sso._studies.table import read_rows

pandas = pytest.importorskip("pandas")
pytest.importorskip("pyarrow")

BASE = {"design": {"beta_deg": [30.0, 40.0, 40.0], "phase_deg": [90.0, 90.0]},
        "bounds": {"beta_deg": [10.0, 40.0]}, "option": 3,
        "solver": {"solvers": ["lm"], "starts": 1}}
AXES = {"design.beta_deg[0]": {"start": 10.0, "stop": 40.0, "num": 6},
        "design.beta_deg[1]": [12.0, 95.0, 30.0]}  # 95 deg: refused, an error row


def test_parts_hold_the_rows_and_the_frame_reads_them(tmp_path):
    result = sso.sweep(BASE, AXES, out_dir=tmp_path, workers=1, chunk_size=5, plots=False,
                       parquet=True)
    parts = sorted((tmp_path / PARQUET_NAME).iterdir())
    assert len(parts) == 4  # 18 points in chunks of 5
    frame = result.frame()
    assert list(frame["point"]) == list(range(18))
    assert list(frame.columns) == list(result.rows[0])
    np.testing.assert_array_equal(frame["residual_error"].to_numpy(dtype=float),
                                  [np.nan if row["residual_error"] is None
                                   else row["residual_error"] for row in result.rows])
    assert list(frame["status"]) == [row["status"] for row in result.rows]
    assert frame["error"][1].startswith("CaseError: point 1: design.beta_deg[1] = 95")
    assert [frame[f"design_beta_deg[{k}]"][0] for k in range(3)] == \
        gathered(result.rows[0], "design_beta_deg")
    assert frame["design_phase_deg[1]"].dtype == float
    assert frame["success"][0] is True or bool(frame["success"][0]) is True
    assert len(read_rows(tmp_path / "sweep.csv")) == 18


def test_a_resumed_sweep_rewrites_its_own_parts_only_once(tmp_path):
    axes = {"design.beta_deg[0]": {"start": 10.0, "stop": 40.0, "num": 12}}
    sso.sweep(BASE, axes, out_dir=tmp_path, workers=1, chunk_size=4, plots=False, parquet=True,
              action="evaluate")
    # As a killed run leaves it: the last chunk's rows and part are missing.
    csv_path = tmp_path / "sweep.csv"
    lines = csv_path.read_text().splitlines(keepends=True)
    csv_path.write_text("".join(lines[:-4]))
    last = sorted((tmp_path / PARQUET_NAME).iterdir())[-1]
    last.unlink()
    resumed = sso.sweep(BASE, axes, out_dir=tmp_path, workers=1, chunk_size=4, plots=False,
                        resume=True, action="evaluate")
    assert resumed.resumed == 8 and resumed.computed == 4
    names = sorted(path.name for path in (tmp_path / PARQUET_NAME).iterdir())
    assert len(names) == 2 and names[0].endswith("-resumed.parquet")
    frame = resumed.frame()
    assert list(frame["point"]) == list(range(12))
    np.testing.assert_allclose(frame["residual_error"].to_numpy(dtype=float),
                               [row["residual_error"] for row in resumed.rows], rtol=0, atol=0)


def test_a_foreign_file_in_the_parts_folder_is_refused(tmp_path):
    (tmp_path / PARQUET_NAME).mkdir()
    (tmp_path / PARQUET_NAME / "mine.parquet").write_bytes(b"x")
    with pytest.raises(ValueError, match="holds sweep.parquet, which sso did not write"):
        sso.sweep(BASE, {"design.beta_deg[0]": [10.0]}, out_dir=tmp_path, workers=1,
                  plots=False, parquet=True, action="evaluate")
    assert (tmp_path / PARQUET_NAME / "mine.parquet").read_bytes() == b"x"


def test_sso_sweep_parquet_from_the_command_line(tmp_path):
    (tmp_path / "s.toml").write_text(
        'name = "p"\naction = "evaluate"\n[case.design]\nbeta_deg = [20.0, 30.0]\n'
        '[axes]\n"design.beta_deg[0]" = [10.0, 20.0, 30.0]\n')
    done = subprocess.run([sys.executable, "-m", "sso._cli", "sweep", "s.toml", "--parquet",
                           "--no-plots", "--workers", "1"], cwd=tmp_path, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    frame = pandas.read_parquet(tmp_path / "results" / "p" / PARQUET_NAME)
    assert sorted(frame["point"]) == [0, 1, 2]
