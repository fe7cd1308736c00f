"""Choice of the number of quadrature angles: the fewest that reach a tolerance."""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from sso.shafts.objective import angle_grid, squared_ratio_error

DEFAULT_RTOL = 1e-10
DEFAULT_ATOL = 1e-16
MIN_SAMPLES = 8
MAX_SAMPLES = 8192


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
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
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
        return squared_ratio_error(np, cos_theta, sin_theta, beta_rad, phase_rad, model)

    return adaptive_rule(squared_errors, rtol, atol, max_samples)


def adaptive_rule(
    squared_errors: Callable[[int], np.ndarray],
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
    max_samples: int = MAX_SAMPLES,
) -> tuple[float, QuadratureRule]:
    """Rectangle rule on the fewest angles whose doubling changes RE within tolerance.

    Starting from 8 angles, the count doubles until ``|RE(2N) - RE(N)| <=
    rtol * |RE(2N)| + atol``; ``N`` is then used and the difference reported as its
    error (convergence is geometric, so ``RE(2N)`` is far more accurate).

    Parameters
    ----------
    squared_errors : callable
        ``squared_errors(count)``: ``(w_out/w_in - 1)^2`` at ``count`` equally
        spaced input angles in ``[0, 180)`` deg, starting at 0.
    rtol, atol : float
        Relative tolerance and absolute floor (dimensionless).
    max_samples : int
        Cap on the angle count; reaching it warns with :class:`QuadratureWarning`.

    Returns
    -------
    (float, QuadratureRule)
        RE at the chosen count, and the rule used.
    """
    samples = MIN_SAMPLES
    while True:
        terms = squared_errors(2 * samples)
        coarse = float(np.mean(terms[::2]))
        fine = float(np.mean(terms))
        difference = abs(fine - coarse)
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
    rtol: float = DEFAULT_RTOL,
    atol: float = DEFAULT_ATOL,
    max_samples: int = MAX_SAMPLES,
) -> QuadratureRule:
    """Angle count that serves every design whose operating angles stay in bounds.

    The integrand is least smooth when every joint sits at its largest allowed
    angle with all phases zero (the chain then acts as one joint with
    ``cos B = prod cos beta_k``), so the count chosen for that design serves the
    whole box and the optimiser's problem keeps one shape. Rules are remembered
    per box, so a batch of solves in one box pays for the choice once.
    """
    rule = _rule_for_bounds(tuple(float(beta) for beta in beta_upper_rad), model, rtol, atol,
                            max_samples)
    if not rule.converged:
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
