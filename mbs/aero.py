"""Simple aerodynamics as force elements: as simple as the paper's, no simpler than a user needs.

* :class:`Airfoil`: ``c_L = a α`` and ``c_D = c_d0 + c_d2 α²`` for attached flow; the angle is
  clipped smoothly at the stall angle (a guard, not a stall model) and the drag rises to a flat
  plate's beyond it. Reverse flow is folded: air from the trailing edge sees the angle
  between the flow and the chord line, as a flat plate does.
* :class:`RotorAero`: blade elements (quasi-steady strip theory, no radial flow, no tip loss,
  no unsteady or dynamic-stall terms); air velocities at each element come from the body
  kinematics (the AD tree gives them for free). Uniform induced inflow with the Pitt-Peters
  apparent mass: ``(8/3) ρ R³ v̇ = T − 2 ρ π R² V_T v``, whose equilibrium is Glauert's momentum
  theory ``T = 2 ρ A v V_T``, ``V_T = sqrt(V_inplane² + (V_normal + v)²)``; the blades see
  ``κ v``. The inflow is a state, so there is no algebraic loop.
* :class:`FuselageAero`: Padfield's Bo105 fuselage polynomials (loads at a reference speed,
  scaled with dynamic pressure), angles clipped to their range of validity.
* :class:`LiftingSurface`: horizontal tail and fin as one aerofoil section each, in the
  free stream of the fuselage motion (no rotor downwash on the tail).

Units: SI, angles in rad. All forces act in still air (no wind, no gust).
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from mbs.forces import ForceElement, Loads, State

EPS = 1e-9  # m/s; keeps derivatives finite at exactly zero airspeed


def soft_clip(a, limit: float, n: int = 8):
    """``a`` for ``|a| << limit``, tending smoothly to ``±limit`` beyond it."""
    return a / (1 + (a / limit) ** n) ** (1.0 / n)


@dataclass
class Airfoil:
    """Section coefficients: lift slope (1/rad), ``cd0``, ``cd2`` (1/rad²), stall angle (rad)."""

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


def section_force(w_c, w_n, airfoil: Airfoil, rho: float, area: float):
    """Force (N) on a section from the air velocity relative to it, in section axes.

    ``w_c``: component along the chord towards the leading edge; ``w_n``: along the
    section normal (the lift direction at zero incidence). Returns ``(f_c, f_n)``.
    """
    alpha = 0.5 * ca.atan2(-2 * w_n * w_c, w_c**2 - w_n**2 + EPS)  # flow angle folded to ±π/2
    cl, cd = airfoil.coefficients(alpha)
    speed = ca.sqrt(w_c**2 + w_n**2 + EPS**2)
    k = 0.5 * rho * area * speed
    return k * (cl * w_n + cd * w_c), k * (-cl * w_c + cd * w_n)


def _rotate(w_c, w_n, angle: float):
    """Components in axes turned nose-up by ``angle`` about the span (and back with -angle)."""
    c, s = np.cos(angle), np.sin(angle)
    return c * w_c + s * w_n, -s * w_c + c * w_n


@dataclass
class Rotor:
    """Geometry of a rotor for :class:`RotorAero`; stations are equal-width strips."""

    name: str
    hub: str
    blades: list
    radius: float
    chord: float
    twist: float
    root_cutout: float
    elements: int
    hinge_radius: float = 0.0

    def stations(self) -> tuple[np.ndarray, float]:
        """Strip mid-radii (m, from the rotor axis) and width (m)."""
        r0 = self.root_cutout * self.radius
        dr = (self.radius - r0) / self.elements
        return r0 + dr * (np.arange(self.elements) + 0.5), dr


class RotorAero(ForceElement):
    """Blade-element loads on every blade of ``rotor`` plus its uniform dynamic inflow state.

    Blade body frames: x along the span (from the blade's joint at ``hinge_radius`` from the
    rotor axis), y towards the leading edge, z the lift direction at zero pitch. The hub
    frame's z axis is the rotor's thrust axis. The inflow state ``<name>.inflow`` (m/s) is
    positive down through the disc (against the thrust axis); its thrust is published as the
    signal ``<name>.thrust`` (N).
    """

    def __init__(self, rotor: Rotor, airfoil: Airfoil, rho: float, kappa: float):
        self.rotor, self.airfoil, self.rho, self.kappa = rotor, airfoil, rho, kappa
        self.name = f"{rotor.name} aerodynamics"
        self.inflow = f"{rotor.name}.inflow"

    def apply(self, state: State, loads: Loads) -> None:
        hub = state.body(self.rotor.hub)
        axis = hub.rotation[:, 2]
        v = state.z(self.inflow)
        air = -self.kappa * v * axis
        thrust = sum(self._blade(state, loads, b, air, axis) for b in self.rotor.blades)
        loads.set_rate(self.inflow, self._inflow_rate(hub.velocity, axis, v, thrust))
        state.signals[f"{self.rotor.name}.thrust"] = thrust

    def _blade(self, state, loads, blade, air, axis):
        radii, dr = self.rotor.stations()
        rot = state.body(blade).rotation
        thrust = 0
        for r in radii:
            point = ca.DM([r - self.rotor.hinge_radius, 0, 0])
            w = ca.mtimes(rot.T, air - state.point_velocity(blade, point))
            twist = self.rotor.twist * r / self.rotor.radius
            f_c, f_n = section_force(*_rotate(w[1], w[2], twist), self.airfoil, self.rho, self.rotor.chord * dr)
            f_y, f_z = _rotate(f_c, f_n, -twist)
            force = ca.vertcat(0, f_y, f_z)
            loads.add_force(blade, force, point=point, frame="body", rotation=rot)
            thrust += ca.dot(ca.mtimes(rot, force), axis)
        return thrust

    def _inflow_rate(self, hub_velocity, axis, v, thrust):
        area = np.pi * self.rotor.radius**2
        v_normal = ca.dot(hub_velocity, axis)
        v_inplane2 = ca.dot(hub_velocity, hub_velocity) - v_normal**2
        v_total = ca.sqrt(v_inplane2 + (v_normal + v) ** 2 + EPS**2)
        apparent_mass = 8.0 / 3.0 * self.rho * self.rotor.radius**3
        return (thrust - 2 * self.rho * area * v_total * v) / apparent_mass


def momentum_inflow(thrust: float, rho: float, radius: float, v_inplane: float = 0.0,
                    v_normal: float = 0.0) -> float:
    """Glauert momentum-theory induced velocity (m/s) for ``thrust`` (N): the inflow state's equilibrium."""
    area, v = np.pi * radius**2, np.sqrt(abs(thrust) / (2 * rho * np.pi * radius**2))
    for _ in range(100):
        v_total = np.hypot(v_inplane, v_normal + v)
        v = 0.5 * v + 0.5 * thrust / (2 * rho * area * max(v_total, 1e-6))
    return float(v)


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
        f_c, f_n = _rotate(*section_force(*_rotate(w_c, w_n, self.incidence), self.airfoil, self.rho, self.area),
                           -self.incidence)
        force = f_c * ca.DM(self.c) + f_n * ca.DM(self.n)
        loads.add_force(self.body, force, point=self.point, frame="body", rotation=rot)
