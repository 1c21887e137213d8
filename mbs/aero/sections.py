"""Aerofoil sections: coefficients and the force on one section from its air velocity.

Section axes: ``c`` along the chord towards the leading edge, ``n`` along the section normal
(the lift direction at zero incidence). Units: SI, angles in rad.
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from mbs.aero.interpolation import Spline

EPS = 1e-9  # m/s; keeps derivatives finite at exactly zero airspeed


def soft_clip(a, limit: float, n: int = 8):
    """``a / (1 + (a/limit)^n)^(1/n)``: ``a`` for ``|a| << limit``, tending smoothly to ``±limit``
    beyond it. ``n`` a power of 2 (even, so the sign of ``a`` does not matter): the power is
    repeated squaring and the root repeated square roots, which cost a fraction of ``pow``."""
    if n < 2 or n & (n - 1):
        raise ValueError(f"soft_clip order n = {n} must be a power of 2")
    y = a * (1.0 / limit)
    for _ in range(n.bit_length() - 1):
        y = y * y
    y = 1 + y
    for _ in range(n.bit_length() - 1):
        y = ca.sqrt(y)
    return a / y


@dataclass
class Airfoil:
    """Section coefficients: lift slope (1/rad), ``cd0``, ``cd2`` (1/rad²), stall angle (rad),
    ``cd1`` (1/rad).

    ``c_L = a α`` and ``c_D = c_d0 + c_d1 α + c_d2 α²`` for attached flow; the angle is clipped smoothly
    at the stall angle (a guard, not a stall model) and the drag rises to a flat plate's
    beyond it.
    """

    lift_slope: float
    cd0: float
    cd2: float = 0.0
    alpha_stall: float = 0.26
    cd_stalled: float = 1.8
    cd1: float = 0.0

    def coefficients(self, alpha):
        """``(c_L, c_D)`` at angle of attack ``alpha`` (rad, within ±π/2)."""
        return self.coefficients_of(alpha, ca.sin(alpha) ** 2)

    def coefficients_of(self, alpha, sin2_alpha):
        """:meth:`coefficients` given ``sin²(alpha)`` as well (which a section computes without
        trigonometry from its air velocity)."""
        a = soft_clip(alpha, self.alpha_stall)
        cd = self.cd0 + self.cd2 * a**2 + self.cd_stalled * (sin2_alpha - ca.sin(a) ** 2)
        if self.cd1:  # only when given, so that a polar without it builds the same code as before
            cd = cd + self.cd1 * a
        return self.lift_slope * a, cd


@dataclass(frozen=True)
class ZeroLiftShift:
    """A cambered section: ``section`` (an :class:`Airfoil`) about its zero-lift line, which lies
    at ``alpha_0`` (rad, negative when the section lifts at zero angle) from the chord:
    ``c_L = a (α − α_0)``, the stall guard and the drag polar at ``α − α_0`` as well."""

    section: Airfoil
    alpha_0: float

    def coefficients(self, alpha):
        """``(c_L, c_D)`` at angle of attack ``alpha`` (rad, from the chord)."""
        return self.section.coefficients(alpha - self.alpha_0)

    def coefficients_of(self, alpha, sin2_alpha):
        """:meth:`coefficients` (``sin2_alpha`` of the chord's angle, unused: the shifted one is computed)."""
        shifted = alpha - self.alpha_0
        return self.section.coefficients_of(shifted, ca.sin(shifted) ** 2)


@dataclass
class TableSection:
    """Section coefficients as published: ``c_L`` and ``c_D`` against the angle of attack
    ``alpha`` (rad, increasing), natural cubic splines through the rows
    (:class:`mbs.aero.interpolation.Spline`: C², continued linearly beyond the ends). A table
    within ±π/2 is used as :class:`Airfoil` is, at the folded angle of :func:`flow_angle`; one
    over the full circle, -π to π (``full_circle``), at the air's own angle (:func:`section_angle`),
    its reverse flow as printed."""

    alpha: tuple
    lift: tuple
    drag: tuple

    def __post_init__(self):
        self.spline = Spline(self.alpha, np.column_stack([self.lift, self.drag]))
        self.full_circle = self.alpha[0] <= -np.pi + 1e-9 and self.alpha[-1] >= np.pi - 1e-9

    def coefficients(self, alpha):
        """``(c_L, c_D)`` at angle of attack ``alpha`` (rad)."""
        return tuple(self.spline(alpha))

    def coefficients_of(self, alpha, sin2_alpha):
        """:meth:`coefficients` (``sin2_alpha`` unused: the table carries the drag at every angle)."""
        return self.coefficients(alpha)


def flow_angle(w_c, w_n):
    """Angle of attack (rad) of the air velocity ``(w_c, w_n)``, reverse flow folded to ±π/2,
    and ``sin²`` of it.

    Air from the trailing edge sees the angle between the flow and the chord line, as a flat
    plate does. ``α = ½ atan2(Y, X)`` with ``X = w_c² − w_n²``, ``Y = −2 w_n w_c``, so
    ``sin² α = (1 − cos 2α)/2 = (1 − X/sqrt(X² + Y²))/2``, without a sine.
    """
    x, y = w_c**2 - w_n**2 + EPS, -2 * w_n * w_c
    return 0.5 * ca.atan2(y, x), 0.5 * (1 - x / ca.sqrt(x**2 + y**2))


def section_angle(airfoil, w_c, w_n):
    """Angle of attack (rad) and ``sin²`` of it at which ``airfoil`` is read: the full-circle
    angle ``atan2(w_n, -w_c)`` for a table over the full circle, else :func:`flow_angle`'s folded one."""
    if getattr(airfoil, "full_circle", False):
        alpha = ca.atan2(w_n, EPS - w_c)
        return alpha, ca.sin(alpha) ** 2
    return flow_angle(w_c, w_n)


FLAT_PLATE = (np.sin(np.pi / 4) ** 2, np.sin(np.pi / 3) ** 2)
"""``sin²`` of the angles of attack (45 and 60 deg) between which a fixed surface's lift turns
into a flat plate's (:func:`flat_plate_share`)."""


def flat_plate_share(sin2):
    """Share (0 to 1) of a flat plate's lift in a fixed surface's at ``sin² α``: none up to 45 deg,
    all from 60 deg (``t²(3 − 2t)``, ``t`` linear in ``sin² α`` between)."""
    low, high = FLAT_PLATE
    t = ca.fmin(1, ca.fmax(0, (sin2 - low) / (high - low)))
    return t * t * (3 - 2 * t)


def flat_plate_lift(airfoil, alpha, sin2, cl):
    """``c_L`` of a fixed surface: the section's ``cl`` up to 45 deg, a flat plate's
    ``c_D,90 sin α cos α`` from 60 deg (``c_D,90`` the section's ``cd_stalled``; none without
    one). The folded angle of :func:`flow_angle` jumps from +90 to -90 deg as the air crosses the
    surface's normal: the bounded lift jumped with it (a tail square in a hover's downwash did not
    trim), a flat plate's is none there from either side, with one slope, and its normal force
    ``c_D,90 sin α`` is the plate's measured one (Hoerner, *Fluid-Dynamic Drag*, 1965, ch. 3)."""
    plate = getattr(airfoil, "cd_stalled", None) or getattr(getattr(airfoil, "section", None), "cd_stalled", 0.0)
    w = flat_plate_share(sin2)
    return (1 - w) * cl + w * (0.5 * plate) * ca.sin(2 * alpha)


def section_force(w_c, w_n, airfoil: Airfoil, rho: float, area: float, lift_factor: float = 1.0,
                  coefficients=None, flat_plate: bool = False):
    """Force (N) on a section from the air velocity relative to it, in section axes.

    ``w_c``: component along the chord towards the leading edge; ``w_n``: along the
    section normal (the lift direction at zero incidence); ``area`` m². ``lift_factor``
    scales the lift only (tip loss); ``coefficients(alpha, sin²alpha, speed) -> (c_L, c_D)``
    replaces the aerofoil's (compressibility); ``flat_plate``: a fixed surface's lift, a flat plate's
    beyond 45 deg (:func:`flat_plate_lift`). Returns ``(f_c, f_n)``.
    """
    alpha, sin2 = section_angle(airfoil, w_c, w_n)
    speed = ca.sqrt(w_c**2 + w_n**2 + EPS**2)
    cl, cd = airfoil.coefficients_of(alpha, sin2) if coefficients is None else coefficients(alpha, sin2, speed)
    if lift_factor != 1.0:  # exactly 1.0 leaves the expression as it was without tip loss
        cl = lift_factor * cl
    if flat_plate and not getattr(airfoil, "full_circle", False):  # a full-circle table gives its own lift at 90 deg
        cl = flat_plate_lift(airfoil, alpha, sin2, cl)
    k = 0.5 * rho * area * speed
    return k * (cl * w_n + cd * w_c), k * (-cl * w_c + cd * w_n)


def turn(w_c, w_n, angle: float):
    """Components in axes turned nose-up by ``angle`` about the span (and back with -angle)."""
    c, s = np.cos(angle), np.sin(angle)
    return c * w_c + s * w_n, -s * w_c + c * w_n
