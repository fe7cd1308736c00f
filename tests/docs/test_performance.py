"""The Performance page shows every target of one recorded benchmark run, met and missed."""

from __future__ import annotations

import copy

from benchmarks.work_precision import targets
from doctools import performance
from doctools.blocks import ROOT


def test_the_recorded_run_is_dated_and_its_machine_described():
    run = performance.load()["run"]
    assert run["date_utc"] and run["commit"]
    assert run["command"].startswith("python -m benchmarks.work_precision")
    assert run["machine"]["cores"] >= 1 and run["machine"]["cpu"]


def test_every_target_of_the_run_is_on_the_page_with_its_verdict():
    document = performance.load()
    page = performance.page_with_section(
        (ROOT / "docs" / "performance.md").read_text(encoding="utf-8"), document)
    assert performance.MARKER not in page
    groups = (document["issue_12"]["targets"], document["targets"])
    for group in groups:
        for name, target in group.items():
            row = next(line for line in page.split("\n") if line.startswith(f"| {name}"))
            assert ("| met |" in row) == target["met"], row
            assert ("| **MISSED** |" in row) == (not target["met"]), row


def test_the_run_holds_every_target_the_benchmark_checks_today():
    # The v0.1 targets are named by the benchmark itself; a target added there and
    # missing from the recorded run means the page needs a new run.
    assert set(performance.load()["targets"]) == set(targets([], {}))


def test_a_missed_target_is_shown_missed_with_its_misses():
    document = copy.deepcopy(performance.load())
    name = next(iter(document["targets"]))
    document["targets"][name] = {"met": False, "misses": ["option 3 lm: nfev 96 > 296/4"]}
    section = performance.section(document)
    assert f"| {name} (v0.1 target, each case's reference) | **MISSED** | " \
           "option 3 lm: nfev 96 > 296/4 |" in section
