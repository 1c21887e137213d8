"""The main rotor's swashplate and pitch links as local loops (:mod:`mbs.loops`).

Three actuators set the non-rotating plate's height ``Z`` and tilt ``(τc, τs)`` (the plate's
height at azimuth ψ and radius r is ``Z + r (τc cos ψ + τs sin ψ)``, exactly, for a rigid
plate whose normal is ``(-τc, -τs, √(1 - τc² - τs²))`` in the rotor's azimuth frame); each
actuator moves its ball on the plate along the shaft, so the mixing from the three
displacements to ``(Z, τc, τs)`` is linear and exact. The rotating plate lies in the same plane
and turns with the hub (an ideal scissors link). One rigid pitch link per blade joins the
rotating plate, ``plate_radius`` from the shaft and ``phase`` ahead of the blade, to the upper
ball on the pitch horn; the blade's pitch angle is the dependent coordinate of that link's
loop (:class:`mbs.loops.LinkLoop`, closed form), a function of the blade's flap and lag (a
horn on the blade) or of neither (a horn on the feathering housing), the rotor azimuth and the
controls. The geometry is the aircraft file's ``[swashplate]`` section.

Controls: pilot pitch inputs (``collective``, ``lateral_cyclic``, ``longitudinal_cyclic``, rad)
mixed into the plate by the kinematics linearised at neutral (``Z = h θ0``, the tilt turned
by the phase), or the three actuator displacements themselves (m). The blade pitch that
results is an output (``blade<k>.pitch``); it differs from the pilot inputs by the
mechanism's nonlinearity and couplings.

Loads (outputs, from the joint reactions): each pitch link's axial force (the blade's moment
about its feathering axis over the link's moment arm, ``-∂ℓ/∂θ`` by AD) and each actuator's
force (the massless plate's equilibrium under the links' forces).
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from mbs.forces import ForceElement
from mbs.joints import Hinge, Serial
from mbs.loops import Assembly, LinkLoop, LoopJoint, Newton, add_loop_outputs
from mbs.loops.outputs import joint_coordinates
from mbs.models.helicopter.hinges import main_flap_hinge
from mbs.tree import Model

PITCH_INPUTS = ("collective", "lateral_cyclic", "longitudinal_cyclic")


@dataclass(frozen=True)
class Swashplate:
    """The ``[swashplate]`` geometry (m, rad) with the flap hinge offset ``hinge_offset`` (m)."""

    horn: str
    arm: float
    height: float
    offset: float
    length: float
    lean: float
    radius: float
    phase: float
    plate_height: float
    hinge_offset: float
    actuator_radius: float
    azimuths: tuple
    stroke: float

    @classmethod
    def of(cls, d) -> "Swashplate":
        sp = d.get("swashplate") or {}
        if not sp:
            raise ValueError(f"aircraft {d['aircraft']['name']!r} has no [swashplate] section, which the swashplate "
                             "scenes need (the mechanism's geometry): uncomment the [swashplate] block that 'heli "
                             "aircraft new' writes and put your aircraft's values in it, or use a scene without "
                             "the swashplate (forward-flight)")
        return cls(sp["horn"], sp["horn_arm"], sp["horn_height"], sp["ball_offset"], sp["link_length"],
                   sp["link_lean"], sp["plate_radius"], sp["phase"], sp["plate_height"],
                   d["main_rotor"]["flap_hinge_offset"], sp["actuator_radius"], tuple(sp["actuator_azimuths"]),
                   sp["actuator_stroke"])

    def ball(self, sense: int) -> np.ndarray:
        """The upper ball in the blade frame at zero pitch, from the blade's hinge point (m)."""
        return np.array([self.offset, sense * self.arm, self.height])

    def neutral_anchor(self, sense: int) -> np.ndarray:
        """The lower ball at neutral in the blade's joint frame (m)."""
        return self.ball(sense) - self.length * np.array([np.sin(self.lean), 0.0, np.cos(self.lean)])

    def mixing(self) -> np.ndarray:
        """(3, 3): actuator displacements (m) = mixing @ (Z (m), τc, τs)."""
        return np.array([[1.0, self.actuator_radius * np.cos(a), self.actuator_radius * np.sin(a)]
                         for a in self.azimuths])

    def plate_from_pitch(self, collective, lateral, longitudinal):
        """(Z, τc, τs) of pilot pitch inputs (rad), by the kinematics linearised at neutral."""
        k, c, s = self.arm / self.radius, np.cos(self.phase), np.sin(self.phase)
        return self.arm * collective, k * (c * lateral - s * longitudinal), k * (s * lateral + c * longitudinal)

    def pitch_from_plate(self, z, tc, ts):
        """Pilot pitch inputs (rad) equivalent to a plate position: the inverse of :meth:`plate_from_pitch`."""
        k, c, s = self.radius / self.arm, np.cos(self.phase), np.sin(self.phase)
        return z / self.arm, k * (c * tc + s * ts), k * (-s * tc + c * ts)

    def actuators_from_pitch(self, collective, lateral, longitudinal) -> np.ndarray:
        return self.mixing() @ np.array(self.plate_from_pitch(collective, lateral, longitudinal), dtype=float)

    def tilt(self, tc, ts) -> ca.SX:
        """Rotation (3, 3) taking the shaft axis to the plate's normal, azimuth-frame components."""
        v = ca.vertcat(ts, -tc, 0)
        vx = ca.vertcat(ca.horzcat(0, -v[2], v[1]), ca.horzcat(v[2], 0, -v[0]), ca.horzcat(-v[1], v[0], 0))
        return ca.SX.eye(3) + vx + ca.mtimes(vx, vx) / (1 + ca.sqrt(1 - tc**2 - ts**2))

    def on_plate(self, plate, radius: float, azimuth) -> ca.SX:
        """The plate's point at ``radius`` (m) and plate azimuth ``azimuth`` (rad), azimuth frame (3,)."""
        z, tc, ts = plate
        flat = ca.vertcat(radius * ca.cos(azimuth), radius * ca.sin(azimuth), 0)
        return ca.vertcat(0, 0, self.plate_height + z) + ca.mtimes(self.tilt(tc, ts), flat)

    def lower_ball(self, plate, psi) -> ca.SX:
        """A blade's lower ball in its rotating frame (x from the axis, y ahead, z up), (3,),
        with the blade at azimuth ``psi``."""
        b = self.on_plate(plate, self.radius, psi + self.phase)
        return ca.vertcat(ca.cos(psi) * b[0] + ca.sin(psi) * b[1], -ca.sin(psi) * b[0] + ca.cos(psi) * b[1], b[2])


def check(cfg) -> None:
    """ValueError when ``cfg`` asks for the swashplate where it cannot work."""
    if cfg.swashplate not in (None, "pitch", "actuators"):
        raise ValueError(f"swashplate = {cfg.swashplate!r}: choose None (driven pitch), 'pitch' (pilot pitch inputs "
                         "through the mechanism) or 'actuators' (actuator displacements as the controls)")
    if cfg.loop_solver not in ("closed-form", "newton"):
        raise ValueError(f"loop_solver = {cfg.loop_solver!r}: choose 'closed-form' or 'newton'")
    if cfg.pitch_link not in ("rigid", "elastic"):
        raise ValueError(f"pitch_link = {cfg.pitch_link!r}: choose 'rigid' (the links close their loops) or "
                         "'elastic' (the pitch a state, each link a spring of the file's link_stiffness)")
    if cfg.swashplate is None:
        for name, default in (("loop_solver", "closed-form"), ("pitch_link", "rigid")):
            if getattr(cfg, name) != default:
                raise ValueError(f"{name} applies to the swashplate's pitch links: turn the swashplate on")
        return
    if cfg.pitch_link == "elastic" and cfg.loop_solver != "closed-form":
        raise ValueError("loop_solver: elastic pitch links have no loop to solve (the pitch is a state)")
    needs = [("rotors", "driven", "the pitch links follow the hub's prescribed azimuth"),
             ("pitch_hinge", True, "the links turn the blades' pitch hinges"), ("blade_segments", 0, "rigid blades"),
             ("blade_modes", 0, "rigid blades")]
    for name, value, why in needs:
        if getattr(cfg, name) != value:
            raise ValueError(f"the swashplate needs {name} = {value!r} ({why}), not {getattr(cfg, name)!r}")


def _pitch_guess(sp: Swashplate, plate, psi):
    """Newton's predictor: the small-angle mechanism (the linearised plate law, minus δ3 and
    lean couplings for a horn on the blade)."""
    def guess(joint, q, t, p):
        c0, c1c, c1s = sp.pitch_from_plate(*plate(p))
        theta = c0 + c1c * ca.cos(psi(t, p)) + c1s * ca.sin(psi(t, p))
        if sp.horn == "blade":
            theta = theta - sp.offset / sp.arm * q[0] - np.tan(sp.lean) * q[1]
        return theta
    return guess


def blade_joint(d, cfg, k: int, psi0: float, sense: int) -> LoopJoint | Serial:
    """Blade ``k`` (from 1)'s joint: flap, lag and pitch hinges, the pitch solved by its rigid
    pitch link (a :class:`LoopJoint`) or, with an elastic link, a free hinge (the link is then a
    spring, :class:`ElasticLink`)."""
    joint = link_joint(d, cfg, k, psi0, sense)
    return joint if cfg.pitch_link == "rigid" else Serial(*joint.parts)


def link_joint(d, cfg, k: int, psi0: float, sense: int) -> LoopJoint:
    """Blade ``k`` (from 1)'s flap, lag and pitch hinges, its pitch solved by its pitch link."""
    mr, sp = d["main_rotor"], Swashplate.of(d)
    plate = plate_of(d, cfg)

    def psi(t, p):
        return p["omega"] * t + psi0

    def anchor(t, p):
        b = sp.lower_ball(plate(p), psi(t, p))
        return ca.vertcat(b[0] - sp.hinge_offset, sense * b[1], b[2])

    link = LinkLoop(f"blade{k}.pitch_link", "pitch", tuple(sp.ball(sense)), sp.length, anchor,
                    Assembly(0.0, tuple(sp.neutral_anchor(sense))), inboard=sp.horn == "housing")
    loop = link if cfg.loop_solver == "closed-form" else Newton(link, _pitch_guess(sp, plate, psi),
                                                                iterations=NEWTON_ITERATIONS)
    return LoopJoint(main_flap_hinge(mr, sense),
                     Hinge((0, 0, -sense), name="lag", stiffness=mr["lag_stiffness"],
                           damping=mr["lag_damping"] if cfg.dampers else 0.0),
                     Hinge((sense, 0, 0), name="pitch"), loop=loop)


NEWTON_ITERATIONS = 4
"""Newton steps per pitch-link solve with ``loop_solver="newton"``: from the small-angle
predictor (within about 1e-2 rad) the third step is converged to round-off; one more makes the
rates and accelerations exact (:mod:`mbs.loops.newton`)."""


def plate_of(d, cfg):
    """``plate(p) -> (Z, τc, τs)`` from the model's control parameters."""
    sp = Swashplate.of(d)
    if cfg.swashplate == "actuators":
        inverse = np.linalg.inv(sp.mixing())
        return lambda p: tuple(sum(inverse[i, j] * p[f"actuator{j + 1}"] for j in range(3)) for i in range(3))
    return lambda p: sp.plate_from_pitch(*(p[n] for n in PITCH_INPUTS))


def add_actuator_inputs(m: Model, d, pitch: dict) -> None:
    """The three actuator displacements as controls (m, up), starting where the pilot
    ``pitch`` inputs (rad, by name) put them."""
    sp = Swashplate.of(d)
    if abs(np.linalg.det(sp.mixing())) < 1e-9 * sp.actuator_radius**2:
        raise ValueError("swashplate.actuator_azimuths: three actuators in line cannot set the plate's tilt")
    start = sp.actuators_from_pitch(*(pitch[n] for n in PITCH_INPUTS))
    for i, (x, azimuth) in enumerate(zip(start, sp.azimuths)):
        m.add_parameter(f"actuator{i + 1}", float(np.clip(x, -sp.stroke, sp.stroke)), "m",
                        f"displacement of the swashplate actuator at azimuth {np.degrees(azimuth):.0f} deg along the "
                        "shaft, up", control=True, low=-sp.stroke, high=sp.stroke)


# -- the links: rigid (a loop) or elastic (a spring) ---------------------------------------------

@dataclass
class PitchLink:
    """Blade ``blade``'s link: ``joint`` its geometry (the :class:`LoopJoint` of the rigid link),
    ``stiffness`` (N/m) when elastic (None: rigid)."""

    blade: str
    joint: LoopJoint
    stiffness: float | None = None

    @property
    def link(self) -> LinkLoop:
        loop = self.joint.loop
        return loop if isinstance(loop, LinkLoop) else loop.loop

    def q(self, state) -> ca.SX:
        return joint_coordinates(state, self.blade, self.joint)

    def pitch(self, state) -> ca.SX:
        """The blade's pitch (rad): the loop's solution, or the state of an elastic link's blade."""
        if self.stiffness is None:
            return self.joint.loop.solve(self.joint, self.q(state), state.t, state.p)
        return state.q(f"{self.blade}.pitch")

    def along(self, state) -> ca.SX:
        """From the lower to the upper ball (3,), m, in the blade's joint frame."""
        q_all = self.joint.merge(self.q(state), self.pitch(state))
        return self.link.point_in_joint(self.joint, q_all, state.t, state.p) - self.link.anchor(state.t, state.p)

    def arm(self, state) -> ca.SX:
        return self.link.arm(self.joint, self.q(state), self.pitch(state), state.t, state.p)

    def force(self, state) -> ca.SX:
        """Axial force (N), tension positive: the moment the blade needs about its feathering axis
        over the arm (rigid), the spring's ``k (ℓ - L)`` (elastic)."""
        if self.stiffness is None:
            return state.reactions.about_axis(self.blade, "pitch") / self.arm(state)
        return self.stiffness * (ca.norm_2(self.along(state)) - self.link.length)


@dataclass
class ElasticLink(ForceElement):
    """An elastic pitch link: the potential ``½ k (ℓ - L)²`` of its stretch, its generalized forces
    on the blade's flap, lag and pitch ``-∂V/∂q`` by AD."""

    link: PitchLink

    def __post_init__(self):
        self.name = f"{self.link.blade} elastic pitch link"

    def apply(self, state, loads):
        names = [f"{self.link.blade}.{n}" for n in ("flap", "lag", "pitch")]
        q = ca.vertcat(*[state.q(n) for n in names])
        gradient = ca.jacobian(self.potential(state), q)
        for k, name in enumerate(names):
            loads.add_generalized(f"{name}_rate", -gradient[k])

    def potential(self, state):
        return 0.5 * self.link.stiffness * (ca.norm_2(self.link.along(state)) - self.link.link.length) ** 2


def pitch_links(m: Model, d, cfg) -> list[PitchLink]:
    """The main rotor's links: the tree's loop joints (rigid) or rebuilt ones (elastic)."""
    from mbs.models.helicopter.frames import blade_azimuths, main_sense

    blades = [b for b in m.bodies if b.startswith("blade") and b[5:].isdigit()]
    if cfg.pitch_link == "rigid":
        return [PitchLink(b, m.bodies[b].joint) for b in blades]
    sense, stiffness = main_sense(d), d["swashplate"]["link_stiffness"]
    return [PitchLink(b, link_joint(d, cfg, k + 1, psi0, sense), stiffness)
            for k, (b, psi0) in enumerate(zip(blades, blade_azimuths(d["main_rotor"]["n_blades"])))]


def add_elastic_links(m: Model, d, cfg) -> None:
    """With elastic links: each link's spring, and each blade's pitch starting where its link is
    unstretched (the rigid loop's pitch at the initial state, time 0 and the default inputs)."""
    from mbs.joints import Params

    p = Params(list(m.parameters), ca.DM([q.default for q in m.parameters.values()]))
    for link in pitch_links(m, d, cfg):
        m.add_force(ElasticLink(link))
        q = ca.DM([m.initial.get(f"{link.blade}.{n}", 0.0) for n in ("flap", "lag")])
        m.set_initial(**{f"{link.blade}.pitch": float(link.joint.loop.solve(link.joint, q, 0.0, p))})


# -- outputs ------------------------------------------------------------------------------------

def add_swashplate_outputs(m: Model, d, cfg) -> list[str]:
    """Blade pitch, pitch-link closure (rigid) or stretch (elastic), force and arm, actuator
    displacements and forces."""
    sp, plate, links = Swashplate.of(d), plate_of(d, cfg), pitch_links(m, d, cfg)
    names = add_loop_outputs(m)
    for link in links:
        blade = link.blade
        if link.stiffness is not None:
            m.add_output(f"{blade}.pitch_link.length_error", lambda s, k=link: ca.norm_2(k.along(s)) - k.link.length,
                         "m", f"{blade} elastic pitch link's stretch")
        m.add_output(f"{blade}.pitch", link.pitch, "rad", f"{blade} pitch angle set by its pitch link, nose up")
        m.add_output(f"{blade}.pitch_link.arm", link.arm, "m",
                     f"{blade} pitch link's moment arm about the feathering axis (nose-up moment per newton of tension)")
        m.add_output(f"{blade}.pitch_link.force", link.force, "N", f"{blade} pitch link's axial force, tension positive")
        names += [f"{blade}.pitch", f"{blade}.pitch_link.arm", f"{blade}.pitch_link.force"]
    mix = sp.mixing()
    for i, azimuth in enumerate(sp.azimuths):
        where = f"swashplate actuator at azimuth {np.degrees(azimuth):.0f} deg"
        m.add_output(f"actuator{i + 1}.displacement", lambda s, i=i: sum(mix[i, j] * plate(s.p)[j] for j in range(3)),
                     "m", f"displacement of the {where} along the shaft, up")
        m.add_output(f"actuator{i + 1}.force", lambda s, i=i: _actuator_forces(s, sp, plate, links, d)[i], "N",
                     f"force of the {where} on the plate along the shaft, up (compression positive)")
        names += [f"actuator{i + 1}.displacement", f"actuator{i + 1}.force"]
    return names


def _actuator_forces(state, sp: Swashplate, plate, links: list[PitchLink], d) -> ca.SX:
    """(3,) N: the actuators' forces on the massless plate (along the shaft) that balance the
    links' pull along the shaft and their tilting moments about the plate's centre."""
    from mbs.models.helicopter.frames import blade_azimuths, main_sense

    sense, z = main_sense(d), plate(state.p)
    centre = ca.vertcat(0, 0, sp.plate_height + z[0])
    force, moment = ca.SX.zeros(3), ca.SX.zeros(3)
    for link, psi0 in zip(links, blade_azimuths(d["main_rotor"]["n_blades"])):
        along = link.along(state)
        u, psi = along / ca.norm_2(along), state.p["omega"] * state.t + psi0
        u_az = ca.vertcat(ca.cos(psi) * u[0] - ca.sin(psi) * sense * u[1], ca.sin(psi) * u[0]
                          + ca.cos(psi) * sense * u[1], u[2])
        pull = link.force(state) * u_az
        ball = sp.on_plate(z, sp.radius, psi + sp.phase)
        force, moment = force + pull, moment + ca.cross(ball - centre, pull)
    arms = [sp.on_plate(z, sp.actuator_radius, a) - centre for a in sp.azimuths]
    lhs = ca.vertcat(ca.horzcat(*[1 for _ in arms]), ca.horzcat(*[r[1] for r in arms]),
                     ca.horzcat(*[-r[0] for r in arms]))
    return ca.solve(lhs, -ca.vertcat(force[2], moment[0], moment[1]))
