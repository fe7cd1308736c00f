"""Ctrl-C and SIGTERM during an IPOPT multi-start: how fast ``sso run`` stops, and how.

``python -m benchmarks.interrupts [--signals N] [--starts N] [--sweep [--workers N]]`` runs the
``sso`` command on the paper model's five-joint case with IPOPT only (tests/slow_case.py,
60 starts by default) in a subprocess, waits until it says it is solving and then a
random 0.5 to 1.5 s more, and sends SIGINT; then the same with SIGTERM; N times each
(default 10). Each run must end with exit 130, write no report and leave no
temporary or lock file; the time from the signal to the end of the process is measured. The
target: every run ends with exit 130 within 2 s. A run that finishes before its
signal is not counted (it is started again). ``--sweep`` signals
``sso sweep --workers 1`` over four points of that case instead; with ``--workers 2``
or more, the sweep's process pool, whose workers (and multiprocessing's resource
tracker: every child of the sweep, from /proc) must be gone too, within 5 s
(tests/studies/test_shutdown.py checks that they go, not how fast).

For each run the table says whether the signal reached IPOPT mid-iteration (CasADi
then logs ``KeyboardInterruptException``; the run used to go on with exit 0) or
arrived between solves.
"""

from __future__ import annotations

import argparse
import random
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
from processes import alive, children  # noqa: E402  (the tests' helpers, shared)
from slow_case import SLOW_SWEEP, slow_case  # noqa: E402

TARGET_S = 2.0
POOL_TARGET_S = 5.0


def one_run(folder: Path, signal_number: int, sweep: bool, workers: int,
            rng: random.Random) -> dict[str, object] | None:
    """Signal one run; its outcome, or None if it ended before the signal."""
    arguments = (["sweep", "sweep.toml", "--workers", str(workers)] if sweep
                 else ["run", "slow.toml", "--out", "out"])
    child = subprocess.Popen([sys.executable, "-m", "sso._cli", *arguments, "--no-plots"],
                             cwd=folder, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True)
    assert child.stdout is not None
    if sweep:
        while not (folder / "results" / "slow_sweep" / "sweep.json").exists():
            if child.poll() is not None:
                raise RuntimeError(child.communicate()[1])
            time.sleep(0.02)
    else:
        line = child.stdout.readline()
        if "solving" not in line:
            raise RuntimeError(line + child.communicate()[1])
    time.sleep(rng.uniform(0.5, 1.5))
    started = children(child.pid)
    if child.poll() is not None:
        child.communicate()
        return None
    sent = time.perf_counter()
    child.send_signal(signal_number)
    _, stderr = child.communicate(timeout=120)
    ended_s = time.perf_counter() - sent
    while any(alive(pid) for pid in started) and time.perf_counter() - sent < 120:
        time.sleep(0.01)
    gone_s = time.perf_counter() - sent
    report = (folder / "results" / "slow_sweep" / "report.md") if sweep else folder / "out" / "slow"
    leftovers = [path.name for pattern in (".sso-tmp-*", ".sso-lock-*")
                 for path in folder.rglob(pattern)]
    return {"signal": signal.Signals(signal_number).name, "exit": child.returncode,
            "ended_s": ended_s, "children": len(started), "gone_s": gone_s,
            "in_ipopt": "KeyboardInterruptException" in stderr,
            "report_written": report.exists(), "temporaries": leftovers,
            "says_interrupted": "error: interrupted" in stderr}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--signals", type=int, default=10, help="runs per signal")
    parser.add_argument("--starts", type=int, default=60)
    parser.add_argument("--sweep", action="store_true",
                        help="signal sso sweep --workers 1 instead of sso run")
    parser.add_argument("--workers", type=int, default=1,
                        help="the sweep's workers (2 or more: a process pool)")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    target_s = POOL_TARGET_S if args.sweep and args.workers > 1 else TARGET_S
    rng = random.Random(args.seed)
    outcomes = []
    for signal_number in (signal.SIGINT, signal.SIGTERM):
        done = 0
        while done < args.signals:
            with tempfile.TemporaryDirectory() as name:
                folder = Path(name)
                (folder / "slow.toml").write_text(slow_case("ipopt", args.starts))
                (folder / "sweep.toml").write_text(SLOW_SWEEP)
                outcome = one_run(folder, signal_number, args.sweep, args.workers, rng)
            if outcome is None:
                print("  (ended before its signal; started again)", flush=True)
                continue
            done += 1
            outcomes.append(outcome)
            flaws = (["REPORT WRITTEN"] if outcome["report_written"] else []) + (
                [f"TEMPORARIES {outcome['temporaries']}"] if outcome["temporaries"] else [])
            print(f"{outcome['signal']:8} exit {outcome['exit']}  ended in "
                  f"{outcome['ended_s']:.3f} s, its {outcome['children']} children gone in "
                  f"{outcome['gone_s']:.3f} s  "
                  f"{'mid-IPOPT' if outcome['in_ipopt'] else 'between solves'}  "
                  + "  ".join(flaws), flush=True)
    good = [outcome for outcome in outcomes
            if outcome["exit"] == 130 and float(str(outcome["gone_s"])) <= target_s
            and not outcome["report_written"] and not outcome["temporaries"]
            and outcome["says_interrupted"]]
    times = [float(str(outcome["ended_s"])) for outcome in outcomes]
    for name in ("SIGINT", "SIGTERM"):
        mine = [outcome for outcome in good if outcome["signal"] == name]
        print(f"{name}: {len(mine)} of {args.signals} ended with exit 130 within {target_s} s "
              "(the process and every child), no report, no temporary file")
    gone = [float(str(outcome["gone_s"])) for outcome in outcomes]
    print(f"time from signal to exit: median {statistics.median(times):.3f} s, "
          f"max {max(times):.3f} s; to the last child gone: max {max(gone):.3f} s; "
          f"{sum(bool(o['in_ipopt']) for o in outcomes)} of "
          f"{len(outcomes)} signals reached IPOPT mid-iteration")
    sys.exit(0 if len(good) == len(outcomes) else 1)


if __name__ == "__main__":
    main()
