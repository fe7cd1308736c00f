"""sso._display: six significant digits, round-off printed as the floor, and the
default summary of a result from its plain fields."""

from dataclasses import dataclass

import numpy as np
import pytest

from sso._display import FLOOR_TEXT, Readable, format_number
from sso._limits import ROUND_OFF_FLOOR


@pytest.mark.parametrize("value, text", [
    (0.0, "0"), (7.8e-31, FLOOR_TEXT), (-3e-17, FLOOR_TEXT), (ROUND_OFF_FLOOR, FLOOR_TEXT),
    (2.1e-15, "2.1e-15"), (0.00349849123, "0.00349849"), (1234567.0, "1.23457e+06"),
    (None, "n/a"), (float("nan"), "n/a"), (3, "3"), (True, "True"),
])
def test_numbers_have_six_digits_and_round_off_prints_as_the_floor(value, text):
    assert format_number(value) == text


def test_a_result_without_its_own_summary_reads_from_its_plain_fields():
    @dataclass(frozen=True, repr=False)
    class Outcome(Readable):
        fun: float
        x: tuple[float, ...]
        message: str
        samples: np.ndarray

    outcome = Outcome(3e-31, (90.0, 45.5), "done", np.zeros(1000))
    assert repr(outcome) == "Outcome(fun=< 1e-15, x=[90, 45.5], message=done)"
    assert "fun      < 1e-15" in outcome.summary().splitlines()
