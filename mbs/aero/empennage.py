"""Tail surfaces as published: a stabilator's incidence schedule and interference tables.

A stabilator is a horizontal tail whose incidence (rad, leading edge up positive, i.e. trailing
edge down) a schedule sets: a table against airspeed (m/s) plus gains on the collective (rad per
rad, about a reference collective), the longitudinal cyclic (rad per rad: an elevator linked to
the cyclic stick, as the UH-1H's synchronized elevator) and the pitch rate (rad per rad/s), held
within its stops by a smooth clamp (:func:`smooth_clamp`). Interference tables replace the
rotor-wake model at a surface with published ratios against the fuselage angle of attack: the
dynamic-pressure ratio
``η = q_tail / q`` (the air speed at the surface scales by ``sqrt η``) and the downwash angle
``ε`` (rad, the flow turned down at the horizontal tail; for the fin the sidewash angle ``σ``
against the sideslip, the flow turned to starboard). Units SI, angles in rad.
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from mbs.aero.airframe import LiftingSurface, air_velocity
from mbs.aero.airframe_tables import flow_angles
from mbs.aero.interpolation import Spline, Spline2
from mbs.aero.sections import EPS, section_angle, section_force

CLAMP_SMOOTHING = 0.005  # rad: the stops are rounded over about this much (0.3 deg)


def smooth_clamp(x, low: float, high: float, width: float = CLAMP_SMOOTHING):
    """``x`` held within ``[low, high]`` by smooth minimum and maximum (rounded over ``width``):
    within ``width²/(4 d)`` of ``x`` at a distance ``d`` from a stop, ``width/2`` short of it at it."""
    up = 0.5 * (x + low + ca.sqrt((x - low) ** 2 + width**2))
    return 0.5 * (up + high - ca.sqrt((up - high) ** 2 + width**2))


HOLD_WIDTH = 0.5
"""m/s: the rounding of a schedule's hold at its first and last airspeed."""
HOLD_COLLECTIVE = 0.002
"""rad: the rounding of a two-variable schedule's hold at its least and largest collective."""


def held(x, low: float, high: float, width: float):
    """``x`` held within ``[low, high]``: itself from ``width`` inside the ends, the end from
    ``width`` beyond, a parabola between (value and slope continuous)."""
    def end(x, at, sign):
        band = sign * (x - at) + width  # 0 at width beyond the end, 2 width at width inside
        return ca.if_else(band <= 0, at, ca.if_else(band >= 2 * width, x, at + sign * band**2 / (4 * width)))
    return end(end(x, low, 1.0), high, -1.0)


@dataclass(frozen=True)
class Schedule:
    """Stabilator incidence against ``airspeed`` (m/s) breakpoints: ``incidence`` (rad) values,
    ``collective_gain`` (rad/rad) about ``collective_reference`` (rad), ``pitch_rate_gain``
    (rad per rad/s), stops ``low``/``high`` (rad), ``cyclic_gain`` (rad per rad of the model's
    longitudinal cyclic θ1s)."""

    airspeed: tuple
    incidence: tuple
    collective_gain: float
    collective_reference: float
    pitch_rate_gain: float
    low: float
    high: float
    cyclic_gain: float = 0.0
    collective: tuple = ()  # rad: a table's collective breakpoints; incidence then (len(collective), len(airspeed))

    def __call__(self, airspeed, collective, pitch_rate, cyclic=0.0):
        """The scheduled incidence (rad) and the incidence before the stops (rad): the spline in
        airspeed (with ``collective`` breakpoints, the tensor spline in collective and airspeed),
        held at its ends (a schedule does not run on past its table; the airspeed and collective
        :func:`held` within their ends)."""
        if len(self.airspeed) > 1:
            airspeed = held(airspeed, self.airspeed[0], self.airspeed[-1], HOLD_WIDTH)
        if self.collective:
            at = held(collective, self.collective[0], self.collective[-1], HOLD_COLLECTIVE)
            raw = Spline2(self.collective, self.airspeed, self.incidence)(at, airspeed)
        else:
            raw = Spline(self.airspeed, self.incidence)(airspeed)
        if self.collective_gain:
            raw = raw + self.collective_gain * (collective - self.collective_reference)
        if self.cyclic_gain:
            raw = raw + self.cyclic_gain * cyclic
        if self.pitch_rate_gain:
            raw = raw + self.pitch_rate_gain * pitch_rate
        return smooth_clamp(raw, self.low, self.high), raw


def _pilot_input(state, name: str, entry: str):
    """The run-time control ``name`` that the schedule's ``entry`` gain reads, or a ValueError
    naming the gain when the scene flies other controls (the swashplate actuators)."""
    try:
        return state.p[name]
    except KeyError:
        raise ValueError(f"stabilator.{entry}: the schedule reads the {name}, which this scene does not fly (its "
                         f"controls are other inputs, such as the swashplate actuators): fly a scene with blade-angle "
                         f"controls, or leave {entry} out") from None


@dataclass(frozen=True)
class Interference:
    """Published interference at a surface: ``angle`` breakpoints (rad) of the fuselage angle of
    attack (horizontal tail) or sideslip (fin), ``q_ratio`` ``η`` (-) and ``flow_angle`` ``ε``
    or ``σ`` (rad) on them (either may be None: 1 and 0)."""

    angle: tuple
    q_ratio: tuple | None
    flow_angle: tuple | None
    lateral: bool = False


class TailSurface(LiftingSurface):
    """A :class:`mbs.aero.LiftingSurface` with a scheduled incidence (``schedule``) and/or
    published interference (``interference``, replacing the wake). Signals ``<name>.incidence``,
    ``<name>.alpha`` (rad, the section's angle of attack) and, scheduled, ``<name>.incidence_raw``."""

    def __init__(self, *args, schedule: Schedule | None = None, interference: Interference | None = None, **kw):
        super().__init__(*args, **kw)
        self.schedule, self.interference = schedule, interference

    def apply(self, state, loads):
        m = state.body(self.body)
        rot = m.rotation
        incidence = self._incidence(state, m)
        air = self._air(state, rot)
        w_c, w_n = ca.dot(air, ca.DM(self.c)), ca.dot(air, ca.DM(self.n))
        cos_i, sin_i = ca.cos(incidence), ca.sin(incidence)
        w_c, w_n = cos_i * w_c + sin_i * w_n, -sin_i * w_c + cos_i * w_n
        state.signals[f"{self.name}.alpha"] = section_angle(self.airfoil, w_c, w_n)[0]
        f_c, f_n = section_force(w_c, w_n, self.airfoil, state.density(self.rho), self.area, flat_plate=True)
        f_c, f_n = cos_i * f_c - sin_i * f_n, sin_i * f_c + cos_i * f_n
        loads.add_force(self.body, f_c * ca.DM(self.c) + f_n * ca.DM(self.n), point=self.point, frame="body",
                        rotation=rot)

    def _incidence(self, state, m):
        if self.schedule is None:
            state.signals[f"{self.name}.incidence"] = self.incidence
            return self.incidence
        own = ca.mtimes(m.rotation.T, m.velocity)
        airspeed = ca.sqrt(ca.dot(own, own) + EPS**2)
        reads = self.schedule.collective_gain or self.schedule.collective
        entry = "collective_gain" if self.schedule.collective_gain else "incidence_table"
        collective = _pilot_input(state, "collective", entry) if reads else 0.0
        cyclic = _pilot_input(state, "longitudinal_cyclic", "cyclic_gain") if self.schedule.cyclic_gain else 0.0
        incidence, raw = self.schedule(airspeed, collective, m.omega[1], cyclic)
        state.signals[f"{self.name}.incidence"], state.signals[f"{self.name}.incidence_raw"] = incidence, raw
        return incidence

    def _air(self, state, rot):
        """Air velocity (3,) (m/s, body axes) at the surface: the wake's, or the interference's."""
        if self.interference is None:
            from mbs.aero.airframe import wake_flow

            wake, immersion = wake_flow(state, self.wake, self.body, self.point)
            if self.wake is not None:
                state.signals[f"{self.name}.wake"] = ca.mtimes(rot.T, wake)
                state.signals[f"{self.name}.immersion"] = immersion
            return air_velocity(state, self.body, self.point, rot, wake)
        return self._interfered(state, air_velocity(state, self.body, self.point, rot))

    def _interfered(self, state, air):
        """``air`` (body axes) scaled by ``sqrt η`` and turned by ``ε`` (down) or ``σ`` (starboard),
        the tables read at the angle of attack (sideslip) of ``air``: the fuselage's in steady
        flight, where the surface moves with the CG."""
        table = self.interference
        u, v, w = (-air[i] for i in range(3))
        alpha, beta, _ = flow_angles(u, v, w)
        arg = beta if table.lateral else alpha
        scale = ca.sqrt(Spline(table.angle, table.q_ratio)(arg)) if table.q_ratio is not None else 1.0
        turn = Spline(table.angle, table.flow_angle)(arg) if table.flow_angle is not None else 0.0
        c, s = ca.cos(turn), ca.sin(turn)
        if table.lateral:  # sidewash: the air arrives from further to port, moving to starboard
            turned = ca.vertcat(c * air[0] + s * air[1], -s * air[0] + c * air[1], air[2])
        else:  # downwash: the air moving aft is turned down
            turned = ca.vertcat(c * air[0] + s * air[2], air[1], -s * air[0] + c * air[2])
        state.signals[f"{self.name}.interference"] = ca.vertcat(scale, turn)
        state.signals[f"{self.name}.wake"] = scale * turned - air  # what the interference adds (body axes)
        return scale * turned
