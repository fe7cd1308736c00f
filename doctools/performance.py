"""The Performance page's measured section, rendered from one recorded benchmark run.

``python -m doctools.performance record SUMMARY_JSON`` copies the ``summary.json``
that ``python -m benchmarks.work_precision`` wrote into ``docs/data/performance_run.json``,
adding when the run was made and on what machine. At each build the hook replaces
the marker line ``<!-- performance run -->`` of ``performance.md`` with
:func:`section`: every target the benchmark checked, met or missed, and the tables
behind them, all from that one run. Nothing on the page is typed in by hand.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
from datetime import UTC, datetime
from importlib import metadata
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
RECORD = ROOT / "docs" / "data" / "performance_run.json"
MARKER = "<!-- performance run -->"


def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _memory_gib() -> float | None:
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal:"):
                return round(int(line.split()[1]) / 2**20, 1)
    except OSError:
        pass
    return None


def _version(distribution: str) -> str:
    try:
        return metadata.version(distribution)
    except metadata.PackageNotFoundError:
        return "not installed"


def machine() -> dict[str, Any]:
    """What the run was measured on."""
    load = os.getloadavg() if hasattr(os, "getloadavg") else None
    return {
        "cpu": _cpu_model(),
        "cores": os.cpu_count(),
        "memory_gib": _memory_gib(),
        "system": platform.platform(),
        "python": platform.python_version(),
        "numpy": _version("numpy"),
        "scipy": _version("scipy"),
        "casadi": _version("casadi"),
        "load_average_1min": None if load is None else round(load[0], 2),
    }


def record(summary: Path, target: Path = RECORD) -> dict[str, Any]:
    """Write the run record from a benchmark ``summary.json``; returns it.

    The date and the machine are the benchmark's own when its summary has them
    (``started_utc``, ``finished_utc``, ``machine``), else the summary file's time
    and this machine, described now.
    """
    document = json.loads(summary.read_text(encoding="utf-8"))
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                            capture_output=True, text=True).stdout.strip()
    quick = bool(document.get("settings", {}).get("quick"))
    finished = document.get("finished_utc") or datetime.fromtimestamp(
        summary.stat().st_mtime, UTC).strftime("%Y-%m-%d %H:%M")
    document["run"] = {
        "date_utc": finished,
        "started_utc": document.get("started_utc", ""),
        "command": "python -m benchmarks.work_precision" + (" --quick" if quick else ""),
        "commit": commit or "unknown",
        "machine": machine(),
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
    box = run["machine"]
    memory = f", {box['memory_gib']} GiB" if box.get("memory_gib") else ""
    when = (f"from {run['started_utc']} to {run['date_utc']} UTC" if run.get("started_utc")
            else f"on {run['date_utc']} UTC")
    load = document.get("machine", {}).get("load_average_1_5_15_min")
    load_text = (f"load average over 1, 5 and 15 min {load} at the end of the run" if load
                 else f"load average {box['load_average_1min']} when recorded")
    lines = [
        f"Measured **{when}** by `{run['command']}` at commit `{run['commit']}`, on "
        f"{box['cores']} cores of an {box['cpu']}{memory} ({box['system']}; Python "
        f"{box['python']}, NumPy {box['numpy']}, SciPy {box['scipy']}, CasADi "
        f"{box['casadi']}; {load_text}). The machine is shared with other work, so "
        "absolute times wander; every ratio is taken within this one run.",
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
        "Median wall time after a warm-up; ratio = skilled baseline time / method time "
        "(higher is faster).",
        "",
        "| option | method | time (ms) | RE | baseline time / method time |",
        "| --- | --- | --- | --- | --- |",
    ]
    for option, case in document["issue_12"]["latency"].items():
        for name, figures in case.items():
            if isinstance(figures, dict):
                lines.append(f"| {option} | {name} | {figures['time_s'] * 1e3:.3f} | "
                             f"{figures['fun']:.3g} | {figures['baseline_over_method']:.2f} |")
    lines += [
        "",
        "### Random cases, one start",
        "",
        "`sso.optimise(..., solvers=(\"lm\",), starts=1)` against the skilled baseline, "
        "median of each method's passes over the starts:",
        "",
        "| option | joints | starts | baseline (ms/solve) | lm (ms/solve) | ratio "
        "| lm RE above the baseline's |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    lines.extend(f"| {row['option']} | {row['joints']} | {row['starts']} | "
                 f"{row['skilled_ms_per_solve']:.3f} | {row['lm_ms_per_solve']:.3f} | "
                 f"{row['ratio']:.2f} | {row['lm_higher_re']} |"
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
