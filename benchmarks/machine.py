"""What a benchmark ran on, described once.

Every benchmark summary that describes its machine calls :func:`machine_description`
at the end of its run, and the Performance page (``doctools/performance.py``)
shows the description from the recorded summary, never one made when recording.
"""

from __future__ import annotations

import os
import platform
from importlib import metadata
from pathlib import Path
from typing import Any


def machine_description() -> dict[str, Any]:
    """The platform, CPU model and count, memory, load, Python and the numerical libraries.

    Returns
    -------
    dict
        ``platform``, ``machine`` (the architecture), ``processor`` (the CPU's model),
        ``cpu_count``, ``memory_gib`` (None where unknown), ``load_average_1_5_15_min``
        (NaN where the system has none), and the versions of ``python``, ``numpy``,
        ``scipy``, ``casadi`` and ``sso``.
    """
    load = os.getloadavg() if hasattr(os, "getloadavg") else (float("nan"),) * 3
    return {"platform": platform.platform(), "machine": platform.machine(),
            "processor": _cpu_model(), "cpu_count": os.cpu_count(),
            "memory_gib": _memory_gib(),
            "load_average_1_5_15_min": [round(value, 2) for value in load],
            "python": platform.python_version(),
            **{name: _version(name) for name in ("numpy", "scipy", "casadi", "sso")}}


def _cpu_model() -> str:
    """The CPU's model name (Linux: /proc/cpuinfo), else what ``platform`` knows."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine() or "unknown"


def _memory_gib() -> float | None:
    """Total memory, GiB (Linux: /proc/meminfo), else None."""
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
