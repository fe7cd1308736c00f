"""The Performance page's measured section, rendered from one recorded benchmark run.

``python -m doctools.performance record SUMMARY_JSON`` copies the ``summary.json``
that ``python -m benchmarks.work_precision`` wrote into ``docs/data/performance_run.json``,
adding the command and the commit. The run's dates and its machine are the
benchmark's own (``benchmarks/machine.py`` described it at the end of the run);
nothing here describes a machine. At each build the hook replaces
the marker line ``<!-- performance run -->`` of ``performance.md`` with
:func:`section`: every target the benchmark checked, met or missed, and the tables
behind them, all from that one run. Nothing on the page is typed in by hand.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "docs" / "data" / "performance_run.json"
MARKER = "<!-- performance run -->"


def record(summary: Path, target: Path = RECORD) -> dict[str, Any]:
    """Write the run record from a benchmark ``summary.json``; returns it.

    Raises
    ------
    ValueError
        If the summary does not say when the run was made and on what machine
        (``started_utc``, ``finished_utc``, ``machine``): a summary of an earlier
        benchmark; run the benchmark again.
    """
    document = json.loads(summary.read_text(encoding="utf-8"))
    missing = [key for key in ("started_utc", "finished_utc", "machine") if not document.get(key)]
    if missing:
        raise ValueError(f"{summary} has no {', '.join(missing)}: it was written by an earlier "
                         "benchmark; run python -m benchmarks.work_precision again")
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    quick = bool(document.get("settings", {}).get("quick"))
    document["run"] = {
        "date_utc": document["finished_utc"],
        "started_utc": document["started_utc"],
        "command": "python -m benchmarks.work_precision" + (" --quick" if quick else ""),
        "commit": commit or "unknown",
    }
    target.parent.mkdir(parents=True, exist_ok=True)
    target.write_text(json.dumps(document, indent=1) + "\n", encoding="utf-8")
    return document


def target_rows(document: dict[str, Any]) -> list[dict[str, str]]:
    """Every target of the run: ``target``, ``status``, ``measured`` and ``reason``.

    ``status`` is ``met``, ``MISSED`` or ``retired`` (with the ``reason``).

    The rows are the benchmark's own ``target_table`` when the summary has one; else
    they are built from its two groups of targets the same way (none retired).
    """
    if "target_table" in document:
        return [{key: str(row.get(key, "")) for key in ("target", "status", "measured", "reason")}
                for row in document["target_table"]]
    rows = [{"target": name, "status": "met" if target["met"] else "MISSED",
             "measured": target["measured"], "reason": ""}
            for name, target in document["issue_12"]["targets"].items()]
    rows += [{"target": name, "status": "met" if target["met"] else "MISSED",
              "measured": "; ".join(target["misses"]) or "met by every case and method",
              "reason": ""}
             for name, target in document["targets"].items()]
    return rows


def _verdict(status: str) -> str:
    return {"met": "met", "MISSED": "**MISSED**"}.get(status, status)


def _cell(text: str) -> str:
    return str(text).replace("|", "\\|").replace("\n", " ")


def _number(value: Any, spec: str) -> str:
    return "n/a" if value is None else format(value, spec)


def section(document: dict[str, Any]) -> str:
    """The measured part of the Performance page, Markdown."""
    run = document["run"]
    box = document["machine"]  # the benchmark's own description (benchmarks/machine.py)
    memory = f", {box['memory_gib']} GiB" if box.get("memory_gib") else ""
    lines = [
        f"Measured **from {run['started_utc']} to {run['date_utc']} UTC** by "
        f"`{run['command']}` at commit `{run['commit']}`, on {box['cpu_count']} CPUs of "
        f"{box['processor']}{memory} ({box['platform']}, {box['machine']}; Python "
        f"{box['python']}, NumPy {box['numpy']}, SciPy {box['scipy']}, CasADi "
        f"{box['casadi']}, sso {box['sso']}; load average over 1, 5 and 15 min "
        f"{box['load_average_1_5_15_min']} at the end of the run). The machine is shared "
        "with other work, so absolute times wander; every ratio is taken within this one "
        "run.",
        "",
        "### Every target the benchmark checks",
        "",
        "| target | verdict | measured in this run |",
        "| --- | --- | --- |",
    ]
    rows = target_rows(document)
    lines += [f"| {_cell(row['target'])} | {_verdict(row['status'])} | {_cell(row['measured'])} |"
              for row in rows]
    retired = [row for row in rows if row["status"] == "retired"]
    if retired:
        lines += ["", "Retired targets are still measured and shown; why each was retired:", ""]
        lines += [f"- {row['target']}: {row['reason']}" for row in retired]
    lines += [
        "",
        "### One design, the paper's exact-model options",
        "",
        "Medians after a warm-up, of wall time and of this process's CPU time (on a shared "
        "machine the CPU time is the work the call did; the wall time adds its waits for a "
        "core); ratio = skilled baseline time / method time (higher is faster).",
        "",
        "| option | method | time (ms) | CPU time (ms) | RE | baseline time / method time "
        "| baseline CPU time / method CPU time |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    latency = document["issue_12"]["latency"]
    for option, case in latency.items():
        for name, figures in case.items():
            if isinstance(figures, dict):
                lines.append(f"| {option} | {name} | {figures['time_s'] * 1e3:.3f} | "
                             f"{figures['cpu_time_s'] * 1e3:.3f} | {figures['fun']:.3g} | "
                             f"{figures['baseline_over_method']:.2f} | "
                             f"{figures['baseline_over_method_cpu']:.2f} |")
    lines += [
        "",
        "The default call (both solvers, cross-checked) against the skilled baseline's "
        "single solve, method time / baseline time:",
        "",
        "| option | wall time | CPU time |",
        "| --- | --- | --- |",
    ]
    lines.extend(f"| {option} | {case['default_over_baseline']:.2f}x | "
                 f"{case['default_over_baseline_cpu']:.2f}x |" for option, case in latency.items())
    lines += [
        "",
        "### Random cases, one start",
        "",
        "`sso.optimise(..., solvers=(\"lm\",), starts=1)` against the skilled baseline, "
        "median of each method's passes over the starts:",
        "",
        "| option | joints | starts | baseline (ms/solve) | lm (ms/solve) | ratio "
        "| ratio of CPU times | lm RE above the baseline's |",
        "| --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    lines.extend(f"| {row['option']} | {row['joints']} | {row['starts']} | "
                 f"{row['skilled_ms_per_solve']:.3f} | {row['lm_ms_per_solve']:.3f} | "
                 f"{row['ratio']:.2f} | {row['ratio_cpu']:.2f} | {row['lm_higher_re']} |"
                 for row in document["issue_12"]["random_cases"]["rows"])
    lines += [
        "",
        "### Work against precision",
        "",
        "Speedup = reference time / sso time, each at the reference's best error (the "
        "fastest run that reaches it); the reference is the skilled baseline for the exact "
        "model and the finite-difference port for the paper model.",
        "",
        "| case | reference | reference time (ms) | method | best error | speedup "
        "| nfev at tol 1e-12 |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for key, case in document["cases"].items():
        for method, figures in case["methods"].items():
            lines.append(f"| {key} | {case['reference']} | {1e3 * case['baseline_time_s']:.2f} | "
                         f"{method} | {figures['best_error']:.3g} | "
                         f"{_number(figures['speedup'], '.2f')} | "
                         f"{figures['nfev_at_default_tol']} |")
    return "\n".join(lines) + "\n"


def page_with_section(markdown: str, document: dict[str, Any]) -> str:
    """``markdown`` with its marker line replaced by the measured section."""
    if MARKER not in markdown:
        raise ValueError(f"the Performance page has no {MARKER} line")
    return markdown.replace(MARKER, section(document))


def load(target: Path = RECORD) -> dict[str, Any]:
    """The recorded run."""
    loaded: dict[str, Any] = json.loads(target.read_text(encoding="utf-8"))
    return loaded


def main(arguments: list[str] | None = None) -> int:
    """``python -m doctools.performance record SUMMARY_JSON``: record a benchmark run."""
    parser = argparse.ArgumentParser(description=main.__doc__)
    parser.add_argument("action", choices=["record"])
    parser.add_argument("summary", type=Path)
    options = parser.parse_args(arguments)
    document = record(options.summary)
    print(f"recorded the run of {document['run']['date_utc']} UTC in {RECORD}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
