"""The Performance page shows every target of one recorded benchmark run, met and missed."""

from __future__ import annotations

import copy
import json

import pytest

from benchmarks.machine import machine_description
from benchmarks.work_precision import targets
from doctools import performance
from doctools.blocks import ROOT


def test_the_recorded_run_is_dated_and_its_machine_described_by_the_benchmark():
    document = performance.load()
    run, machine = document["run"], document["machine"]
    assert run["date_utc"] == document["finished_utc"] and run["commit"]
    assert run["started_utc"] == document["started_utc"]
    assert run["command"].startswith("python -m benchmarks.work_precision")
    # The keys of benchmarks/machine.py: the benchmark described the machine itself.
    assert set(machine) >= set(machine_description()) - {"memory_gib"}
    assert machine["cpu_count"] >= 1 and machine["processor"]
    section = performance.section(document)
    for key in ("processor", "platform", "python", "numpy", "scipy", "casadi", "sso"):
        assert str(machine[key]) in section, key
    assert f"{machine['cpu_count']} CPUs" in section
    assert str(machine["load_average_1_5_15_min"]) in section


def test_recording_keeps_the_summary_s_machine_and_refuses_a_summary_without_one(tmp_path):
    summary = copy.deepcopy(performance.load())
    del summary["run"]
    path = tmp_path / "summary.json"
    path.write_text(json.dumps(summary), encoding="utf-8")
    recorded = performance.record(path, tmp_path / "record.json")
    assert recorded["machine"] == summary["machine"]
    assert recorded["run"]["date_utc"] == summary["finished_utc"]
    del summary["machine"]
    path.write_text(json.dumps(summary), encoding="utf-8")
    with pytest.raises(ValueError, match="has no machine: it was written by an earlier"):
        performance.record(path, tmp_path / "record.json")


def test_every_target_of_the_run_is_on_the_page_with_its_verdict():
    document = performance.load()
    page = performance.page_with_section(
        (ROOT / "docs" / "performance.md").read_text(encoding="utf-8"), document)
    assert performance.MARKER not in page
    rows = performance.target_rows(document)
    names = {row["target"] for row in rows}
    assert names >= set(document["issue_12"]["targets"]) | set(document["targets"])
    shown = {"met": "| met |", "MISSED": "| **MISSED** |", "retired": "| retired |"}
    for row in rows:
        line = next(line for line in page.split("\n") if line.startswith(f"| {row['target']} |"))
        assert shown[row["status"]] in line, line
        if row["status"] == "retired":
            assert f"- {row['target']}: {row['reason']}" in page


def test_the_run_holds_every_target_the_benchmark_checks_today():
    # The v0.1 targets are named by the benchmark itself; a target added there and
    # missing from the recorded run means the page needs a new run.
    assert set(performance.load()["targets"]) == set(targets([], {}))


def test_a_missed_and_a_retired_target_are_shown_as_such():
    document = copy.deepcopy(performance.load())
    document["target_table"] = [
        {"target": "fast enough", "status": "MISSED", "measured": "4.6x", "reason": ""},
        {"target": "few evaluations", "status": "retired", "measured": "would be MISSED",
         "reason": "evaluations no longer measure work"}]
    section = performance.section(document)
    assert "| fast enough | **MISSED** | 4.6x |" in section
    assert "| few evaluations | retired | would be MISSED |" in section
    assert "- few evaluations: evaluations no longer measure work" in section


def test_the_page_shows_the_cpu_times_the_run_recorded():
    # Every CPU-time figure of the recorded run (docs/data/performance_run.json) is on
    # the rendered page beside its wall-time figure, at the digits the page prints.
    document = performance.load()
    lines = performance.section(document).split("\n")
    for option, case in document["issue_12"]["latency"].items():
        for name, figures in case.items():
            if isinstance(figures, dict):
                row = (f"| {option} | {name} | {figures['time_s'] * 1e3:.3f} | "
                       f"{figures['cpu_time_s'] * 1e3:.3f} | {figures['fun']:.3g} | "
                       f"{figures['baseline_over_method']:.2f} | "
                       f"{figures['baseline_over_method_cpu']:.2f} |")
                assert row in lines, row
        default = (f"| {option} | {case['default_over_baseline']:.2f}x | "
                   f"{case['default_over_baseline_cpu']:.2f}x |")
        assert default in lines, default
    for row in document["issue_12"]["random_cases"]["rows"]:
        cells = (f"| {row['ratio']:.2f} | {row['ratio_cpu']:.2f} | {row['lm_higher_re']} |")
        assert any(line.startswith(f"| {row['option']} | {row['joints']} | {row['starts']} |")
                   and line.endswith(cells) for line in lines), cells
