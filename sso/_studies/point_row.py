"""One sweep point's row while it is computed, and the result columns every row shares.

A point's work runs in steps (read its case, solve, evaluate); each step's
warnings and time are kept, and an exception turns the row into an error row
instead of escaping: a failing point is data, not a crash. The point-by-point path
(:mod:`sso._studies.worker`) and the points solved together (:mod:`sso._studies.batched`)
build their rows here, so both give the same columns.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, TypeVar

T = TypeVar("T")


@dataclass
class PointRow:
    """One point's row while it is computed: its cells, warnings and busy time.

    Attributes
    ----------
    cells : dict
        The row so far (point index and axis values first).
    notes : list of str
        Warnings raised by its work, in order.
    busy_s : float
        Wall time spent on this point's work (its share, for work done together).
    """

    cells: dict[str, Any]
    notes: list[str] = field(default_factory=list)
    busy_s: float = 0.0

    @property
    def failed(self) -> bool:
        """Whether a step of its work raised (the row is then an error row)."""
        return self.cells.get("status") == "failed"

    def attempt(self, work: Callable[[], T]) -> T | None:
        """Run one step of the point's work; never raises.

        The step's warnings join the notes and its time the busy time. Returns
        the step's value, or None if it raised: the row is then an error row
        (``status = "failed"`` and the error).
        """
        started = time.perf_counter()
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                value = work()
        except Exception as error:  # noqa: BLE001 - a failing point is data, not a crash
            self.cells["status"] = "failed"
            self.cells["error"] = f"{type(error).__name__}: {error}"
            return None
        finally:
            self.busy_s += time.perf_counter() - started
        self.notes.extend(str(warning.message) for warning in caught)
        return value

    def fill(self, work: Callable[[], dict[str, Any]]) -> None:
        """Run a step that gives result cells (:meth:`attempt`) and add them to the row."""
        cells = self.attempt(work)
        if cells is not None:
            self.cells.update(cells)

    def finish(self) -> dict[str, Any]:
        """The finished row: status, warnings (when it succeeded) and time."""
        if not self.failed:
            self.cells["status"] = "ok"
            self.cells["warnings"] = " | ".join(dict.fromkeys(self.notes))
        self.cells["time_s"] = self.busy_s
        return self.cells


def design_columns(evaluation: Any, beta_deg: Sequence[float],
                   phase_deg: Sequence[float]) -> dict[str, Any]:
    """The figures of a design (an :class:`sso.Evaluation`) and its angles, deg."""
    return {
        "residual_error": evaluation.residual_error,
        "residual_error_rpm2": evaluation.residual_error_rpm2,
        "fluctuation": evaluation.fluctuation,
        "max_output_accel_rad_s2": evaluation.max_output_accel_rad_s2,
        "design_beta_deg": list(beta_deg),
        "design_phase_deg": list(phase_deg),
    }


def solver_columns(name: str, fun: float, status: int, success: bool, message: str,
                   kkt: float, time_s: float) -> dict[str, Any]:
    """One solver's columns: its best RE, status, convergence, KKT measure, time, message."""
    return {
        f"{name}_residual_error": fun,
        f"{name}_status": status,
        f"{name}_success": success,
        f"{name}_message": message,
        f"{name}_kkt_per_rad": kkt,
        f"{name}_time_s": time_s,
    }
