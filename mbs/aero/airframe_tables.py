"""Fuselage (or any airframe component's) loads from published tables in α and β.

A report prints the six components per dynamic pressure (``D/q`` in m², ``M/q`` in m³), as
coefficients or as loads at a speed, against the angle of attack, the sideslip or both, about a
reference point and in body, stability or wind axes. :class:`AirframeTable` holds them as
printed, brought to SI per dynamic pressure once when the aircraft file is read; the loads at
any (α, β) are the tables' natural cubic splines (:mod:`mbs.aero.interpolation`), turned from the
published axes to body axes and moved to the centre of gravity.

Conventions (body axes x forward, y starboard, z down; air velocity relative to the aircraft
``-(u, v, w)``): ``α = atan2(w, u + ε)``, ``β = asin(v / sqrt(V² + ε²))``, ``ε`` =
:data:`mbs.aero.sections.EPS` (finite derivatives in hover). Wind axes: ``x_w`` along the
aircraft's velocity ``(cos α cos β, sin β, sin α cos β)``, ``z_w = (−sin α, 0, cos α)``, ``y_w =
z_w × x_w``; stability axes the same with β = 0. Drag acts along ``−x``, lift along ``−z``,
side force along ``+y``; the rolling, pitching and yawing moments are about ``x``, ``y``, ``z``
of the stated axes. Body axes: X, Y, Z, L, M, N as they are. Units SI, angles in rad.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from mbs.aero.interpolation import Spline, Spline2
from mbs.aero.sections import EPS

AXES = ("body", "stability", "wind")
WIND_COMPONENTS = ("drag", "side", "lift", "roll", "pitch", "yaw")
BODY_COMPONENTS = ("X", "Y", "Z", "L", "M", "N")
ARGUMENTS = ("alpha", "beta", "alpha_beta")


@dataclass
class AirframeTable:
    """Six load components per dynamic pressure (forces m², moments m³) in ``axes`` about
    ``reference`` (3,) (m, body axes from the CG). ``parts[i]``: list of ``(argument, values)``
    summed for component ``i`` (0..5 in the order of :data:`WIND_COMPONENTS` or
    :data:`BODY_COMPONENTS`), ``argument`` one of :data:`ARGUMENTS`, ``values`` on ``alpha``
    and/or ``beta`` (rad) — (n_alpha,), (n_beta,) or (n_alpha, n_beta). A part
    ``(argument, values, breakpoints)`` is on its own ``breakpoints`` (rad) instead: (n,) for one
    angle, ``(alpha, beta)`` for both (``None``: the shared ones). ``beta_sign``: -1 for tables
    printed with the other sideslip sign (read at -β; the wind axes stay the air's own)."""

    axes: str
    reference: tuple
    alpha: np.ndarray | None
    beta: np.ndarray | None
    parts: dict = field(default_factory=dict)
    beta_sign: float = 1.0

    def __post_init__(self):
        if self.axes not in AXES:
            raise ValueError(f"axes {self.axes!r}: one of {', '.join(AXES)}")
        self._splines = {i: [(p[0], self._spline(*p)) for p in parts] for i, parts in self.parts.items()}

    def _spline(self, arg: str, values, own=None):
        if arg == "alpha_beta":
            return Spline2(*(own if own is not None else (self.alpha, self.beta)), values)
        return Spline(own if own is not None else self.alpha if arg == "alpha" else self.beta, values)

    def per_q(self, alpha, beta) -> list:
        """The six components per dynamic pressure as published (m², m³) at ``alpha``, ``beta``."""
        out = []
        for i in range(6):
            total = 0
            for arg, spline in self._splines.get(i, []):
                total = total + (spline(alpha) if arg == "alpha" else spline(beta) if arg == "beta"
                                 else spline(alpha, beta))
            out.append(total)
        return out

    def body_per_q(self, alpha, beta):
        """Force (3,) (m²) and moment about the CG (3,) (m³) per dynamic pressure, body axes."""
        c = self.per_q(alpha, beta if self.beta_sign > 0 else -beta)
        if self.axes == "body":
            force, moment = ca.vertcat(*c[:3]), ca.vertcat(*c[3:])
        else:
            x, y, z = axes_in_body(alpha, beta if self.axes == "wind" else 0)
            force = -c[0] * x + c[1] * y - c[2] * z
            moment = c[3] * x + c[4] * y + c[5] * z
        return force, moment + ca.cross(ca.DM(self.reference), force)


def axes_in_body(alpha, beta):
    """Unit vectors (3,) of the wind axes (β = 0: stability axes) in body components."""
    ca_, sa, cb, sb = ca.cos(alpha), ca.sin(alpha), ca.cos(beta), ca.sin(beta)
    x = ca.vertcat(ca_ * cb, sb, sa * cb)
    z = ca.vertcat(-sa, 0, ca_)
    return x, ca.cross(z, x), z


def flow_angles(u, v, w):
    """``(α, β, V²)`` of the body-axis velocity ``(u, v, w)`` (m/s) through still air."""
    speed2 = u**2 + v**2 + w**2
    return ca.atan2(w, u + EPS), ca.asin(v / ca.sqrt(speed2 + EPS**2)), speed2
