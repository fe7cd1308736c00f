"""A propshaft's tube and its first bending (whirl) critical speed.

A uniform tube, simply supported at its joint centres (Euler-Bernoulli beam): the first
bending mode turns at

    n_c = (30 / pi) (pi / L)^2 sqrt(E I / (rho A))  rpm
        = (30 pi / 4) sqrt(E / rho) sqrt(D^2 + d^2) / L^2

with ``I = pi (D^4 - d^4) / 64`` and ``A = pi (D^2 - d^2) / 4`` (SI units inside). The
safe speed is a fraction of it: 0.70 for automotive shafts, 0.65 for industrial ones
(IMS Ltd, "SAE joint selection graph"). The length at which a shaft must be split is
the one whose safe speed equals the maximum shaft speed (``n_c`` falls as ``1 / L^2``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from sso._record import register_record
from sso._validation import finite_in_range

STEEL_YOUNGS_MODULUS_GPA = 207.0
STEEL_DENSITY_KG_M3 = 7850.0
SAFE_SPEED_FRACTION = {"automotive": 0.70, "industrial": 0.65}
"""Safe fraction of the critical speed by application (IMS Ltd)."""


@register_record
@dataclass(frozen=True)
class Tube:
    """A propshaft's tube: a uniform circular tube of one material.

    Parameters
    ----------
    outside_diameter_mm : float
        Outside diameter ``D``, mm, in ``(0, 2000]``.
    wall_mm : float
        Wall thickness, mm, ``> 0`` and below the radius ``D / 2`` (a solid shaft is
        not a tube: give it as a wall just under ``D / 2``).
    youngs_modulus_gpa : float
        ``E``, GPa, in ``(0, 1000]``; steel 207 by default.
    density_kg_m3 : float
        ``rho``, kg/m^3, in ``(0, 25000]``; steel 7850 by default.

    Raises
    ------
    ValueError
        Naming the field, its value and the allowed range.
    """

    outside_diameter_mm: float
    wall_mm: float
    youngs_modulus_gpa: float = STEEL_YOUNGS_MODULUS_GPA
    density_kg_m3: float = STEEL_DENSITY_KG_M3

    def __post_init__(self) -> None:
        diameter = finite_in_range("outside_diameter_mm", self.outside_diameter_mm, 0.0,
                                   2000.0, "mm", lower_open=True)
        wall = finite_in_range("wall_mm", self.wall_mm, 0.0, diameter / 2.0, "mm",
                               lower_open=True, upper_open=True)
        modulus = finite_in_range("youngs_modulus_gpa", self.youngs_modulus_gpa, 0.0, 1000.0,
                                  "GPa", lower_open=True)
        density = finite_in_range("density_kg_m3", self.density_kg_m3, 0.0, 25000.0,
                                  "kg/m^3", lower_open=True)
        for name, value in (("outside_diameter_mm", diameter), ("wall_mm", wall),
                            ("youngs_modulus_gpa", modulus), ("density_kg_m3", density)):
            object.__setattr__(self, name, value)

    @property
    def inside_diameter_mm(self) -> float:
        """``d = D - 2 wall``, mm."""
        return self.outside_diameter_mm - 2.0 * self.wall_mm

    def critical_speed_rpm(self, length_mm: float) -> float:
        """First bending critical speed of this tube over ``length_mm`` between supports, rpm.

        Raises
        ------
        ValueError
            If the length is not finite and positive.
        """
        length_m = finite_in_range("length_mm", length_mm, 0.0, math.inf, "mm",
                                   lower_open=True) / 1000.0
        outside_m = self.outside_diameter_mm / 1000.0
        inside_m = self.inside_diameter_mm / 1000.0
        modulus_pa = self.youngs_modulus_gpa * 1e9
        stiffness_per_mass = modulus_pa * (outside_m**2 + inside_m**2) / (16.0 * self.density_kg_m3)
        omega_rad_s = (math.pi / length_m) ** 2 * math.sqrt(stiffness_per_mass)
        return omega_rad_s * 30.0 / math.pi

    def split_length_mm(self, length_mm: float, shaft_speed_rpm: float,
                        safe_fraction: float) -> float:
        """The length (mm) at which ``safe_fraction`` of the critical speed equals the speed."""
        critical = self.critical_speed_rpm(length_mm)
        return length_mm * math.sqrt(safe_fraction * critical / shaft_speed_rpm)
