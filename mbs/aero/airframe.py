"""Airframe aerodynamics: Padfield's Bo105 fuselage polynomials and single-section tail surfaces.

Both act in the free stream of the fuselage motion (still air, no rotor downwash on the
airframe). Units: SI, angles in rad; loads in the fuselage body axes (x forward, y starboard,
z down).
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from mbs.aero.sections import EPS, Airfoil, section_force, soft_clip, turn
from mbs.forces import ForceElement


class FuselageAero(ForceElement):
    """Fuselage loads from polynomials in α and β (rad) at ``v_ref`` (m/s), scaled by (V/v_ref)².

    ``coefficients``: dict with X, Y, Z (N) and M, N (N m) polynomial coefficients, lowest
    power first; X, Z, M in α, Y, N in β; body axes, acting at the body-frame origin.
    """

    def __init__(self, body: str, coefficients: dict, v_ref: float, angle_limit: float):
        self.name, self.body = "fuselage aerodynamics", body
        self.coef, self.v_ref, self.limit = coefficients, v_ref, angle_limit

    def _poly(self, name, x):
        return sum(c * x**k for k, c in enumerate(self.coef[name]))

    def apply(self, state, loads):
        m = state.body(self.body)
        u, v, w = (ca.mtimes(m.rotation.T, m.velocity)[i] for i in range(3))
        speed2 = u**2 + v**2 + w**2
        alpha = soft_clip(ca.atan2(w, u + EPS), self.limit)
        beta = soft_clip(ca.asin(v / ca.sqrt(speed2 + EPS**2)), self.limit)
        scale = speed2 / self.v_ref**2
        force = scale * ca.vertcat(self._poly("X", alpha), self._poly("Y", beta), self._poly("Z", alpha))
        torque = scale * ca.vertcat(0, self._poly("M", alpha), self._poly("N", beta))
        loads.add_force(self.body, force, point=[0, 0, 0], frame="body", rotation=m.rotation)
        loads.add_torque(self.body, torque)


class LiftingSurface(ForceElement):
    """One aerofoil section (horizontal tail, fin) fixed to ``body`` at ``point`` (m).

    ``chord_axis``: body-frame direction towards the leading edge; ``normal``: the lift
    direction at zero incidence; ``incidence`` (rad) turns the section nose-up about
    ``normal x chord_axis``; ``area`` m².
    """

    def __init__(self, name: str, body: str, point, chord_axis, normal, incidence: float,
                 area: float, airfoil: Airfoil, rho: float):
        self.name, self.body, self.point = name, body, np.asarray(point, dtype=float)
        self.c, self.n = np.asarray(chord_axis, dtype=float), np.asarray(normal, dtype=float)
        self.incidence, self.area, self.airfoil, self.rho = incidence, area, airfoil, rho

    def apply(self, state, loads):
        rot = state.body(self.body).rotation
        w = ca.mtimes(rot.T, -state.point_velocity(self.body, self.point))
        w_c, w_n = ca.dot(w, ca.DM(self.c)), ca.dot(w, ca.DM(self.n))
        f_c, f_n = turn(*section_force(*turn(w_c, w_n, self.incidence), self.airfoil, self.rho, self.area),
                           -self.incidence)
        force = f_c * ca.DM(self.c) + f_n * ca.DM(self.n)
        loads.add_force(self.body, force, point=self.point, frame="body", rotation=rot)
