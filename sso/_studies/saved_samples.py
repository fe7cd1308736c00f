"""The saved form of a Monte Carlo study: its settings and summary, not its samples.

A study of a million samples would save some 200 MB of numbers in ``result.json``
(more than ``sso report`` reads back). Its record holds instead what makes the
samples (design, tolerances, distribution, seed, count) and their summary
(percentiles, mean and largest value of each figure); the samples themselves are in
the study's table (``tolerance.csv``). Reading the record back draws the samples again
from the seed (the same numbers: a study's chunking, executor and worker count never
change them) and checks the saved summary against them, so a report read back
certifies nothing it did not compute.
"""

from __future__ import annotations

import dataclasses
import math
import typing
from collections.abc import Mapping, Sequence
from typing import Any

from sso._record import (
    FIELD_RULES,
    RecordError,
    check_field,
    check_field_names,
    decode,
    record_classes,
)
from sso._solvers.crosscheck import allowed_objective_gap
from sso._validation import shown

SHAFT_SAMPLE_FIELDS = ("beta_deg", "phase_deg", "residual_error", "fluctuation",
                       "max_output_accel_rad_s2")
"""The per-sample arrays of a shaft series' study (:class:`sso.ToleranceResult`)."""
SUMMARY_RULE = "1e-14 + 1e-6 * |figure|"
_FIGURES_SCHEMA = {"type": "object", "additionalProperties": {"type": "number"}}
EXTRA_SCHEMA: dict[str, Any] = {
    "samples": {"type": "integer", "minimum": 1,
                "description": "samples drawn (they are in the study's tolerance.csv)"},
    "summary": {
        "type": "object", "additionalProperties": False,
        "required": ["percentiles", "mean", "max"],
        "description": "of each figure over the samples: checked on reading against the "
                       "samples drawn again from the seed",
        "properties": {"percentiles": {"type": "object",
                                       "additionalProperties": _FIGURES_SCHEMA},
                       "mean": _FIGURES_SCHEMA, "max": _FIGURES_SCHEMA}},
}
"""The saved form's fields beyond the class's own (the JSON Schema of each)."""


def saved_field_names(cls: type, sample_fields: Sequence[str]) -> list[str]:
    """The fields of the study class ``cls`` its record holds: all but its samples."""
    return [item.name for item in dataclasses.fields(cls)
            if item.init and item.name not in sample_fields]


def read_saved_fields(cls: type, saved: Mapping[str, Any], names: Sequence[str],
                      extra: Sequence[str], where: str) -> dict[str, Any]:
    """The fields ``names`` of ``cls`` decoded from ``saved`` (each checked as the
    record's codec checks it), which must hold exactly those, ``extra`` and nothing else.

    Raises
    ------
    sso._record.RecordError
        Naming the field missing, unknown, of the wrong type or out of range.
    """
    check_field_names(cls, saved, {*names, *extra}, where)
    hints = typing.get_type_hints(cls, localns=record_classes())
    arguments = {name: decode(saved[name], hints[name], f"{where}.{name}") for name in names}
    for name, value in arguments.items():
        check_field(f"{where}.{name}", name, value, arguments, FIELD_RULES)
    return arguments


def check_summary(saved: Any, computed: Mapping[str, Any], where: str,
                  source: str = "the samples drawn again from the study's seed") -> None:
    """Refuse a saved summary that is not ``computed`` from ``source`` (the same nesting
    of names, every number within ``1e-14 + 1e-6 * |figure|``).

    Raises
    ------
    sso._record.RecordError
        Naming the first figure that differs, or the part missing or unknown.
    """
    if isinstance(computed, Mapping):
        if not isinstance(saved, Mapping) or set(saved) != set(computed):
            raise RecordError(f"{where} = {shown(saved)}; allowed: an object of "
                              f"{', '.join(sorted(computed))}")
        for key, value in computed.items():
            check_summary(saved[key], value, f"{where}.{key}", source)
        return
    if isinstance(saved, bool) or not isinstance(saved, (int, float)) \
            or not math.isfinite(saved):
        raise RecordError(f"{where} = {shown(saved)}; allowed: a finite number")
    allowed = allowed_objective_gap((float(saved), float(computed)))
    if not abs(saved - computed) <= allowed:
        raise RecordError(f"{where} = {saved!r} is not the figure of {source}: "
                          f"{computed!r} (allowed difference "
                          f"{allowed:.3g}: {SUMMARY_RULE}); the file was changed after sso "
                          "wrote it")
