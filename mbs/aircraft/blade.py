"""A main-rotor blade from its distributions along the span: chord, twist, mass and section
inertias per length, each a table of stations r/R (linear between stations, held beyond the
ends for chord and twist).

The rigid blade body is the part outboard of the flap hinge (radius ``e``): its mass
``m = ∫ μ dr``, first moment ``S = ∫ μ (r - e) dr`` and flap inertia
``I_β = ∫ μ (r - e)² dr + ∫ i_flap dr`` about the hinge, and its inertia tensor about its
centre of mass from the same integrals (the chordwise offset of the sections' centres of mass is
not modelled). Without section inertias a section is a box of the local chord and the blade
thickness. Without a mass table the blade is the uniform box of ``I_flap`` as before. Units SI.
"""
from __future__ import annotations

import numpy as np

GAUSS = np.polynomial.legendre.leggauss(3)  # exact for the cubic integrands of linear tables


def at(table, x: float) -> float:
    """Linear interpolation of a table's second column at ``x`` (its first column), held beyond."""
    rows = np.asarray(table, float)
    return float(np.interp(x, rows[:, 0], rows[:, 1]))


def _integral(f, a: float, b: float, breaks: np.ndarray) -> float:
    """``∫_a^b f(r) dr`` by 3-point Gauss–Legendre on each piece between ``breaks``."""
    points = np.unique(np.clip(np.r_[a, breaks, b], a, b))
    x, w = GAUSS
    total = 0.0
    for lo, hi in zip(points[:-1], points[1:]):
        r = 0.5 * (hi - lo) * x + 0.5 * (hi + lo)
        total += 0.5 * (hi - lo) * float(np.dot(w, f(r)))
    return total


class Distribution:
    """The blade of the main-rotor data ``mr`` (SI) as distributed along the span."""

    def __init__(self, mr: dict):
        self.radius, self.hinge = mr["radius"], mr["flap_hinge_offset"]
        self.mass_rows = np.asarray(mr["mass_table"], float)
        self.breaks = self.mass_rows[:, 0] * self.radius
        chord = mr.get("chord_table") or [[0.0, mr["chord"]], [1.0, mr["chord"]]]
        self.chord_rows, self.thickness = np.asarray(chord, float), mr["blade_thickness"]
        sections = mr.get("section_inertia_table")
        self.section_rows = np.asarray(sections, float) if sections else None
        self.breaks = np.unique(np.r_[self.breaks, self.chord_rows[:, 0] * self.radius,
                                      [] if self.section_rows is None else self.section_rows[:, 0] * self.radius])

    def mass_per_length(self, r):
        """kg/m at radii ``r`` (m); zero outside the table."""
        rows = self.mass_rows
        return np.interp(r / self.radius, rows[:, 0], rows[:, 1], left=0.0, right=0.0)

    def section_inertias(self, r) -> tuple:
        """Flap, lag and torsion inertia per length (kg m) at radii ``r`` (m)."""
        if self.section_rows is not None:
            rows = self.section_rows
            return tuple(np.interp(r / self.radius, rows[:, 0], rows[:, k], left=0.0, right=0.0) for k in (1, 2, 3))
        mu = self.mass_per_length(r)
        chord = np.interp(r / self.radius, self.chord_rows[:, 0], self.chord_rows[:, 1])
        flap, lag = mu * self.thickness**2 / 12, mu * chord**2 / 12
        return flap, lag, flap + lag

    def integral(self, f, inboard: bool = False) -> float:
        """``∫ f(r) dr`` over the blade body (hinge to tip), or inboard of the hinge."""
        a, b = (0.0, self.hinge) if inboard else (self.hinge, self.radius)
        return _integral(f, a, b, self.breaks)

    @property
    def mass(self) -> float:
        return self.integral(self.mass_per_length)

    @property
    def first_moment(self) -> float:
        return self.integral(lambda r: self.mass_per_length(r) * (r - self.hinge))

    @property
    def flap_inertia(self) -> float:
        """About the flap hinge, kg m²."""
        return self.integral(lambda r: self.mass_per_length(r) * (r - self.hinge) ** 2 + self.section_inertias(r)[0])

    @property
    def lag_inertia(self) -> float:
        """About the lag hinge (at the flap hinge), kg m²."""
        return self.integral(lambda r: self.mass_per_length(r) * (r - self.hinge) ** 2 + self.section_inertias(r)[1])

    @property
    def inboard_mass(self) -> float:
        """The table's mass inboard of the flap hinge (not part of the blade body), kg."""
        return self.integral(self.mass_per_length, inboard=True)

    def body(self) -> tuple[float, np.ndarray, np.ndarray]:
        """Mass (kg), centre of mass (3,) and inertia tensor about it (3, 3) in blade axes (x along
        the span from the hinge, y towards the leading edge, z normal)."""
        m = self.mass
        xc = self.first_moment / m
        spread = self.integral(lambda r: self.mass_per_length(r) * (r - self.hinge - xc) ** 2)
        flap, lag, torsion = (self.integral(lambda r, k=k: self.section_inertias(r)[k]) for k in range(3))
        return m, np.array([xc, 0.0, 0.0]), np.diag([torsion, spread + flap, spread + lag])


def equivalent_chord(rows, cutout: float) -> float:
    """The thrust-weighted chord ``∫ c r² dr / ∫ r² dr`` over the aerodynamic blade (r/R from
    ``cutout`` to 1), m."""
    r = np.linspace(cutout, 1.0, 2001)
    c = np.interp(r, np.asarray(rows)[:, 0], np.asarray(rows)[:, 1])
    return float(np.trapezoid(c * r**2, r) / np.trapezoid(r**2, r))


def equivalent_twist(rows, cutout: float) -> float:
    """The linear twist (tip minus axis, rad) of the straight line through the twist table over
    the aerodynamic blade, fitted with the weight r² (where the thrust comes from)."""
    r = np.linspace(cutout, 1.0, 2001)
    theta = np.interp(r, np.asarray(rows)[:, 0], np.asarray(rows)[:, 1])
    slope, _ = np.polyfit(r, theta, 1, w=r)  # polyfit weights multiply the residuals: w = r gives r²
    return float(slope)
