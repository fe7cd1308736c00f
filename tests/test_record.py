"""The record codec: saved forms are strict JSON, read back equal, and read strictly."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

import sso
from sso._record import Record, RecordError, built, built_from, decode, encode, rebuilt
from sso._shafts.series import checked_series

SERIES = sso.ShaftSeries([10.0, 15.0, 12.0], [80.0, 95.0])


@dataclass(frozen=True, eq=False)
class Sample(Record):
    """A record of every kind of field the codec knows."""

    count: int
    value: float
    flags: tuple[bool, ...]
    table: np.ndarray
    named: dict[str, float]
    series: sso.ShaftSeries | None


def test_every_kind_of_field_survives_strict_json():
    sample = Sample(count=3, value=math.inf, flags=(True, False),
                    table=np.array([[1.0, math.nan], [2.5, -math.inf]]),
                    named={"a": 1.0, "b": math.nan}, series=SERIES)
    text = json.dumps(sample.to_dict(), allow_nan=False)
    back = Sample.from_dict(json.loads(text))
    assert back == sample
    assert back.table.dtype == np.float64 and back.table.shape == (2, 2)
    assert math.isnan(back.table[0, 1]) and back.table[1, 1] == -math.inf
    assert back.series == SERIES


def test_integer_and_boolean_arrays_keep_their_type():
    for array in (np.array([1, 2, 3]), np.array([True, False]), np.zeros((0, 3))):
        back = decode(encode(array), np.ndarray, "table")
        assert back.dtype == array.dtype and back.shape == array.shape
        np.testing.assert_array_equal(back, array)


@pytest.mark.parametrize(("saved", "message"), [
    ({"dtype": "<f8", "shape": [2, 2], "data": [1.0]}, r"shape \[2, 2\] does not hold 1"),
    ({"dtype": "<U3", "shape": [1], "data": ["abc"]}, "allowed: booleans, integers or floats"),
    ({"dtype": "nonsense", "shape": [1], "data": [1]}, "no array type"),
    ([1.0, 2.0], "allowed: an array"),
])
def test_arrays_are_read_strictly(saved, message):
    with pytest.raises(RecordError, match=message):
        decode(saved, np.ndarray, "table")


def test_from_dict_refuses_another_version_or_type():
    saved = sso.can_cancel([10.0, 12.0, 5.0]).to_dict()
    with pytest.raises(RecordError, match="version = 2; this sso reads version 1"):
        sso.CancelVerdict.from_dict({**saved, "version": 2})
    with pytest.raises(RecordError, match="type = 'bogus' is no sso result type"):
        sso.CancelVerdict.from_dict({**saved, "type": "bogus"})
    assert sso.PhasingResult  # imported, so its name is known
    with pytest.raises(RecordError, match="type = 'PhasingResult'; allowed: CancelVerdict"):
        sso.CancelVerdict.from_dict({**saved, "type": "PhasingResult"})
    with pytest.raises(RecordError, match="margin is missing"):
        sso.CancelVerdict.from_dict({key: value for key, value in saved.items()
                                     if key != "margin"})
    with pytest.raises(RecordError, match="colour is not a field of CancelVerdict"):
        sso.CancelVerdict.from_dict({**saved, "colour": "red"})
    with pytest.raises(RecordError, match="limiting_joint = 1.5; allowed: an integer"):
        sso.CancelVerdict.from_dict({**saved, "limiting_joint": 1.5})


@pytest.mark.parametrize(("path", "value", "message"), [
    (("input_speed_rpm",), -25.0, "input_speed_rpm = -25.0; allowed: a finite number > 0"),
    (("option",), 99, "option = 99; allowed: 1, 2 or 3"),
    (("model",), "bogus", "model = 'bogus'; allowed: exact or paper"),
    (("optimum", "residual_error"), -5.0, "optimum.residual_error = -5.0; allowed: a finite"),
    (("best", "fun"), {"float": "nan"}, "best.fun = nan with success = true"),
    (("initial_series", "beta_deg", 0), 95.0, r"beta_deg\[0\] = 95"),
])
def test_from_dict_checks_values_as_strictly_as_case_files(path, value, message):
    saved = sso.optimise(SERIES, 1, starts=1, solvers="ipopt").to_dict()
    edited = json.loads(json.dumps(saved))
    target = edited
    for key in path[:-1]:
        target = target[key]
    target[path[-1]] = value
    with pytest.raises(RecordError, match=message):
        sso.OptimisationResult.from_dict(edited)


def test_built_and_rebuilt_go_through_the_dataclass_constructor():
    fields = {"count": 3, "value": 0.5, "flags": (True,), "table": np.zeros((1, 2)),
              "named": {"a": 1.0}, "series": SERIES}
    made = built(Sample, **fields)
    assert type(made) is Sample and made == Sample(**fields)
    assert made.to_dict() == Sample(**fields).to_dict()
    with pytest.raises(TypeError, match="unexpected keyword argument 'valu'"):
        built(Sample, **{**{key: item for key, item in fields.items() if key != "value"},
                         "valu": 0.5})
    with pytest.raises(TypeError, match="missing 1 required positional argument: 'value'"):
        built_from(Sample, {key: item for key, item in fields.items() if key != "value"})
    # the constructor's own checks run: __post_init__ here, ShaftSeries's range checks
    with pytest.raises(ValueError, match="count = -1"):
        built(Checked, count=-1)
    assert rebuilt(built(Checked, count=2), count=5) == Checked(count=5)
    with pytest.raises(ValueError, match="count = -1"):
        rebuilt(built(Checked, count=2), count=-1)
    with pytest.raises(ValueError, match=r"beta_deg\[0\] = 95"):
        checked_series((95.0,), (), "exact")


@dataclass(frozen=True, eq=False)
class Checked(Record):
    """A record whose constructor refuses a negative count."""

    count: int

    def __post_init__(self) -> None:
        if self.count < 0:
            raise ValueError(f"count = {self.count}; allowed: >= 0")


def test_no_record_skips_its_constructor():
    # Issue 33: records are made by their dataclasses' constructors, never by
    # object.__new__ and an update of the instance's dictionary.
    package = Path(sso.__file__).parent
    found = [f"{path.relative_to(package)}: {needle}"
             for path in sorted(package.rglob("*.py"))
             for needle in ("object.__new__", "__dict__.update")
             if needle in path.read_text(encoding="utf-8")]
    assert found == []
