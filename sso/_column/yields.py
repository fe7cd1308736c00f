"""The yield of built columns against a case's ``[limits]``, with its confidence interval.

The yield of a limit is the fraction of sampled built columns whose figure meets it
(at most the limit); the yield of all limits together, the fraction meeting every
one. Each comes with its Wilson score interval (E. B. Wilson, "Probable inference,
the law of succession, and statistical inference", J. Amer. Statist. Assoc. 22
(1927) 209-212): the proportions ``p`` whose score test ``|k/n - p| <= z sqrt(p (1 -
p) / n)`` does not reject ``k`` of ``n`` passing, ``z`` the normal quantile of the
two-sided confidence (1.96 at 95 %). Unlike ``k/n +- z sqrt(...)`` it stays inside
``[0, 1]`` and keeps its coverage when ``k`` is 0 or ``n`` (a perfect sample).

The verdict against a required yield ``y`` (``[limits] yield``) reads the interval
of all limits together, ``[low, high]``:

* ``"meets"`` when ``low >= y``: the sample shows the yield is at least ``y``;
* ``"fails"`` when ``high < y``: the sample shows it is below ``y``;
* ``"not decided"`` otherwise: the interval straddles ``y``. More samples narrow it:
  :func:`deciding_samples` gives the count at which Wilson's half-width at the
  observed yield ``p`` falls below ``|p - y|``, so that the same yield would be
  decided (about; a new sample's yield moves too).

Only ``"meets"`` signs a column off: ``sso tolerance``, ``sso run`` and ``sso evaluate``
exit 1 on the other two.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from statistics import NormalDist

import numpy as np

from sso._column.steering_criteria import SteeringLimits
from sso._display import format_number
from sso._record import register_record
from sso._validation import finite_in_range

CONFIDENCE = 0.95
"""Two-sided confidence of every yield's interval."""
VERDICTS = ("meets", "fails", "not decided", "not judged")
ALL_LIMITS = "all limits together"

# (limit of SteeringLimits, figure of a built column, label, unit)
COLUMN_LIMITS = (
    ("speed_fluctuation_percent", "speed_fluctuation_percent",
     "speed-ratio fluctuation, lock to lock", "%"),
    ("torque_fluctuation_percent", "torque_fluctuation_percent",
     "output-torque fluctuation, lock to lock", "%"),
    ("transmission_error_deg", "largest_transmission_error_deg",
     "largest |transmission error|, lock to lock", "deg"),
    ("max_operating_angle_deg", "largest_operating_angle_deg", "largest operating angle", "deg"),
)


def wilson_interval(passed: int, samples: int,
                    confidence: float = CONFIDENCE) -> tuple[float, float]:
    """Wilson score interval of a proportion: ``passed`` of ``samples`` (module notes).

    Raises
    ------
    ValueError
        If ``samples < 1``, ``passed`` is outside ``[0, samples]`` or ``confidence``
        outside ``(0, 1)``.
    """
    if samples < 1 or not 0 <= passed <= samples:
        raise ValueError(f"passed = {passed} of samples = {samples}: need samples >= 1 and "
                         "0 <= passed <= samples")
    z = _normal_quantile(confidence)
    fraction = passed / samples
    centre = (fraction + z * z / (2.0 * samples)) / (1.0 + z * z / samples)
    half = _wilson_half_width(fraction, samples, z)
    return max(0.0, centre - half), min(1.0, centre + half)


def deciding_samples(fraction: float, required: float,
                     confidence: float = CONFIDENCE) -> int | None:
    """The fewest samples at which the Wilson half-width at ``fraction`` falls below
    ``|fraction - required|``: about the sample that would decide a yield ``fraction``
    against ``required`` (module notes); None when they are equal (no sample decides).

    Raises
    ------
    ValueError
        If ``fraction`` or ``required`` is outside ``[0, 1]`` or ``confidence``
        outside ``(0, 1)``.
    """
    fraction = finite_in_range("fraction", fraction, 0.0, 1.0)
    distance = abs(fraction - finite_in_range("required", required, 0.0, 1.0))
    z = _normal_quantile(confidence)
    if distance == 0.0:
        return None
    # The half-width falls as the count grows: double past the count, then bisect.
    low, high = 0, 1
    while _wilson_half_width(fraction, high, z) >= distance:
        low, high = high, 2 * high
    while high - low > 1:
        middle = (low + high) // 2
        low, high = (middle, high) if _wilson_half_width(fraction, middle, z) >= distance \
            else (low, middle)
    return high


def _normal_quantile(confidence: float) -> float:
    """``z``: the normal quantile of a two-sided ``confidence``."""
    finite_in_range("confidence", confidence, 0.0, 1.0, lower_open=True, upper_open=True)
    return NormalDist().inv_cdf(0.5 + confidence / 2.0)


def _wilson_half_width(fraction: float, samples: int, z: float) -> float:
    """Half the width of Wilson's interval of ``fraction`` over ``samples``."""
    return z / (1.0 + z * z / samples) * math.sqrt(fraction * (1.0 - fraction) / samples
                                                    + z * z / (4.0 * samples * samples))


@register_record
@dataclass(frozen=True)
class LimitYield:
    """The yield of one limit (or of all together) over a sample of built columns.

    Attributes
    ----------
    figure : str
        The figure judged (``"speed_fluctuation_percent"``, ...; ``"all"`` for every
        limit together).
    label, unit : str
        The figure in words and its unit.
    limit : float or None
        The largest value that passes, in ``unit`` (None for all together).
    passed, samples : int
        Built columns meeting the limit, and built columns drawn.
    low, high : float
        Its Wilson score interval at :data:`CONFIDENCE` (fractions).
    """

    figure: str
    label: str
    unit: str
    limit: float | None
    passed: int
    samples: int
    low: float
    high: float

    @property
    def fraction(self) -> float:
        """The yield: ``passed / samples``."""
        return self.passed / self.samples

    @property
    def text(self) -> str:
        """The yield, its interval in percent, the interval's width and the sample count,
        as reports print it."""
        return (f"{percent(self.fraction)} (95 % CI {percent(self.low)} to "
                f"{percent(self.high)}, width {percent(self.high - self.low)}, "
                f"{self.samples:,} samples)")


@register_record
@dataclass(frozen=True)
class YieldJudgement:
    """The yields of a sample of built columns against limits, and the verdict.

    Attributes
    ----------
    limits : tuple of LimitYield
        One per limit set, in :data:`COLUMN_LIMITS` order.
    together : LimitYield
        Every limit at once.
    required : float or None
        The required yield (``[limits] yield``), a fraction; None: not judged.
    """

    limits: tuple[LimitYield, ...]
    together: LimitYield
    required: float | None

    @property
    def verdict(self) -> str:
        """One of :data:`VERDICTS` (module notes)."""
        if self.required is None:
            return "not judged"
        if self.together.low >= self.required:
            return "meets"
        return "fails" if self.together.high < self.required else "not decided"

    @property
    def deciding_samples(self) -> int | None:
        """When the verdict is ``"not decided"``: about the samples that would decide
        it (:func:`deciding_samples`), or None when the yield equals the requirement;
        else None."""
        if self.verdict != "not decided":
            return None
        assert self.required is not None
        return deciding_samples(self.together.fraction, self.required)

    @property
    def verdict_text(self) -> str:
        """The verdict in a table cell: with the required yield, and for one not
        decided the samples it was judged on and those that would decide it."""
        if self.required is None:
            return self.verdict
        if self.verdict != "not decided":
            return f"{self.verdict} {percent(self.required)}"
        return (f"not decided {percent(self.required)} at {self.together.samples:,} samples "
                f"({self._deciding_words})")

    @property
    def _deciding_words(self) -> str:
        needed = self.deciding_samples
        return ("no sample count decides a yield equal to the requirement" if needed is None
                else f"about {needed:,} samples would decide it")

    @property
    def signed_off(self) -> bool:
        """True when the verdict is ``"meets"`` or nothing is required."""
        return self.verdict in ("meets", "not judged")

    @property
    def sentence(self) -> str:
        """The verdict in words."""
        together = f"yield of {ALL_LIMITS} {self.together.text}"
        if self.required is None:
            return (f"{together}; no required yield set ([limits] yield): the yield is "
                    "reported, not judged")
        required = percent(self.required)
        return {
            "meets": f"MEETS the required yield {required}: {together}, its lower bound at or "
                     "above it",
            "fails": f"FAILS the required yield {required}: {together}, its upper bound below "
                     "it",
            "not decided": f"NOT DECIDED at {self.together.samples:,} samples against the "
                           f"required yield {required}: {together} straddles it; "
                           f"{self._deciding_words} (Wilson's half-width below the distance "
                           "from the yield to the requirement)",
        }[self.verdict]


def percent(fraction: float) -> str:
    """A fraction in percent, to 0.1 %."""
    return f"{100.0 * fraction:.1f} %"


def judge_yields(figures: Mapping[str, np.ndarray],
                 limits: Sequence[tuple[str, str, str, float]],
                 required: float | None) -> YieldJudgement:
    """The yield of each limit and of all together, and the verdict.

    Parameters
    ----------
    figures : mapping of str to numpy.ndarray
        Each figure's value per built column (one value per sample, same length).
    limits : sequence of (figure, label, unit, limit)
        The limits judged: a figure at most ``limit`` passes. At least one.
    required : float or None
        The required yield, in ``(0, 1]``; None judges nothing.

    Raises
    ------
    ValueError
        For no limits, no samples, or a required yield outside ``(0, 1]``.
    """
    if not limits:
        raise ValueError("limits is empty: give at least one (figure, label, unit, limit)")
    if required is not None:
        required = finite_in_range("yield", required, 0.0, 1.0, lower_open=True)
    passing = [np.asarray(figures[figure]) <= limit for figure, _, _, limit in limits]
    count = len(passing[0])
    if count < 1:
        raise ValueError("no built columns to judge: samples must be >= 1")
    judged = tuple(_limit_yield(figure, label, unit, limit, mask)
                   for (figure, label, unit, limit), mask in zip(limits, passing, strict=True))
    together = _limit_yield("all", ALL_LIMITS, "", None, np.logical_and.reduce(passing))
    return YieldJudgement(limits=judged, together=together, required=required)


def _limit_yield(figure: str, label: str, unit: str, limit: float | None,
                 mask: np.ndarray) -> LimitYield:
    passed, samples = int(np.count_nonzero(mask)), len(mask)
    low, high = wilson_interval(passed, samples)
    return LimitYield(figure=figure, label=label, unit=unit, limit=limit, passed=passed,
                      samples=samples, low=low, high=high)


def column_limits(limits: SteeringLimits) -> tuple[tuple[str, str, str, float], ...]:
    """The limits a case sets, as :func:`judge_yields` takes them (figures of
    :data:`COLUMN_LIMITS`; the largest operating angle always has one)."""
    chosen = []
    for name, figure, label, unit in COLUMN_LIMITS:
        value = getattr(limits, name)
        if value is not None:
            chosen.append((figure, label, unit, float(value)))
    return tuple(chosen)


def limit_text(item: LimitYield) -> str:
    """``"at most 2 %"``, or ``"every limit"`` for all together."""
    return "every limit" if item.limit is None else (
        f"at most {format_number(item.limit)} {item.unit}")
