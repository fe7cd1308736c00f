"""A saved result's figures computed again from the designs they belong to.

A report read back from ``result.json`` (``sso report``) shows the designs the file
names and the figures it gives them; :func:`check_figures` recomputes every such
figure from its design before anything is rendered, and refuses, naming the field,
a figure that disagrees with its design beyond round-off, or that no design can
have (an RE below zero, not finite):

* every solver answer of an optimisation of a shaft series (a ``Solution`` of an
  :class:`sso.OptimisationResult`): ``fun`` is the RE of its ``series``;
* every evaluation shown beside its design (an optimisation's ``initial`` and
  ``optimum``, a compared design's ``evaluation`` and speed curve, a tolerance
  study's ``nominal``): each figure of :meth:`sso.ShaftSeries.evaluate`;
* a column's assemblies and best phasing (the RE of the chain matrix at its
  hardpoints) and its closed-form least RE (:func:`sso.can_cancel`);
* a mechanism run's tables (each linkage's table, curve and positions, analysed
  again over the case's crank angles).

Round-off is the solvers' agreement rule
(:func:`sso._solvers.crosscheck.allowed_objective_gap`): an RE agrees within
``1e-14 + 1e-6 * |RE|``; the other figures (speeds, fluctuation, acceleration,
torque ratios; the speed curve) within ``1e-12 + 1e-6 * |figure|``. Both the closed
form of the exact model and the paper model's quadrature (at the result's own
tolerance, or the default 1e-10) reproduce the saved figures far closer than that.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterator, Mapping
from typing import Any

import numpy as np

from sso._column.cancel import can_cancel
from sso._column.chain_matrix import residual_error
from sso._column.geometry import ColumnGeometry
from sso._column.phasing import PhasingResult
from sso._limits import DEFAULT_QUADRATURE_ATOL, DEFAULT_QUADRATURE_RTOL
from sso._linkages.table import MechanismTable
from sso._record import RecordError
from sso._run.column import ColumnRun
from sso._run.mechanism_run import MechanismRun, linkage_curves
from sso._shafts.curves import ComparedDesign, compared_design
from sso._shafts.evaluation import Evaluation
from sso._shafts.optimise import OptimisationResult
from sso._shafts.series import ShaftSeries
from sso._solvers.crosscheck import allowed_objective_gap
from sso._solvers.solution import Solution

FIGURE_ATOL = 1e-12
"""Absolute part of the round-off allowed to a figure other than an RE (speeds in rpm,
fluctuation, acceleration in rad/s^2, torque ratios)."""
RE_RULE = "1e-14 + 1e-6 * |RE|"
FIGURE_RULE = "1e-12 + 1e-6 * |figure|"
# (design, where result.json holds it, its evaluation): the results that show both.
_EVALUATED = (("best_series", "best.series", "optimum"),
              ("initial_series", "initial_series", "initial"),
              ("design", "design", "nominal"))
_MAX_DEPTH = 64


def check_figures(result: Any) -> None:
    """Refuse a result whose figures are not those of its designs.

    Raises
    ------
    sso._record.RecordError
        Naming the field (its path in ``result.json``), the saved value, the value
        computed again and the tolerance.
    """
    _Checker().visit(result, "", 0)


@dataclasses.dataclass
class _Checker:
    quadrature: tuple[float, float] = (DEFAULT_QUADRATURE_RTOL, DEFAULT_QUADRATURE_ATOL)
    in_optimisation: bool = False

    def visit(self, node: Any, path: str, depth: int) -> None:
        if depth > _MAX_DEPTH:
            return
        if isinstance(node, (tuple, list)):
            for index, item in enumerate(node):
                self.visit(item, f"{path}[{index}]", depth + 1)
            return
        if isinstance(node, Mapping):
            for key, item in node.items():
                self.visit(item, _join(path, str(key)), depth + 1)
            return
        if not dataclasses.is_dataclass(node) or isinstance(node, type):
            return
        rtol = getattr(node, "quadrature_rtol", None)
        atol = getattr(node, "quadrature_atol", None)
        if isinstance(rtol, float) and isinstance(atol, float):
            self.quadrature = (rtol, atol)
        if isinstance(node, OptimisationResult):
            self.in_optimisation = True  # its solvers' fun is the RE of their series
        for name, value in _fields(node):  # a part's own figures first
            self.visit(value, _join(path, name), depth + 1)
        try:
            self.check(node, path)
        except RecordError:
            raise
        except (ValueError, TypeError, ArithmeticError, IndexError, KeyError) as error:
            raise RecordError(f"{path or 'result'}: its figures cannot be computed again from "
                              f"its design ({error}); the file was changed after sso wrote "
                              "it") from None

    def check(self, node: Any, path: str) -> None:
        if (self.in_optimisation and isinstance(node, Solution)
                and isinstance(node.series, ShaftSeries)):
            _non_negative(_join(path, "fun"), node.fun)
            computed = self.evaluate(node.series, None).residual_error
            _compare(_join(path, "fun"), node.fun, computed, f"{_join(path, 'series')}", RE_RULE)
        for design_name, saved_as, evaluation_name in _EVALUATED:
            design = getattr(node, design_name, None)
            evaluation = getattr(node, evaluation_name, None)
            if isinstance(design, ShaftSeries) and isinstance(evaluation, Evaluation):
                self.check_evaluation(evaluation, design, _join(path, evaluation_name),
                                      _join(path, saved_as))
        if isinstance(node, ComparedDesign):
            self.check_evaluation(node.evaluation, node.series, _join(path, "evaluation"),
                                  _join(path, "series"))
            curve = compared_design(node.role, node.label, node.series, node.evaluation)
            _compare_array(_join(path, "output_speed_rpm"), node.output_speed_rpm,
                           curve.output_speed_rpm, _join(path, "series"))
        if isinstance(node, PhasingResult):
            _column_re(_join(path, "fun"), node.fun, node.geometry, node.x,
                       _join(path, "x"))
            _least_re(_join(path, "minimum_residual_error"), node.minimum_residual_error,
                      node.geometry)
        if isinstance(node, MechanismRun):  # each linkage's tables, analysed again
            for index, linkage in enumerate(node.linkages):
                try:
                    fresh = linkage_curves(linkage.role, linkage.mechanism, node.case)
                except ValueError as error:
                    raise RecordError(f"{_join(path, f'linkages[{index}].mechanism')}: not the "
                                      f"linkage its tables were analysed from ({error})") from None
                for name in ("table", "curve", "positions"):
                    _compare_table(_join(path, f"linkages[{index}].{name}"),
                                   getattr(linkage, name), getattr(fresh, name),
                                   _join(path, f"linkages[{index}].mechanism"))
        if isinstance(node, ColumnRun):  # its parts at its own hardpoints
            _least_re(_join(path, "cancel.minimum_residual_error"),
                      node.cancel.minimum_residual_error, node.geometry)
            for index, assembly in enumerate(node.assemblies):
                where = _join(path, f"assemblies[{index}]")
                _column_re(f"{where}.residual_error", assembly.residual_error, node.geometry,
                           assembly.yoke_phase_deg, f"{where}.yoke_phase_deg")

    def evaluate(self, series: ShaftSeries, speed_rpm: float | None) -> Evaluation:
        rtol, atol = self.quadrature
        if speed_rpm is None:
            return series.evaluate(quadrature_rtol=rtol, quadrature_atol=atol)
        return series.evaluate(speed_rpm, quadrature_rtol=rtol, quadrature_atol=atol)

    def check_evaluation(self, saved: Evaluation, series: ShaftSeries, path: str,
                         design_path: str) -> None:
        computed = self.evaluate(series, saved.input_speed_rpm)
        for field in dataclasses.fields(Evaluation):
            value, again = getattr(saved, field.name), getattr(computed, field.name)
            if isinstance(value, bool) or not isinstance(value, float):
                continue
            is_re = field.name == "residual_error"
            _compare(_join(path, field.name), value, again, design_path,
                     RE_RULE if is_re else FIGURE_RULE, None if is_re else FIGURE_ATOL)


def _fields(node: Any) -> Iterator[tuple[str, Any]]:
    """The parts of ``node`` that may hold figures: its fields and the derived ones its
    record saves (``_record_derived``)."""
    names = [field.name for field in dataclasses.fields(node)]
    for name in (*names, *getattr(type(node), "_record_derived", ())):
        value = getattr(node, name, None)
        if isinstance(value, (tuple, list, Mapping)) or dataclasses.is_dataclass(value):
            yield name, value


def _join(path: str, name: str) -> str:
    return name if not path else f"{path}.{name}"


def _non_negative(path: str, value: float) -> None:
    if not math.isfinite(value) or value < 0.0:
        raise RecordError(f"{path} = {value!r}; allowed: a finite number >= 0 (a residual "
                          "error)")


def _compare(path: str, saved: float, computed: float, design_path: str, rule: str,
             absolute: float | None = None) -> None:
    if not math.isfinite(saved):
        raise RecordError(f"{path} = {saved!r}; allowed: a finite number (the figure of "
                          f"{design_path})")
    allowed = (allowed_objective_gap((saved, computed)) if absolute is None else
               allowed_objective_gap((saved, computed), objective_atol=absolute))
    if not abs(saved - computed) <= allowed:
        raise RecordError(f"{path} = {saved!r} is not the figure of {design_path}, computed "
                          f"again: {computed!r} (allowed difference {allowed:.3g}: {rule}); "
                          "the file was changed after sso wrote it")


def _compare_array(path: str, saved: np.ndarray, computed: np.ndarray, design_path: str,
                   what: str = "the speed curve") -> None:
    """Refuse ``saved`` unless each value is ``computed``'s within round-off
    (:data:`FIGURE_RULE`; NaN where it is NaN, a boolean exactly)."""
    held, again = np.asarray(saved), np.asarray(computed)
    if held.shape != again.shape:
        raise RecordError(f"{path} holds {held.size} values, not the {again.size} of "
                          f"{what} of {design_path}")
    if held.dtype == bool or again.dtype == bool:
        same = held == again
    else:
        numbers, figures = held.astype(float), again.astype(float)
        allowed = FIGURE_ATOL + 1e-6 * np.maximum(np.abs(numbers), np.abs(figures))
        same = (np.abs(numbers - figures) <= allowed) | (np.isnan(numbers) & np.isnan(figures))
    wrong = np.flatnonzero(~same)
    if wrong.size:
        first = int(wrong[0])
        raise RecordError(f"{path}[{first}] = {held[first].item()!r} is not the figure of "
                          f"{what} of {design_path}, computed again: {again[first].item()!r} "
                          f"(allowed difference: {FIGURE_RULE}); the file was changed after "
                          "sso wrote it")


def _compare_table(path: str, saved: MechanismTable, computed: MechanismTable,
                   design_path: str) -> None:
    if list(saved.columns) != list(computed.columns):
        raise RecordError(f"{path} has the columns {list(saved.columns)}, not the "
                          f"{list(computed.columns)} of {design_path}, analysed again")
    for name, values in computed.columns.items():
        _compare_array(f"{path}.columns.{name}", saved.columns[name], values, design_path,
                       "the table")


def _column_re(path: str, saved: float, geometry: ColumnGeometry, yoke_phase_deg: Any,
               design_path: str) -> None:
    _non_negative(path, saved)
    if len(yoke_phase_deg) != geometry.joint_count - 1:
        raise RecordError(f"{design_path} holds {len(yoke_phase_deg)} phasings; the column "
                          f"has {geometry.joint_count - 1} intermediate shafts")
    phase_deg = geometry.phase_deg_from_yoke(yoke_phase_deg)
    computed = float(residual_error(np.radians(geometry.beta_deg), np.radians(phase_deg)))
    _compare(path, saved, computed, design_path, RE_RULE)


def _least_re(path: str, saved: float, geometry: ColumnGeometry) -> None:
    _non_negative(path, saved)
    computed = can_cancel(geometry.beta_deg).minimum_residual_error
    _compare(path, saved, computed, "the column's operating angles (sso.can_cancel)", RE_RULE)
