"""Building blocks shared by the planar vector-loop solvers.

Points and link vectors are complex numbers ``x + iy``; every function works
element-wise on numpy arrays of crank positions. A position that does not exist
comes back as NaN together with a ``False`` entry in the returned mask, so the
caller decides what to do with it.
"""

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]
BoolArray = NDArray[np.bool_]


def circle_circle_intersection(
    first_centre: ArrayLike,
    first_radius: float,
    second_centre: ArrayLike,
    second_radius: float,
    side: int,
) -> tuple[ComplexArray, BoolArray]:
    """Intersect two circles and pick one of the two points by side.

    Parameters
    ----------
    first_centre, second_centre : array_like of complex
        Centres of the circles (length units), broadcast against each other.
    first_radius, second_radius : float
        Radii of the circles (length units).
    side : {1, -1}
        ``1`` picks the point to the left of the directed line from the first
        centre to the second, ``-1`` the point to its right.

    Returns
    -------
    point : ndarray of complex
        The chosen intersection; NaN where the circles do not meet.
    meets : ndarray of bool
        ``True`` where the circles meet (touching counts as meeting).
    """
    first_centre = np.asarray(first_centre, dtype=complex)
    offset = np.asarray(second_centre, dtype=complex) - first_centre
    distance = np.abs(offset)
    with np.errstate(divide="ignore", invalid="ignore"):
        along = (first_radius**2 - second_radius**2 + distance**2) / (2.0 * distance)
        half_chord_squared = first_radius**2 - along**2
        meets = (distance > 0.0) & (half_chord_squared >= 0.0)
        direction = offset / distance
    half_chord = np.sqrt(np.where(meets, half_chord_squared, np.nan))
    point = first_centre + direction * (along + 1j * side * half_chord)
    return point, meets


def circle_horizontal_line_intersection(
    centre: ArrayLike, radius: float, line_height: float
) -> tuple[ComplexArray, BoolArray]:
    """Intersect a circle with the line ``y = line_height``, keeping the larger x.

    Parameters
    ----------
    centre : array_like of complex
        Centre of the circle (length units).
    radius : float
        Radius of the circle (length units).
    line_height : float
        Height of the horizontal line (length units).

    Returns
    -------
    point : ndarray of complex
        The intersection with the larger x; NaN where the circle misses the line.
    meets : ndarray of bool
        ``True`` where the circle reaches the line (touching counts).
    """
    centre = np.asarray(centre, dtype=complex)
    half_chord_squared = radius**2 - (line_height - centre.imag) ** 2
    meets = half_chord_squared >= 0.0
    half_chord = np.sqrt(np.where(meets, half_chord_squared, np.nan))
    return centre.real + half_chord + 1j * line_height, meets


def solve_real_pair(
    known: ArrayLike, first: ArrayLike, second: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """Solve ``known + x * first + y * second = 0`` for real ``x`` and ``y``.

    This is the velocity or acceleration equation of a vector loop: the
    complex equation holds two real equations for two real unknowns, solved
    here by Cramer's rule.

    Parameters
    ----------
    known : array_like of complex
        Sum of the terms that do not contain the unknowns.
    first, second : array_like of complex
        Coefficients of the unknowns ``x`` and ``y``.

    Returns
    -------
    x, y : ndarray of float
        The unknowns; non-finite where ``first`` and ``second`` are parallel
        (a dead point, where the loop cannot be driven).
    """
    known, first, second = (np.asarray(value, dtype=complex) for value in (known, first, second))
    determinant = _cross(first, second)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = _cross(second, known) / determinant
        y = _cross(known, first) / determinant
    return x, y


def _cross(left: ComplexArray, right: ComplexArray) -> FloatArray:
    """The z-component of the planar cross product ``left × right``."""
    return left.real * right.imag - left.imag * right.real
