"""Choice of the number of quadrature angles: the fewest that reach a tolerance.

The rectangle rule on a smooth periodic integrand converges geometrically, and
comparing ``N`` angles against ``2N`` estimates the error well once the grid
resolves the integrand's narrowest peak. Near 90 deg a joint's speed ratio has a
peak of height ``1/cos beta`` and width about ``cos beta`` rad; a grid coarser
than that misses the peak at both counts and the comparison agrees on a wrong
answer. So the count starts where the grid resolves the peak: the integrand is
analytic in a strip ``|Im theta| < d`` around the real axis with

* paper model: ``d = atanh(min_k cos beta_k)`` (every joint sees the input angle);
* exact model: ``d >= atanh(prod_k cos beta_k)`` (each joint widens the next
  joint's peak in the input angle by at most ``1/cos beta``; equality for zero
  phases, where the chain acts as one joint),

and the rule needs ``N * d >= RESOLUTION`` before its doubling test is trusted
(the rectangle rule's error falls like ``exp(-2 N d)``). A design that would need
more than the cap is reported unconverged, with a :class:`QuadratureWarning`,
never as converged.
"""

from __future__ import annotations

import functools
import math
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from sso._limits import DEFAULT_QUADRATURE_ATOL, DEFAULT_QUADRATURE_RTOL
from sso._shafts.objective import angle_grid, squared_ratio_error

MIN_SAMPLES = 8
MAX_SAMPLES = 8192
"""Cap of the optimiser's rule (the graph's evaluation cost grows with it)."""
EVALUATION_MAX_SAMPLES = 262144
"""Cap of the rule of :func:`sso.evaluate` (numpy; 2x this many angles are sampled)."""
RESOLUTION = 4.0
"""Least ``N * d`` (angles times the strip half-width, rad) at which the rule's
doubling test is trusted: the grid then puts about ``N d / pi`` >= 1.3 angles across
the narrowest peak and the rule's error ``~exp(-2 N d)`` already falls geometrically."""


class QuadratureWarning(UserWarning):
    """The quadrature reached its cap of angles before meeting its tolerance."""


@dataclass(frozen=True)
class QuadratureRule:
    """How the residual error was integrated.

    Attributes
    ----------
    samples : int
        Equally spaced input angles in ``[0, 180)`` deg.
    error_estimate : float
        Estimated absolute error of RE at ``samples`` angles (dimensionless): the
        change against twice as many angles.
    converged : bool
        False when the cap was reached before the tolerance was met.
    """

    samples: int
    error_estimate: float
    converged: bool


def adaptive_residual_error(
    beta_rad: Sequence[float],
    phase_rad: Sequence[float],
    model: str,
    rtol: float = DEFAULT_QUADRATURE_RTOL,
    atol: float = DEFAULT_QUADRATURE_ATOL,
    max_samples: int = MAX_SAMPLES,
) -> tuple[float, QuadratureRule]:
    """Residual error with the fewest angles whose doubling changes it within tolerance.

    See :func:`adaptive_rule`; this evaluates the chain afresh at each count.

    Parameters
    ----------
    beta_rad, phase_rad : sequence of float
        The design (rad).
    model : {"exact", "paper"}
        Chain model.
    rtol, atol : float
        Relative tolerance and absolute floor (dimensionless).
    max_samples : int
        Cap on the angle count; reaching it warns with :class:`QuadratureWarning`.

    Returns
    -------
    (float, QuadratureRule)
        RE at the chosen count, and the rule used.
    """
    def squared_errors(count: int) -> np.ndarray:
        cos_theta, sin_theta = angle_grid(count)
        squared: np.ndarray = squared_ratio_error(np, cos_theta, sin_theta, beta_rad, phase_rad,
                                                  model)
        return squared

    return adaptive_rule(squared_errors, rtol, atol, max_samples,
                         resolving_samples(beta_rad, model))


def analytic_half_width(beta_rad: Sequence[float], model: str) -> float:
    """Half-width ``d`` (rad) of the strip around the real axis where RE's integrand
    is analytic (a lower bound for the exact model); see the module docstring.

    Returns ``inf`` for straight shafts and ``0`` when the cosines underflow.
    """
    cosines = np.abs(np.cos(np.asarray(beta_rad, dtype=float)))
    if cosines.size == 0:
        return math.inf
    narrowest = float(np.prod(cosines)) if model == "exact" else float(np.min(cosines))
    return math.inf if narrowest >= 1.0 else float(np.arctanh(narrowest))


def resolving_samples(beta_rad: Sequence[float], model: str) -> float:
    """Fewest angles over 180 deg whose grid resolves the narrowest peak of the
    integrand (``RESOLUTION / d``; ``inf`` if no count does)."""
    width = analytic_half_width(beta_rad, model)
    return math.inf if width <= 0.0 else RESOLUTION / width


def adaptive_rule(
    squared_errors: Callable[[int], np.ndarray],
    rtol: float = DEFAULT_QUADRATURE_RTOL,
    atol: float = DEFAULT_QUADRATURE_ATOL,
    max_samples: int = MAX_SAMPLES,
    least_samples: float = MIN_SAMPLES,
) -> tuple[float, QuadratureRule]:
    """Rectangle rule on the fewest angles whose doubling changes RE within tolerance.

    Starting from the first power of two (at least 8) not below ``least_samples``,
    the count doubles until ``|RE(2N) - RE(N)| <= rtol * |RE(2N)| + atol``; ``N`` is
    then used and the difference reported as its error (convergence is geometric,
    so ``RE(2N)`` is far more accurate). When ``least_samples`` exceeds the cap the
    grid cannot resolve the integrand: RE at the cap is returned unconverged (its
    error estimate is then only a lower bound) with a warning.

    Parameters
    ----------
    squared_errors : callable
        ``squared_errors(count)``: ``(w_out/w_in - 1)^2`` at ``count`` equally
        spaced input angles in ``[0, 180)`` deg, starting at 0.
    rtol, atol : float
        Relative tolerance and absolute floor (dimensionless).
    max_samples : int
        Cap on the angle count; reaching it warns with :class:`QuadratureWarning`.
    least_samples : float
        Fewest angles that resolve the integrand (see :func:`resolving_samples`).

    Returns
    -------
    (float, QuadratureRule)
        RE at the chosen count, and the rule used.
    """
    samples = MIN_SAMPLES
    while samples < least_samples and samples < max_samples:
        samples *= 2
    resolved = samples >= least_samples
    while True:
        terms = squared_errors(2 * samples)
        coarse = float(np.mean(terms[::2]))
        fine = float(np.mean(terms))
        difference = abs(fine - coarse)
        if not resolved:
            rule = QuadratureRule(samples, difference, False)
            _warn_unresolved(rule, least_samples)
            return coarse, rule
        if difference <= rtol * abs(fine) + atol:
            return coarse, QuadratureRule(samples, difference, True)
        if 2 * samples > max_samples:
            rule = QuadratureRule(samples, difference, False)
            _warn_capped(rule, rtol, atol)
            return coarse, rule
        samples *= 2


def rule_for_bounds(
    beta_upper_rad: Sequence[float],
    model: str,
    rtol: float = DEFAULT_QUADRATURE_RTOL,
    atol: float = DEFAULT_QUADRATURE_ATOL,
    max_samples: int = MAX_SAMPLES,
) -> QuadratureRule:
    """Angle count that serves every design whose operating angles stay in bounds.

    The integrand is least smooth when every joint sits at its largest allowed
    angle with all phases zero (the chain then acts as one joint with
    ``cos B = prod cos beta_k``), so the count chosen for that design serves the
    whole box and the optimiser's problem keeps one shape. Rules are remembered
    per box, so a batch of solves in one box pays for the choice once.
    """
    upper = tuple(float(beta) for beta in beta_upper_rad)
    rule = _rule_for_bounds(upper, model, rtol, atol, max_samples)
    if not rule.converged:
        least_samples = resolving_samples(upper, model)
        if least_samples > rule.samples:
            _warn_unresolved(rule, least_samples)
        else:
            _warn_capped(rule, rtol, atol)
    return rule


@functools.lru_cache(maxsize=256)
def _rule_for_bounds(beta_upper_rad: tuple[float, ...], model: str, rtol: float, atol: float,
                     max_samples: int) -> QuadratureRule:
    worst_phases = [0.0] * (len(beta_upper_rad) - 1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", QuadratureWarning)
        _, rule = adaptive_residual_error(list(beta_upper_rad), worst_phases, model, rtol, atol,
                                          max_samples)
    return rule


def _warn_capped(rule: QuadratureRule, rtol: float, atol: float) -> None:
    warnings.warn(
        f"the residual-error quadrature reached its cap of {rule.samples} angles "
        f"with an estimated error of {rule.error_estimate:.3g} (tolerance "
        f"{rtol:g} relative + {atol:g}); operating angles near 90 deg need more",
        QuadratureWarning,
        stacklevel=4,
    )


def _warn_unresolved(rule: QuadratureRule, least_samples: float) -> None:
    needed = "more than any count" if math.isinf(least_samples) else f"{least_samples:.3g}"
    warnings.warn(
        f"the residual-error quadrature cannot resolve the speed-ratio peaks of "
        f"operating angles this close to 90 deg: they need {needed} angles over "
        f"180 deg and the cap is {rule.samples}; the residual error and speed "
        f"figures are not reliable (quadrature_converged is False)",
        QuadratureWarning,
        stacklevel=4,
    )
