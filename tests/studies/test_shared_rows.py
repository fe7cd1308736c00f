"""Number columns that another process writes in place (sso._studies.shared_rows).

Real processes and real memory: a process started by multiprocessing (not a fork of
this one, so it shares nothing with it but what it opens) writes a chunk's rows into
the anonymous memory file, and this process reads them back bit for bit.
"""

from __future__ import annotations

import dataclasses
import multiprocessing
import pickle
import sys

import numpy as np
import pytest

from sso._studies.columns import RowTable
from sso._studies.shared_rows import shared_columns, write_rows

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"),
                                reason="anonymous memory files are Linux's")

KINDS = {"point": (np.dtype(np.int64), ()), "residual_error": (np.dtype(float), ()),
         "design_beta_deg": (np.dtype(float), (3,))}
HEADER = ("point", "residual_error", "design_beta_deg", "status")


def chunk(first: int, rows: int) -> RowTable:
    status = np.empty(rows, dtype=object)
    status[:] = "ok"
    return RowTable(HEADER, {
        "point": np.arange(first, first + rows),
        "residual_error": np.linspace(-0.0, 1e-300, rows),
        "design_beta_deg": np.arange(3.0 * rows).reshape(rows, 3) / 7.0,
        "status": status}, rows)


def test_another_process_writes_a_chunk_in_place_and_only_text_is_left():
    shared = shared_columns(KINDS, 10)
    assert shared is not None
    table = chunk(100, 6)
    process = multiprocessing.get_context("spawn").Process(
        target=write_rows, args=(shared.layout, 4, table))
    process.start()
    process.join(timeout=120)
    assert process.exitcode == 0
    for name in KINDS:
        assert shared.arrays[name][4:10].tobytes() == table.columns[name].tobytes()
    assert not shared.arrays["point"][:4].any()  # rows of other chunks untouched
    rest = write_rows(shared.layout, 0, chunk(0, 4))
    assert rest is not None and set(rest.columns) == {"status"}
    shared.close()
    assert shared.arrays["point"].tolist() == [0, 1, 2, 3, *range(100, 106)]  # still mapped
    assert pickle.loads(pickle.dumps(shared.arrays["design_beta_deg"])).shape == (10, 3)


def test_a_chunk_of_other_columns_or_an_unreachable_memory_writes_nothing():
    shared = shared_columns(KINDS, 4)
    assert shared is not None
    text = chunk(0, 4)
    text.columns["residual_error"] = text.columns["residual_error"].astype(object)
    assert write_rows(shared.layout, 0, text) is None
    assert write_rows(shared.layout, 1, chunk(0, 4)) is None  # past the last row
    # Another file at the same process and descriptor numbers (another machine's):
    elsewhere = dataclasses.replace(shared.layout, name="sso-sweep-rows-elsewhere")
    assert write_rows(elsewhere, 0, chunk(0, 4)) is None
    gone = shared.layout
    shared.close()
    assert write_rows(gone, 0, chunk(0, 4)) is None  # the file is closed
    assert not shared.arrays["point"].any()
