"""Aerofoil sections: coefficients and the force on one section from its air velocity.

Section axes: ``c`` along the chord towards the leading edge, ``n`` along the section normal
(the lift direction at zero incidence). Units: SI, angles in rad.
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

EPS = 1e-9  # m/s; keeps derivatives finite at exactly zero airspeed


def soft_clip(a, limit: float, n: int = 8):
    """``a`` for ``|a| << limit``, tending smoothly to ``±limit`` beyond it."""
    return a / (1 + (a / limit) ** n) ** (1.0 / n)


@dataclass
class Airfoil:
    """Section coefficients: lift slope (1/rad), ``cd0``, ``cd2`` (1/rad²), stall angle (rad).

    ``c_L = a α`` and ``c_D = c_d0 + c_d2 α²`` for attached flow; the angle is clipped smoothly
    at the stall angle (a guard, not a stall model) and the drag rises to a flat plate's
    beyond it.
    """

    lift_slope: float
    cd0: float
    cd2: float = 0.0
    alpha_stall: float = 0.26
    cd_stalled: float = 1.8

    def coefficients(self, alpha):
        """``(c_L, c_D)`` at angle of attack ``alpha`` (rad, within ±π/2)."""
        a = soft_clip(alpha, self.alpha_stall)
        cd = self.cd0 + self.cd2 * a**2 + self.cd_stalled * (ca.sin(alpha) ** 2 - ca.sin(a) ** 2)
        return self.lift_slope * a, cd


def flow_angle(w_c, w_n):
    """Angle of attack (rad) of the air velocity ``(w_c, w_n)``, reverse flow folded to ±π/2.

    Air from the trailing edge sees the angle between the flow and the chord line, as a flat
    plate does.
    """
    return 0.5 * ca.atan2(-2 * w_n * w_c, w_c**2 - w_n**2 + EPS)


def section_force(w_c, w_n, airfoil: Airfoil, rho: float, area: float, lift_factor: float = 1.0,
                  coefficients=None):
    """Force (N) on a section from the air velocity relative to it, in section axes.

    ``w_c``: component along the chord towards the leading edge; ``w_n``: along the
    section normal (the lift direction at zero incidence); ``area`` m². ``lift_factor``
    scales the lift only (tip loss); ``coefficients(alpha, speed) -> (c_L, c_D)`` replaces the
    aerofoil's (compressibility). Returns ``(f_c, f_n)``.
    """
    alpha = flow_angle(w_c, w_n)
    speed = ca.sqrt(w_c**2 + w_n**2 + EPS**2)
    cl, cd = airfoil.coefficients(alpha) if coefficients is None else coefficients(alpha, speed)
    if lift_factor != 1.0:  # exactly 1.0 leaves the expression as it was without tip loss
        cl = lift_factor * cl
    k = 0.5 * rho * area * speed
    return k * (cl * w_n + cd * w_c), k * (-cl * w_c + cd * w_n)


def turn(w_c, w_n, angle: float):
    """Components in axes turned nose-up by ``angle`` about the span (and back with -angle)."""
    c, s = np.cos(angle), np.sin(angle)
    return c * w_c + s * w_n, -s * w_c + c * w_n
