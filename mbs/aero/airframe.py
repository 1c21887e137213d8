"""Airframe aerodynamics: Padfield's Bo105 fuselage polynomials, single-section tail surfaces,
the fuselage download in the rotor's wake and the hub drag.

The fuselage polynomials and the hub drag act in the free stream of the fuselage motion; the tail
surfaces see the main rotor's wake (downwash, swirl) when the scene switches it on
(:mod:`mbs.aero.wake`), and :class:`Download` adds the vertical drag the wake puts on the
fuselage. Units: SI, angles in rad; loads in the fuselage body axes (x forward, y starboard,
z down).
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from mbs.aero.airframe_tables import flow_angles
from mbs.aero.sections import EPS, Airfoil, section_angle, section_force, soft_clip, turn
from mbs.environment.air import through_air
from mbs.forces import ForceElement


class FuselageAero(ForceElement):
    """Fuselage loads from polynomials in α and β (rad) at ``v_ref`` (m/s), scaled by (V/v_ref)².

    ``coefficients``: dict with X, Y, Z (N) and M, N (N m) polynomial coefficients, lowest
    power first; X, Z, M in α, Y, N in β; body axes, acting at the body-frame origin. ``rho``:
    the density (kg/m³) they were measured at; the loads scale with the air's density over it.
    """

    def __init__(self, body: str, coefficients: dict, v_ref: float, angle_limit: float, rho: float | None = None):
        self.name, self.body = "fuselage aerodynamics", body
        self.coef, self.v_ref, self.limit, self.rho = coefficients, v_ref, angle_limit, rho

    def _poly(self, name, x):
        return sum(c * x**k for k, c in enumerate(self.coef[name]))

    def apply(self, state, loads):
        m = state.body(self.body)
        u, v, w = (ca.mtimes(m.rotation.T, through_air(state, m.velocity, m.position))[i] for i in range(3))
        speed2 = u**2 + v**2 + w**2
        alpha = soft_clip(ca.atan2(w, u + EPS), self.limit)
        beta = soft_clip(ca.asin(v / ca.sqrt(speed2 + EPS**2)), self.limit)
        scale = speed2 / self.v_ref**2
        rho = state.density(self.rho)
        if rho is not self.rho:  # the air's density differs from the polynomials' (the ISA at altitude)
            if self.rho is None:
                raise ValueError(f"{self.name}: give the density its polynomials hold at (rho) to fly in the ISA")
            scale = scale * (rho / self.rho)
        force = scale * ca.vertcat(self._poly("X", alpha), self._poly("Y", beta), self._poly("Z", alpha))
        torque = scale * ca.vertcat(0, self._poly("M", alpha), self._poly("N", beta))
        loads.add_force(self.body, force, point=[0, 0, 0], frame="body", rotation=m.rotation)
        loads.add_torque(self.body, torque)


class FuselageTables(ForceElement):
    """Fuselage loads from published tables (:class:`mbs.aero.airframe_tables.AirframeTable`)
    at the dynamic pressure ``½ ρ V²`` of the CG's velocity through the air; force at the CG and
    the moment moved there, body axes. Signals ``fuselage.alpha``, ``fuselage.beta`` (rad)."""

    def __init__(self, body: str, table, rho: float):
        self.name, self.body, self.table, self.rho = "fuselage aerodynamics", body, table, rho

    def apply(self, state, loads):
        rot = state.body(self.body).rotation
        u, v, w = (-air_velocity(state, self.body, (0, 0, 0), rot)[i] for i in range(3))
        alpha, beta, speed2 = flow_angles(u, v, w)
        force, moment = self.table.body_per_q(alpha, beta)
        q = 0.5 * state.density(self.rho) * speed2
        state.signals["fuselage.alpha"], state.signals["fuselage.beta"] = alpha, beta
        loads.add_force(self.body, q * force, point=[0, 0, 0], frame="body", rotation=rot)
        loads.add_torque(self.body, q * moment)


def air_velocity(state, body: str, point, rotation, wake=0):
    """Velocity (3,) (m/s, body axes) of the air relative to ``point`` (m) of ``body``: the
    model's air (still, wind, gusts, turbulence), plus ``wake`` (3,) (m/s, world) where a rotor's
    wake reaches the point."""
    return ca.mtimes(rotation.T, wake - _point_through_air(state, body, point))


def wake_velocity(state, rotor: str | None, body: str, point):
    """The wake of ``rotor`` (m/s, world) at ``point`` (m, ``body`` frame); 0 without a rotor."""
    return wake_flow(state, rotor, body, point)[0]


def wake_flow(state, rotor: str | None, body: str, point):
    """The wake of ``rotor`` at ``point`` (m, ``body`` frame): its velocity (m/s, world) and the
    point's immersion in it (0..1, :meth:`mbs.aero.wake.Wake.flow`); (0, 0) without a rotor."""
    if rotor is None:
        return 0, 0
    key = f"{rotor}.wake"
    if key not in state.signals:
        raise ValueError(f"no wake of {rotor!r}: its rotor aerodynamics must come first and have a wake geometry")
    return state.signals[key].flow(state.point_position(body, point))


class LiftingSurface(ForceElement):
    """One aerofoil section (horizontal tail, fin) fixed to ``body`` at ``point`` (m).

    ``chord_axis``: body-frame direction towards the leading edge; ``normal``: the lift
    direction at zero incidence; ``incidence`` (rad) turns the section nose-up about
    ``normal x chord_axis``; ``area`` m²; ``wake``: the rotor whose wake it sees (None: free
    stream only), published as the signal ``<name>.wake`` (3,) (m/s, body axes).
    """

    def __init__(self, name: str, body: str, point, chord_axis, normal, incidence: float,
                 area: float, airfoil: Airfoil, rho: float, wake: str | None = None):
        self.name, self.body, self.point = name, body, np.asarray(point, dtype=float)
        self.c, self.n = np.asarray(chord_axis, dtype=float), np.asarray(normal, dtype=float)
        self.incidence, self.area, self.airfoil, self.rho, self.wake = incidence, area, airfoil, rho, wake

    def apply(self, state, loads):
        rot = state.body(self.body).rotation
        wake, immersion = wake_flow(state, self.wake, self.body, self.point)
        if self.wake is not None:
            state.signals[f"{self.name}.wake"], state.signals[f"{self.name}.immersion"] = ca.mtimes(rot.T, wake), immersion
        w = air_velocity(state, self.body, self.point, rot, wake)
        w_c, w_n = ca.dot(w, ca.DM(self.c)), ca.dot(w, ca.DM(self.n))
        state.signals[f"{self.name}.alpha"] = section_angle(self.airfoil, *turn(w_c, w_n, self.incidence))[0]
        f_c, f_n = turn(*section_force(*turn(w_c, w_n, self.incidence), self.airfoil, state.density(self.rho),
                                       self.area, flat_plate=True),
                           -self.incidence)
        force = f_c * ca.DM(self.c) + f_n * ca.DM(self.n)
        loads.add_force(self.body, force, point=self.point, frame="body", rotation=rot)


class Download(ForceElement):
    """Vertical drag of fuselage panels in the rotor's wake: the fuselage download.

    ``panels``: rows ``(x, y, z, area, c_d)`` (m, m², –): a point of ``body``, its plan area and
    its drag coefficient in flow along the body z axis. Each panel adds the increment of its
    vertical drag ``½ ρ S c_d (|w| w − |w_0| w_0)`` (N, along body z), ``w`` the air velocity's
    z component with the wake of ``rotor`` and ``w_0`` without it: the free-stream part stays
    in the fuselage polynomials, and out of the wake the increment is zero. Signal
    ``fuselage.download``: the sum (N, along body z, positive down).
    """

    def __init__(self, body: str, rotor: str, panels, rho: float):
        self.name, self.body, self.rotor, self.rho = "fuselage download", body, rotor, rho
        self.panels = [(np.asarray(row[:3], dtype=float), float(row[3]), float(row[4])) for row in panels]

    def apply(self, state, loads):
        rot, rho = state.body(self.body).rotation, state.density(self.rho)
        state.signals["fuselage.download"] = 0
        for point, area, cd in self.panels:
            own = -_point_through_air(state, self.body, point)
            w0 = ca.dot(rot[:, 2], own)
            w = w0 + ca.dot(rot[:, 2], wake_velocity(state, self.rotor, self.body, point))
            drag = 0.5 * rho * area * cd * (w * ca.sqrt(w**2 + EPS**2) - w0 * ca.sqrt(w0**2 + EPS**2))
            loads.add_force(self.body, ca.vertcat(0, 0, drag), point=point, frame="body", rotation=rot)
            state.signals["fuselage.download"] += drag


class HubDrag(ForceElement):
    """Drag of the main-rotor hub and mast, ``−½ ρ f |V| V`` (N) at ``point`` (m) of ``body``
    (the non-rotating airframe), ``V`` the point's velocity through the air, ``f`` the hub's
    equivalent flat-plate area (m²)."""

    def __init__(self, body: str, point, flat_plate_area: float, rho: float):
        self.name, self.body, self.point = "hub drag", body, np.asarray(point, dtype=float)
        self.f, self.rho = flat_plate_area, rho

    def apply(self, state, loads):
        v = _point_through_air(state, self.body, self.point)
        drag = -0.5 * state.density(self.rho) * self.f * ca.sqrt(ca.dot(v, v) + EPS**2) * v
        loads.add_force(self.body, drag, point=self.point, frame="world", rotation=state.body(self.body).rotation)


def _point_through_air(state, body: str, point):
    """World velocity (3,) (m/s) of ``point`` (m, ``body`` frame) through the air there."""
    velocity = state.point_velocity(body, point)
    return velocity if state.air is None else through_air(state, velocity, state.point_position(body, point))
