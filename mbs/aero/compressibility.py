"""Compressibility of a blade section: Prandtl–Glauert lift slope and drag divergence.

Section Mach number ``M = W / a_sound`` from the blade-element velocity ``W`` in the chord–normal
plane (m/s). Lift slope ``a / sqrt(1 − M_b²)`` with ``M_b`` the Mach number bounded smoothly
below ``mach_limit`` (the Prandtl–Glauert factor stays finite); profile drag rises by Lock's
fourth-power law ``Δc_d = 20 (M − M_cr)⁴`` beyond ``M_cr = M_dd − 0.1``, which gives
``Δc_d = 0.002`` at the drag-divergence Mach number ``M_dd``. The bound is a smooth clip
(:func:`mbs.aero.sections.soft_clip` of order 16): 0.2 % below the plain factor at M = 0.64,
the hover tip.

Sources: Prandtl–Glauert rule (J. D. Anderson, *Fundamentals of Aerodynamics*, §11.4); Lock's
drag-rise law (Hilton, *High-Speed Aerodynamics*, 1951; as used in W. Johnson, *Rotorcraft
Aeromechanics*, §7.3).
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca

from mbs.aero.sections import Airfoil, soft_clip

LOCK_RISE = 20.0  # Lock's law coefficient
CRITICAL_MARGIN = 0.1  # M_dd − M_cr


@dataclass(frozen=True)
class Compressibility:
    """Speed of sound (m/s), drag-divergence Mach number, bound of the Prandtl–Glauert Mach number."""

    speed_of_sound: float
    mach_dd: float
    mach_limit: float = 0.8

    def mach(self, speed):
        """Section Mach number of the air speed ``speed`` (m/s)."""
        return speed * (1.0 / self.speed_of_sound)

    def glauert_factor(self, mach):
        """``1 / sqrt(1 − M_b²)`` with ``M_b`` bounded below ``mach_limit``."""
        bounded = soft_clip(mach, self.mach_limit, 16)
        return 1 / ca.sqrt(1 - bounded**2)

    def drag_rise(self, mach):
        """``Δc_d = 20 max(0, M − M_cr)⁴`` (Lock), ``M_cr = M_dd − 0.1``."""
        return LOCK_RISE * ca.fmax(0, mach - (self.mach_dd - CRITICAL_MARGIN)) ** 4

    def coefficients(self, airfoil: Airfoil):
        """``(alpha, sin²alpha, speed) -> (c_L, c_D)`` of ``airfoil`` with these corrections."""
        def corrected(alpha, sin2_alpha, speed):
            cl, cd = airfoil.coefficients_of(alpha, sin2_alpha)
            mach = self.mach(speed)
            return self.glauert_factor(mach) * cl, cd + self.drag_rise(mach)
        return corrected
