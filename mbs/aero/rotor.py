"""Blade-element rotor: quasi-steady strip theory on every blade plus the rotor's inflow states.

Air velocities at each element come from the body kinematics (the AD tree gives them for
free); no radial flow, no unsteady or dynamic-stall terms. What else is modelled is chosen per
scene by :class:`RotorModel`: the inflow model, tip loss and compressibility. Units: SI, rad.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace

import casadi as ca
import numpy as np

from mbs.aero import inflow as inf
from mbs.aero.compressibility import Compressibility
from mbs.aero.sections import EPS, Airfoil, ZeroLiftShift, section_angle, section_force, turn
from mbs.aero.tables.airfoil import BladeAirfoils, table_section_loads
from mbs.aero.tiploss import lift_factors
from mbs.aero.wake import Wake, WakeGeometry
from mbs.forces import ForceElement, Loads, State


@dataclass
class Rotor:
    """Geometry of a rotor for :class:`RotorAero`; stations are equal-width strips.

    ``shaft_body``/``shaft_frame``: the body carrying the hub joint (``None``: the world) and
    the rotor's azimuth frame in its axes (3, 3): x at ψ = 0, y at ψ = 90° (ψ in the sense of
    rotation), z the thrust axis; left-handed for a rotor turning against its thrust axis
    (:attr:`sense`); ``speed_ratio``: rotor speed per ``omega``. ``chord_table``/``twist_table``:
    rows (r/R, chord m) and (r/R, twist rad) replacing the constant chord and the linear twist
    (None: those); ``sweep_angle`` (rad): the quarter-chord line swept aft beyond ``sweep_start``
    (r/R), the tip at ``radius`` along the blade's x axis.
    """

    name: str
    hub: str
    blades: list
    radius: float
    chord: float
    twist: float
    root_cutout: float
    elements: int
    hinge_radius: float = 0.0
    shaft_body: str | None = None
    shaft_frame: np.ndarray = field(default_factory=lambda: np.eye(3))
    speed_ratio: float = 1.0
    pieces: dict = field(default_factory=dict)
    chord_table: tuple | None = None
    twist_table: tuple | None = None
    sweep_start: float = 1.0
    sweep_angle: float = 0.0

    def swept(self, r: float) -> bool:
        """Whether the element at radius ``r`` (m) lies on the swept tip."""
        return self.sweep_angle != 0.0 and r > self.sweep_start * self.radius

    def sweep_offset(self, r: float) -> float:
        """How far aft (m) of the blade's x axis the quarter chord lies at radius ``r`` (m)."""
        return max(r - self.sweep_start * self.radius, 0.0) * float(np.tan(self.sweep_angle))

    def sweep_chord(self) -> tuple[float, float]:
        """The swept section's chord direction (towards the leading edge) in blade x and in the
        unswept chord direction: ``(sin Λ, cos Λ)``."""
        return float(np.sin(self.sweep_angle)), float(np.cos(self.sweep_angle))

    def chord_at(self, r: float) -> float:
        """Chord (m) at radius ``r`` (m): ``chord``, or ``chord_table`` (rows r/R, m) interpolated."""
        return self.chord if self.chord_table is None else _interp(self.chord_table, r / self.radius)

    def twist_at(self, r: float) -> float:
        """Twist (rad) added to the root pitch at radius ``r`` (m): linear, or ``twist_table``
        (rows r/R, rad) interpolated."""
        return self.twist * r / self.radius if self.twist_table is None else _interp(self.twist_table, r / self.radius)

    @property
    def sense(self) -> int:
        """+1 when the rotor turns about its thrust axis (right-handed azimuth frame; blade y
        towards the leading edge), -1 when against it (blade y towards the trailing edge)."""
        return 1 if np.linalg.det(self.shaft_frame) > 0 else -1

    def stations(self) -> tuple[np.ndarray, float]:
        """Strip mid-radii (m, from the rotor axis) and width (m)."""
        r0 = self.root_cutout * self.radius
        dr = (self.radius - r0) / self.elements
        return r0 + dr * (np.arange(self.elements) + 0.5), dr

    def bodies(self, blade: str) -> list[tuple[str, float, np.ndarray]]:
        """The bodies of ``blade`` with the radius of their joints (m) and which stations each
        carries (mask): ``pieces[blade]`` lists them root first for a blade of several bodies
        (an elastic blade's segments); otherwise the blade is one body jointed at ``hinge_radius``."""
        parts = self.pieces.get(blade, [(blade, self.hinge_radius)])
        radii, ends = self.stations()[0], [r for _, r in parts[1:]] + [np.inf]
        return [(body, r, (radii >= (r if k else -np.inf)) & (radii < end))
                for k, ((body, r), end) in enumerate(zip(parts, ends))]


def _interp(rows, x: float) -> float:
    """Linear interpolation of the rows ``(x_k, y_k)`` at ``x``, held beyond the ends."""
    rows = np.asarray(rows, float)
    return float(np.interp(x, rows[:, 0], rows[:, 1]))


@dataclass(frozen=True)
class RotorModel:
    """Per-scene switches: ``inflow`` "uniform" | "pitt-peters"; ``tip_loss`` the effective
    radius factor B (1: off); ``compressibility`` (None: off); ``wake`` the geometry of the
    wake the rotor publishes for the airframe (None: no wake on the airframe); ``ground_effect``:
    the induced velocity reduced near the ground (:mod:`mbs.aero.ground`; the ground plane at the
    world's ``z`` = the run-time parameter ``height``, m); ``duct_exit_ratio``: a ducted fan
    whose duct's exit area is σ_d times the disc's (:func:`mbs.aero.inflow.ducted_fan_thrust`;
    0: an open rotor)."""

    inflow: str = "uniform"
    tip_loss: float = 1.0
    compressibility: Compressibility | None = None
    wake: WakeGeometry | None = None
    ground_effect: bool = False
    duct_exit_ratio: float = 0.0

    def __post_init__(self):
        if self.inflow not in inf.INFLOW_MODELS:
            raise ValueError(f"inflow {self.inflow!r}: choose one of {', '.join(inf.INFLOW_MODELS)}")
        low, high = inf.DUCT_EXIT_RATIO
        if self.duct_exit_ratio and not low <= self.duct_exit_ratio <= high:
            raise ValueError(f"duct exit ratio {self.duct_exit_ratio} outside [{low}, {high}] (0: an open rotor)")
        if self.duct_exit_ratio and (self.inflow != "uniform" or self.ground_effect or self.wake is not None):
            raise ValueError("a ducted fan takes uniform inflow, without ground effect or a published wake")
        if not 0.5 < self.tip_loss <= 1.0:
            raise ValueError(f"tip-loss factor B = {self.tip_loss} outside (0.5, 1]")

    def inflow_states(self, rotor: str) -> list[str]:
        """Names of the inflow states (m/s): ``<rotor>.inflow`` and, Pitt–Peters, ``_1s``, ``_1c``."""
        suffixes = inf.HARMONICS if self.inflow == "pitt-peters" else ("",)
        return [f"{rotor}.inflow{s}" for s in suffixes]


@dataclass
class DiscLoads:
    """Sums over the elements: thrust (N), shaft torque (N m, positive when the shaft drives
    the rotor), first moments of the thrust ``Σ dT y/R``, ``Σ dT x/R`` (N, shaft frame)."""

    thrust: object = 0
    torque: object = 0
    moment_s: object = 0
    moment_c: object = 0
    stalled: object = 0  # m³/s²: Σ U² dr over the elements beyond the analytic section's stall (smoothed)
    pressure: object = 0  # m³/s²: Σ U² dr over every analytic element (U their air speed)

    def __add__(self, other: DiscLoads) -> DiscLoads:
        return DiscLoads(self.thrust + other.thrust, self.torque + other.torque,
                         self.moment_s + other.moment_s, self.moment_c + other.moment_c, self.stalled + other.stalled,
                         self.pressure + other.pressure)


STALL_EDGE = 0.01
"""rad: the width over which an element counts as beyond its stall angle (a smooth step, so the
stall share is differentiable)."""


def stalled_share(airfoil, w_c, w_n):
    """0 to 1: whether an analytic section at the air ``(w_c, w_n)`` is beyond its stall angle and
    short of 45 deg (smooth steps over :data:`STALL_EDGE`): where its lift is only bounded. Beyond
    45 deg (the reverse-flow region's edge) it is a flat plate's, as modelled; 0 for a table
    section, whose tables hold the stall."""
    section, shift = (airfoil.section, airfoil.alpha_0) if isinstance(airfoil, ZeroLiftShift) else (airfoil, 0.0)
    if not isinstance(section, Airfoil):
        return 0
    size = ca.sqrt((section_angle(airfoil, w_c, w_n)[0] - shift) ** 2 + EPS**2)
    beyond = 0.5 * (1 + ca.tanh((size - section.alpha_stall) / STALL_EDGE))
    return beyond * 0.5 * (1 - ca.tanh((size - np.pi / 4) / STALL_EDGE))  # never negative (a stall angle past 45 deg)


@dataclass
class _Air:
    """What one evaluation of a rotor reads of the air: density (kg/m³), section coefficients
    (None: the aerofoil's), the air's velocity at the hub (3,) (m/s, world; None: still)."""

    rho: object
    coefficients: object
    wind: object = None
    mach: object = None  # the airfoil tables' section Mach number of an air speed (None: no tables)
    ground: object = None  # the share of the induced velocity the blades see near the ground (None: far)

    def relative(self, velocity):
        """``velocity`` (3,) (world) through the air at the hub; the same expression in still air."""
        return velocity if self.wind is None else velocity - self.wind


class RotorAero(ForceElement):
    """Blade-element loads on every blade of ``rotor`` plus its dynamic inflow states.

    Blade body frames: x along the span (from the blade's joint at ``hinge_radius`` from the
    rotor axis), y towards the leading edge (the trailing edge when the rotor turns against
    its thrust axis, :attr:`Rotor.sense`), z the lift direction at zero pitch. The hub
    frame's z axis is the rotor's thrust axis. The inflow states (m/s) are positive down
    through the disc (against the thrust axis); the blades see ``κ`` times the induced
    velocity. The air (density, speed of sound, its velocity: wind, gusts, turbulence) is read
    through the state once per evaluation, its velocity at the hub for the whole disc
    (:mod:`mbs.environment.air`). Signals: ``<name>.thrust`` (N), ``<name>.torque`` (N m, shaft torque),
    ``<name>.power`` (W, torque × rotor speed) and, when the model has a wake geometry,
    ``<name>.wake`` (:class:`mbs.aero.wake.Wake`).
    """

    def __init__(self, rotor: Rotor, airfoil: Airfoil, rho: float, kappa: float, model: RotorModel = RotorModel(),
                 tables: BladeAirfoils | None = None):
        self.rotor, self.airfoil, self.rho, self.kappa, self.model = rotor, airfoil, rho, kappa, model
        self.tables = tables
        self.name = f"{rotor.name} aerodynamics"
        self.inflow = f"{rotor.name}.inflow"
        self.states = model.inflow_states(rotor.name)
        radii, dr = rotor.stations()
        self.lift = lift_factors(radii, dr, model.tip_loss * rotor.radius)
        comp = model.compressibility
        self.coefficients = comp.coefficients(airfoil) if comp else None

    def apply(self, state: State, loads: Loads) -> None:
        hub = state.body(self.rotor.hub)
        axis = hub.rotation[:, 2]
        v = [state.z(n) for n in self.states]
        shaft = self._shaft(state)
        air = _Air(state.density(self.rho), self._coefficients(state), state.air_velocity(hub.position),
                   self._mach(state))
        hub_velocity = air.relative(hub.velocity)
        if self.model.ground_effect:
            air.ground = self._ground(state, hub, axis, hub_velocity, v)
        disc = sum((self._blade(state, loads, b, hub, axis, v, shaft, air) for b in self.rotor.blades), DiscLoads())
        for name, rate in zip(self.states, self._inflow_rates(hub_velocity, axis, v, disc, air.rho)):
            loads.set_rate(name, rate)
        self._publish(state, hub, disc)
        if self.model.duct_exit_ratio:
            self._duct(state, loads, shaft[:, 2], ca.dot(hub_velocity, axis), v[0], air.rho)
        if self.model.wake is not None:
            state.signals[f"{self.rotor.name}.wake"] = Wake(hub.position, shaft, v, -hub_velocity, disc.torque,
                                                            self.rotor.radius, air.rho, self.model.wake)

    def _duct(self, state: State, loads: Loads, axis, v_normal, v0, rho) -> None:
        """The duct's thrust along the non-rotating thrust ``axis`` (world), on the body that holds
        the shaft at the hub's centre; published as ``<rotor>.duct_thrust`` (N)."""
        _, duct = inf.ducted_fan_thrust(v0, v_normal, rho, self.rotor.radius, self.model.duct_exit_ratio,
                                        self.model.tip_loss**2)
        state.signals[f"{self.rotor.name}.duct_thrust"] = duct
        body = self.rotor.shaft_body
        if body is None:  # a shaft on the ground: the duct's thrust goes into it
            return
        frame = state.body(body)
        centre = ca.mtimes(frame.rotation.T, state.body(self.rotor.hub).position - frame.position)
        loads.add_force(body, duct * axis, point=centre, frame="world", rotation=frame.rotation)

    def _ground(self, state: State, hub, axis, hub_velocity, v):
        """The share of the induced velocity the blades see near the ground (:mod:`mbs.aero.ground`),
        published as ``<rotor>.ground_factor``."""
        from mbs.aero.ground import inflow_factor

        normal = ca.dot(hub_velocity, axis)
        height = state.p["height"] - hub.position[2]  # the ground plane at world z = height (z down)
        factor = inflow_factor(height, self.rotor.radius, ca.dot(hub_velocity, hub_velocity) - normal**2, v[0])
        state.signals[f"{self.rotor.name}.ground_factor"] = factor
        return factor

    def _coefficients(self, state: State):
        """The section coefficients with compressibility at the state's speed of sound (None: the aerofoil's)."""
        comp = self.model.compressibility
        if comp is None:
            return None
        sound = state.speed_of_sound(comp.speed_of_sound)
        return self.coefficients if sound is comp.speed_of_sound else replace(comp, speed_of_sound=sound).coefficients(
            self.airfoil)

    def _still_air(self) -> _Air:
        """Still air at the element's own density and speed of sound."""
        return _Air(self.rho, self.coefficients, None, None if self.tables is None else self.tables.mach)

    def _mach(self, state: State):
        """The airfoil tables' Mach number of an air speed at the state's speed of sound (None: no tables)."""
        if self.tables is None:
            return None
        sound = state.speed_of_sound(self.tables.speed_of_sound)
        return self.tables.mach if sound is self.tables.speed_of_sound else replace(self.tables,
                                                                                     speed_of_sound=sound).mach

    def _shaft(self, state: State):
        """Non-rotating shaft frame (3, 3) in world axes."""
        frame = ca.DM(self.rotor.shaft_frame)
        return frame if self.rotor.shaft_body is None else ca.mtimes(state.body(self.rotor.shaft_body).rotation, frame)

    def _air(self, disc_point, axis, v):
        """Induced air velocity (m/s) along ``axis`` at the element whose position in the disc
        is ``disc_point = (x/R, y/R)`` (shaft frame)."""
        if len(v) == 1:
            return -self.kappa * v[0] * axis
        return -self.kappa * inf.induced_velocity(v, *disc_point) * axis

    def _induced(self, disc_point, axis, v, air):
        """:meth:`_air`, times the share the blades see near the ground (when the model has ground effect)."""
        induced = self._air(disc_point, axis, v)
        return induced if air.ground is None else air.ground * induced

    def _blade(self, state, loads, blade, hub, axis, v, shaft, air) -> DiscLoads:
        """Loads of one blade's elements, body by body (:meth:`Rotor.bodies`)."""
        return sum((self._body(state, loads, body, root, keep, hub, axis, v, shaft, air)
                    for body, root, keep in self.rotor.bodies(blade) if keep.any()), DiscLoads())

    def _body(self, state, loads, blade, root, keep, hub, axis, v, shaft, air) -> DiscLoads:
        """Loads of the elements ``keep`` of one blade body jointed at radius ``root``, computed
        in its axes: its own velocity (through the air at the hub), thrust axis and shaft axes
        are turned into them once, and the element forces are summed into one force and torque
        on the body."""
        radii, dr = self.rotor.stations()
        m = state.body(blade)
        turn_in = m.rotation.T
        origin, axis_b = ca.mtimes(turn_in, air.relative(m.velocity)), ca.mtimes(turn_in, axis)
        shaft_b, hinge = ca.mtimes(turn_in, shaft[:, :2]), ca.mtimes(turn_in, m.position - hub.position)
        force, torque, out = ca.SX.zeros(3), ca.SX.zeros(3), DiscLoads()
        per_radius = 1.0 / self.rotor.radius
        for r, lift in zip(radii[keep], np.array(self.lift)[keep]):
            arm = r - root
            if self.rotor.swept(r):
                f, moment, disc = self._swept_element(m, origin, hinge, axis_b, shaft_b, v, arm, r, dr, lift, air)
                force, torque, out = force + f, torque + moment, out + disc
                continue
            lever = hinge + ca.DM([arm, 0, 0])
            disc_point = (ca.dot(lever, shaft_b[:, 0]) * per_radius, ca.dot(lever, shaft_b[:, 1]) * per_radius)
            velocity = origin + arm * ca.vertcat(0, m.omega[2], -m.omega[1])  # + ω × (arm, 0, 0)
            w = self._induced(disc_point, axis_b, v, air) - velocity
            if self.tables is None:
                f = self._element_force(w, r, dr, lift, air)
                torque = torque + arm * ca.vertcat(0, -f[2], f[1])  # + (arm, 0, 0) × f
                pressure = dr * (w[1] ** 2 + w[2] ** 2)
                out = out + DiscLoads(stalled=pressure * stalled_share(self.airfoil, *turn(
                    self.rotor.sense * w[1], w[2], self.rotor.twist_at(r))), pressure=pressure)
            else:
                f, pitching = self._table_element(w, r, dr, lift, air)
                torque = torque + ca.vertcat(pitching, -arm * f[2], arm * f[1])
            force = force + f
            out = out + self._element_loads(f, lever, axis_b, disc_point, self.rotor.sense)
        loads.add_force(blade, force, point=[0.0, 0.0, 0.0], frame="body", rotation=m.rotation)
        loads.add_torque(blade, torque)
        return out

    def _element_force(self, w, r: float, dr: float, lift: float, air):
        """Element force (3,) (N, blade axes) from the air velocity ``w`` (3,) (m/s, blade axes)."""
        twist = self.rotor.twist_at(r)
        sense = self.rotor.sense  # blade y along the leading edge (+1) or the trailing edge (-1)
        f_c, f_n = section_force(*turn(sense * w[1], w[2], twist), self.airfoil, air.rho, self.rotor.chord_at(r) * dr,
                                 lift, air.coefficients)
        f_y, f_z = turn(f_c, f_n, -twist)
        return ca.vertcat(0, sense * f_y, f_z)

    def _swept_element(self, m, origin, hinge, axis_b, shaft_b, v, arm: float, r: float, dr: float, lift: float,
                       air: _Air | None = None):
        """An element of the swept tip (simple sweep theory): its quarter chord lies aft of the
        blade's x axis (:meth:`Rotor.sweep_offset`), its chord turned by the sweep angle; the air
        velocity is resolved normal to the swept quarter-chord line (the component along it
        carries no load). Returns its force and torque (blade axes) and its disc loads; ``air``: the
        evaluation's (None: still air at the element's own density and speed of sound)."""
        air = air or self._still_air()
        sense, (c_x, c_y) = self.rotor.sense, self.rotor.sweep_chord()
        offset = -sense * self.rotor.sweep_offset(r)  # blade y of the quarter chord: aft of the axis
        point = ca.DM([arm, offset, 0])
        lever = hinge + point
        per_radius = 1.0 / self.rotor.radius
        disc_point = (ca.dot(lever, shaft_b[:, 0]) * per_radius, ca.dot(lever, shaft_b[:, 1]) * per_radius)
        velocity = origin + ca.cross(m.omega, point)
        w = self._induced(disc_point, axis_b, v, air) - velocity
        twist, chord = self.rotor.twist_at(r), self.rotor.chord_at(r)
        w_c = c_x * w[0] + c_y * sense * w[1]  # along the swept chord, towards the leading edge
        if self.tables is None:
            f_c, f_n = section_force(*turn(w_c, w[2], twist), self.airfoil, air.rho, chord * dr, lift,
                                     air.coefficients)
            moment = 0.0
        else:
            f_c, f_n, moment = table_section_loads(*turn(w_c, w[2], twist), self.tables.at(r / self.rotor.radius),
                                                   air.mach, air.rho, chord * dr, chord * c_y, lift)
        f_y, f_z = turn(f_c, f_n, -twist)
        f = ca.vertcat(c_x * f_y, c_y * sense * f_y, f_z)
        span = ca.DM([c_y, -sense * c_x, 0])  # outward along the swept quarter chord
        return f, ca.cross(point, f) + sense * moment * span, self._element_loads(f, lever, axis_b, disc_point, sense)

    def _table_element(self, w, r: float, dr: float, lift: float, air):
        """Element force (3,) (N, blade axes) and pitching moment about the blade's x axis (N m)
        from the air velocity ``w`` (3,) (m/s, blade axes), with the segment's airfoil tables."""
        twist, sense, chord = self.rotor.twist_at(r), self.rotor.sense, self.rotor.chord_at(r)
        airfoil = self.tables.at(r / self.rotor.radius)
        f_c, f_n, moment = table_section_loads(*turn(sense * w[1], w[2], twist), airfoil, air.mach, air.rho,
                                               chord * dr, chord, lift)
        f_y, f_z = turn(f_c, f_n, -twist)
        return ca.vertcat(0, sense * f_y, f_z), sense * moment

    @staticmethod
    def _element_loads(force, lever, axis, disc_point, sense: int) -> DiscLoads:
        """Thrust, shaft torque (about the axis of rotation) and thrust moments of one element
        force (3,) (N) at ``lever`` (m from the hub), both in the frame of ``axis``;
        ``disc_point`` its ``(x/R, y/R)`` in the azimuth frame."""
        d_thrust = ca.dot(force, axis)
        return DiscLoads(d_thrust, -sense * ca.dot(axis, ca.cross(lever, force)), d_thrust * disc_point[1],
                         d_thrust * disc_point[0])

    def _inflow_rates(self, hub_velocity, axis, v, disc: DiscLoads, rho) -> list:
        v_normal = ca.dot(hub_velocity, axis)
        v_inplane2 = ca.dot(hub_velocity, hub_velocity) - v_normal**2
        area_factor = self.model.tip_loss**2
        if self.model.duct_exit_ratio:
            return [inf.ducted_rate(v[0], disc.thrust, v_normal, rho, self.rotor.radius, self.model.duct_exit_ratio,
                                    area_factor)]
        if len(v) == 1:
            return [inf.uniform_rate(v[0], disc.thrust, v_inplane2, v_normal, rho, self.rotor.radius, area_factor)]
        loads = (disc.thrust, disc.moment_s, disc.moment_c)
        return inf.pitt_peters_rates(v, loads, v_inplane2, v_normal, rho, self.rotor.radius, area_factor)

    def _publish(self, state: State, hub, disc: DiscLoads) -> None:
        try:
            speed = self.rotor.speed_ratio * state.p["omega"]
        except KeyError:  # rotor turning freely: its own angular speed about the shaft
            speed = self.rotor.sense * hub.omega[2]
        name = self.rotor.name
        state.signals.update({f"{name}.thrust": disc.thrust, f"{name}.torque": disc.torque,
                              f"{name}.power": disc.torque * speed,
                              f"{name}.stalled_share": disc.stalled / (disc.pressure + EPS)})
