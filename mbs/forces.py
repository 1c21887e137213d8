"""Force elements.

A force element reads the symbolic motion of the tree (:class:`State`) and adds loads
(:class:`Loads`): forces at points of bodies, torques on bodies, or generalized forces
on joint coordinates. Everything is a CasADi expression, so forces that depend on the
velocities (dampers, aerodynamics) need nothing more than their formula; relative air
velocities come straight from the body kinematics.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import casadi as ca
import numpy as np

from mbs.joints import Params, Relative


class State:
    """Symbolic state of the tree as seen by force elements.

    ``t`` time (s); ``p`` parameters; ``body(name)`` the body-frame motion (origin position
    and velocity in world components, rotation body->world, angular velocity in body
    components); ``q(name)``/``v(name)`` joint coordinates and rates by full name;
    ``energy`` (5,): translational and rotational kinetic, gravity, spring, total (J);
    ``reactions``: the joint reaction loads (:class:`mbs.dynamics.Reactions`), for outputs;
    ``air``: the model's :class:`mbs.environment.Air` (None: still air at the aircraft file's
    density), read through :meth:`air_velocity`, :meth:`density` and :meth:`speed_of_sound`.
    """

    energy = None
    reactions = None  # set after the forces are applied: outputs only

    def __init__(self, t, p: Params, motions: dict[str, Relative], coords: dict, rates: dict,
                 v_index: dict[str, int], extra: dict | None = None, air=None):
        self.t, self.p, self.air = t, p, air
        self._motions, self._coords, self._rates, self.v_index = motions, coords, rates, v_index
        self._extra = extra or {}
        self.signals: dict = {}  # named intermediate results of force elements (e.g. thrust)

    def body(self, name: str) -> Relative:
        return self._motions[name]

    def q(self, name: str) -> ca.SX:
        return self._coords[name]

    def v(self, name: str) -> ca.SX:
        return self._rates[name]

    def z(self, name: str) -> ca.SX:
        """An extra state (see :meth:`mbs.Model.add_state`)."""
        if name not in self._extra:
            raise KeyError(f"unknown extra state {name!r}; known: {sorted(self._extra)}")
        return self._extra[name]

    def air_velocity(self, position):
        """The air's velocity (3,) (m/s, world) at the world point ``position`` (3,) (m): wind,
        gusts and turbulence as the model's air has them; None in still air. Every aerodynamic
        element takes its velocity through the air from here (:func:`mbs.environment.through_air`)."""
        return None if self.air is None else self.air.velocity(self, position)

    def density(self, default: float):
        """Air density (kg/m³): ``default`` (the aircraft file's) unless the model's air is the ISA's."""
        return default if self.air is None else self.air.density(self, default)

    def speed_of_sound(self, default: float):
        """Speed of sound (m/s): ``default`` (the aircraft file's) unless the model's air is the ISA's."""
        return default if self.air is None else self.air.speed_of_sound(self, default)

    def point_position(self, body: str, r) -> ca.SX:
        """World position (m) of the point ``r`` (body frame, m)."""
        m = self._motions[body]
        return m.position + ca.mtimes(m.rotation, ca.DM(r) if isinstance(r, (list, tuple, np.ndarray)) else r)

    def point_velocity(self, body: str, r) -> ca.SX:
        """World velocity (m/s) of the point ``r`` (body frame, m), in world components."""
        m = self._motions[body]
        r = ca.DM(r) if isinstance(r, (list, tuple, np.ndarray)) else r
        return m.velocity + ca.mtimes(m.rotation, ca.cross(m.omega, r))


class Loads:
    """Accumulates loads: per body a force at the centre of mass (world components)
    and a torque about it (body components), plus generalized forces (one per rate)."""

    def __init__(self, bodies, nv: int, v_index: dict[str, int], extra_names=()):
        self._com = {b.name: ca.DM(b.com) for b in bodies}
        self.force = {b.name: ca.SX.zeros(3) for b in bodies}
        self.torque = {b.name: ca.SX.zeros(3) for b in bodies}
        self.generalized = ca.SX.zeros(nv)
        self.rates = {n: None for n in extra_names}
        self._v_index = v_index

    def add_force(self, body: str, force, point=None, frame: str = "body", rotation=None) -> None:
        """Force (N) at ``point`` (body frame, m; default the centre of mass).

        ``frame`` says whether ``force`` has body or world components; ``rotation`` is the
        body's rotation matrix (needed to convert, see :meth:`State.body`).
        """
        f_body = force if frame == "body" else ca.mtimes(rotation.T, force)
        f_world = force if frame == "world" else ca.mtimes(rotation, force)
        self.force[body] = self.force[body] + f_world
        if point is not None:
            lever = (ca.DM(point) if isinstance(point, (list, tuple, np.ndarray)) else point) - self._com[body]
            self.torque[body] = self.torque[body] + ca.cross(lever, f_body)

    def add_torque(self, body: str, torque) -> None:
        """Torque (N m), body components."""
        self.torque[body] = self.torque[body] + torque

    def set_rate(self, state_name: str, value) -> None:
        """Set the time derivative of an extra state (exactly one element does so)."""
        if state_name not in self.rates:
            raise KeyError(f"unknown extra state {state_name!r}")
        if self.rates[state_name] is not None:
            raise ValueError(f"the rate of extra state {state_name!r} is set twice")
        self.rates[state_name] = value

    def add_generalized(self, rate_name: str, value) -> None:
        """Generalized force on the coordinate whose rate is ``rate_name`` (N m or N)."""
        if rate_name not in self._v_index:
            raise KeyError(f"unknown joint rate {rate_name!r}")
        i = self._v_index[rate_name]
        self.generalized[i] = self.generalized[i] + value


class ForceElement:
    """Base class: ``apply`` adds loads; ``potential`` (J) enters the total energy."""

    name = "force"

    def apply(self, state: State, loads: Loads) -> None:
        raise NotImplementedError

    def potential(self, state: State):
        return 0


@dataclass
class SpringDamper(ForceElement):
    """Linear spring and damper on a hinge coordinate ``coordinate`` (e.g. ``"blade1.lag"``).

    stiffness N m/rad, damping N m s/rad, rest angle rad; on a slider coordinate N/m, N s/m, m.
    """

    coordinate: str
    stiffness: float = 0.0
    damping: float = 0.0
    rest: float = 0.0

    def __post_init__(self):
        self.name = f"spring-damper {self.coordinate}"
        for what in ("stiffness", "damping", "rest"):
            if not np.isfinite(getattr(self, what)):
                raise ValueError(f"{self.name}: {what} {getattr(self, what)} is not finite")

    def apply(self, state, loads):
        rate = self.coordinate + "_rate"
        q, v = state.q(self.coordinate), state.v(rate)
        loads.add_generalized(rate, -self.stiffness * (q - self.rest) - self.damping * v)

    def potential(self, state):
        return 0.5 * self.stiffness * (state.q(self.coordinate) - self.rest) ** 2


class Strut(ForceElement):
    """A spring and damper along the line between point ``a`` of ``body_a`` and point ``b`` of
    ``body_b`` (body frames, m): a lag damper between hub and blade, a shock strut.

    The tension ``stiffness (L − rest) + damper(L̇)`` (N; ``L`` the length in m, ``L̇`` its rate in
    m/s, ``damper`` a function of ``L̇``: a force curve) pulls the two points together; equal and
    opposite forces at the points, so the strut does no work but its own. ``rest`` (m) the free
    length; ``potential`` the spring's energy (J)."""

    def __init__(self, name: str, body_a: str, a, body_b: str, b, stiffness: float = 0.0, rest: float = 0.0,
                 damper: Callable | None = None):
        self.name, self.body_a, self.body_b = name, body_a, body_b
        self.a, self.b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
        self.stiffness, self.rest, self.damper = float(stiffness), float(rest), damper
        if not (np.isfinite(self.stiffness) and np.isfinite(self.rest)):
            raise ValueError(f"{name}: stiffness {stiffness} and rest length {rest} must be finite")

    def geometry(self, state: State):
        """``(d, L, L̇)``: the vector from ``a`` to ``b`` (world, m), its length (m) and rate (m/s)."""
        d = state.point_position(self.body_b, self.b) - state.point_position(self.body_a, self.a)
        length = ca.sqrt(ca.dot(d, d))
        rate = ca.dot(d, state.point_velocity(self.body_b, self.b) - state.point_velocity(self.body_a, self.a)) / length
        return d, length, rate

    def tension(self, state: State):
        """The strut's tension (N) and its unit vector from ``a`` to ``b`` (world)."""
        d, length, rate = self.geometry(state)
        tension = self.stiffness * (length - self.rest) + (self.damper(rate) if self.damper else 0.0)
        return tension, d / length

    def apply(self, state, loads):
        tension, e = self.tension(state)
        for body, point, sign in ((self.body_a, self.a, 1.0), (self.body_b, self.b, -1.0)):
            loads.add_force(body, sign * tension * e, point=point, frame="world", rotation=state.body(body).rotation)

    def potential(self, state):
        return 0.5 * self.stiffness * (self.geometry(state)[1] - self.rest) ** 2


class UserForce(ForceElement):
    """Any loads written as a function ``fn(state, loads)`` of the symbolic state."""

    def __init__(self, name: str, fn: Callable):
        self.name, self.fn = name, fn

    def apply(self, state, loads):
        self.fn(state, loads)


def _value(state: State, v):
    """A constant, a parameter name, or a function of the state -> SX."""
    if isinstance(v, str):
        return state.p[v]
    return v(state) if callable(v) else ca.DM(v)


class PointForce(ForceElement):
    """Force (N) on ``body`` at ``point`` (m, body frame), given in ``frame`` ("body" or
    "world") components: a constant (3,), a function ``f(state) -> SX (3,)``, or, per
    component, names of parameters."""

    def __init__(self, name: str, body: str, force, point=(0.0, 0.0, 0.0), frame: str = "body"):
        if frame not in ("body", "world"):
            raise ValueError(f"{name}: frame must be 'body' or 'world', not {frame!r}")
        self.name, self.body, self.force, self.point, self.frame = name, body, force, np.asarray(point, float), frame

    def apply(self, state, loads):
        f = ca.vertcat(*[_value(state, c) for c in self.force]) if isinstance(self.force, (list, tuple)) \
            else _value(state, self.force)
        loads.add_force(self.body, f, self.point, self.frame, state.body(self.body).rotation)


class BodyTorque(ForceElement):
    """Torque (N m) on ``body`` in body-frame components: constant, function or parameter names."""

    def __init__(self, name: str, body: str, torque):
        self.name, self.body, self.torque = name, body, torque

    def apply(self, state, loads):
        t = ca.vertcat(*[_value(state, c) for c in self.torque]) if isinstance(self.torque, (list, tuple)) \
            else _value(state, self.torque)
        loads.add_torque(self.body, t)
