"""The Sweeps at scale page: its measured section comes from the recorded benchmark run,
its projection re-derives from that run's raw passes, and the figures its prose
states are the package's own constants."""

from __future__ import annotations

import copy
import re
import statistics
from pathlib import Path

import pytest

from benchmarks import sweep_throughput
from doctools import scaling
from sso._studies.axes import MAX_POINTS
from sso._studies.report import MOST_DRAWN_POINTS, REPORT_ROWS
from sso._studies.sweep import (
    ARRAY_CHUNK_CAP,
    ARRAY_CHUNK_FLOOR,
    ARRAY_CHUNKS_PER_WORKER,
    ARRAY_SHARE,
    DASK_CHUNK_FLOOR,
    DASK_EVALUATE_CHUNK_CAP,
    _chunk_sizes,
    array_chunk_rule,
)
from sso._studies.worker_memory import KEPT_FREE_BYTES

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "scaling.md"
NUMBER_WORDS = {8: "eighth"}
SHARE_WORDS = {1: "a whole", 2: "half a"}


@pytest.fixture(scope="module")
def document():
    return scaling.load()


def test_the_recorded_run_is_the_full_benchmark_with_identical_rows(document):
    assert document["settings"]["optimise_per_axis"] == sweep_throughput.OPTIMISE_PER_AXIS == 47
    assert document["settings"]["evaluate_per_axis"] == sweep_throughput.EVALUATE_PER_AXIS == 100
    assert document["optimise"]["runs"][scaling.ONE]["points"] == 47**3
    assert document["evaluate"]["runs"][scaling.ONE]["points"] == 100**3
    assert document["optimise"]["identical_rows"] and document["evaluate"]["identical_rows"]
    assert document["on_disk"]["points"] == 100**3
    assert document["load_before"]["cpu_count"] >= 1  # the load is recorded with the ratios


def test_the_page_shows_the_recorded_ratios_and_load(document):
    page = scaling.page_with_section(PAGE.read_text(encoding="utf-8"), document)
    assert scaling.MARKER not in page
    for action in ("optimise", "evaluate"):
        for figures in document[action]["runs"].values():
            assert f"| {figures['ratio_to_one_process']:.2f} |" in page
    assert str(document["load_before"]["load_average_1_5_15_min"]) in page
    assert "Sweeps at scale: scaling.md" in (ROOT / "mkdocs.yml").read_text(encoding="utf-8")


@pytest.mark.parametrize("machines", scaling.MACHINES)
def test_the_projection_follows_from_the_raw_passes(document, machines):
    # Recomputed here from each pass's rate, not from the run's own medians.
    for action in ("optimise", "evaluate"):
        runs = document[action]["runs"]
        one = statistics.median(run["points_per_s"] for run in runs[scaling.ONE]["passes"])
        dask = statistics.median(run["points_per_s"] for run in runs[scaling.DASK]["passes"])
        efficiency = min(1.0, dask / one / 2)
        hours = 1e9 / (machines * 32 * one * efficiency) / 3600
        figures = scaling.projection(document, action, machines)
        assert figures["compute_hours"] == pytest.approx(hours, rel=1e-12)
        assert figures["tasks"] == 1e9 / ARRAY_CHUNK_CAP


def test_the_page_gives_what_a_task_takes_at_the_recorded_rates(document):
    # Recomputed here from the recorded one-process rates and the recorded chunk sizes.
    evaluate_s = 1.0 / document["evaluate"]["runs"][scaling.ONE]["median_points_per_s"]
    optimise_s = 1.0 / document["optimise"]["runs"][scaling.ONE]["median_points_per_s"]
    assert (document["chunks"]["most_points"], document["chunks"]["fewest_points"]) == (
        ARRAY_CHUNK_CAP, ARRAY_CHUNK_FLOOR)
    page = " ".join(scaling.page_with_section(PAGE.read_text(encoding="utf-8"),
                                              document).split())
    assert (f"({evaluate_s * 1e6:.2f} us a point evaluating, {optimise_s * 1e6:.2f} us "
            f"optimising), a task of the most points ({ARRAY_CHUNK_CAP:,}) takes "
            f"{ARRAY_CHUNK_CAP * evaluate_s:.2f} s of evaluating or "
            f"{ARRAY_CHUNK_CAP * optimise_s:.2f} s of optimising, and one of the fewest "
            f"({ARRAY_CHUNK_FLOOR:,}) {ARRAY_CHUNK_FLOOR * evaluate_s * 1e3:.1f} ms or "
            f"{ARRAY_CHUNK_FLOOR * optimise_s * 1e3:.1f} ms") in page
    assert "what a task of either size takes at the rates of the latest run" in page


def test_writing_sweep_csv_is_slower_than_evaluating_in_the_recorded_run(document):
    # The prose says so; the recorded run must show it (and the page gives both rates).
    in_memory = document["evaluate"]["runs"][scaling.ONE]["median_points_per_s"]
    assert scaling.written_rate(document) < in_memory
    page = scaling.page_with_section(PAGE.read_text(encoding="utf-8"), document)
    assert (f"it ran at {scaling.written_rate(document):,.0f} points/s, against "
            f"{in_memory:,.0f} in memory") in " ".join(page.split())


def test_a_sweep_holds_the_bytes_a_point_the_page_states():
    # The rows a sweep's process holds are its columns: their bytes per point, on small
    # sweeps of the benchmark's case ("lm", one start), are those of any sweep of it.
    import sso

    held = {}
    for action in ("optimise", "evaluate"):
        result = sso.sweep(sweep_throughput.base_document(), sweep_throughput.grid(4),
                           action=action, workers=1, progress=False)
        table = result.rows.table
        held[action] = sum(column.nbytes for column in table.columns.values()) / table.length
    text = " ".join(PAGE.read_text(encoding="utf-8").split())
    assert (f"as columns of {held['optimise']:.0f} bytes a point optimising the shipped case "
            f"({held['evaluate']:.0f} evaluating), so a sweep of 10^6 points holds "
            f"{held['optimise'] * 1e6 / 1e9:.1f} GB") in text


def test_the_prose_states_the_package_constants():
    text = " ".join(PAGE.read_text(encoding="utf-8").split())
    assert f"up to about {scaling.TASK_OVERHEAD_S * 1e3:g} ms a task" in text
    assert f"keep up to {KEPT_FREE_BYTES // 2**20} MB it frees" in text
    assert f"at most {ARRAY_CHUNK_CAP:,} points" in text
    assert f"{SHARE_WORDS[ARRAY_SHARE]} worker's share of the points not yet cut" in text
    assert f"at least {ARRAY_CHUNK_FLOOR:,}" in text
    assert (f"the tasks are longer: at least {DASK_CHUNK_FLOOR['optimise']:,} optimised "
            f"points or {DASK_CHUNK_FLOOR['evaluate']:,} evaluated ones, and an evaluate task "
            f"up to {DASK_EVALUATE_CHUNK_CAP:,} points") in text
    assert f"each round {SHARE_WORDS[ARRAY_SHARE].replace(' a', '')} of the points left" in text
    for action, points, pool, dask in (("optimise", 103_823, 13, 6),
                                       ("evaluate", 1_000_000, 32, 12)):
        assert len(_chunk_sizes(None, points, 2, True)) == pool
        assert len(_chunk_sizes(None, points, 2, True, *array_chunk_rule(True, action))) == dask
    rounds = _chunk_sizes(None, 103_823, 2, True, *array_chunk_rule(True, "optimise"))[::2]
    assert ("into 6 tasks on 2 Dask workers (rounds of {:,}, {:,} and {:,} points a task), 13 "
            "in the pool".format(*rounds)) in text
    assert "sweep into 12 and 32" in text
    assert f"an {NUMBER_WORDS[ARRAY_CHUNKS_PER_WORKER]} of a worker's share" in text
    assert f"at most {MOST_DRAWN_POINTS:,} points" in text
    assert f"the {REPORT_ROWS} points of lowest residual error" in text
    assert f"(the first {REPORT_ROWS})" in text
    assert re.search(r"at most 10\^(\d+) points", text)[1] == str(len(str(MAX_POINTS)) - 1)


def test_a_run_with_a_ceiling_shows_the_ratios_over_it(document):
    # A record of the benchmark as it now runs also holds each run's CPU time over one
    # process's and the ceiling; the page gives the ratios over the ceiling.
    run = copy.deepcopy(document)
    run["ceiling"] = {action: {"ratio": 1.25, "cpu_together_over_alone": 1.02}
                      for action in ("optimise", "evaluate")}
    for action in ("optimise", "evaluate"):
        for label in (scaling.POOL, scaling.DASK):
            run[action]["runs"][label]["workers_cpu_over_one_process"] = 1.1
    text = scaling.section(run)
    pool = run["optimise"]["runs"][scaling.POOL]
    assert (f"| optimise | {scaling.POOL} | "
            f"{pool['calling_process_cpu_over_one_process']:.2f} | 1.10 | "
            f"{pool['cpu_bound_ratio']:.2f} | {pool['ratio_to_one_process'] / 1.25:.2f} |") in text
    assert "optimise: two processes 1.25x one, their CPU time per point 1.02x" in text
    older = copy.deepcopy(document)  # a record from before the ceiling was measured
    older.pop("ceiling", None)
    assert "ratio over the ceiling" not in scaling.section(older)
