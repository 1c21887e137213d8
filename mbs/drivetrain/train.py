"""The main and tail rotors on one drive train.

Coordinates: the main hub's ``main_hub.azimuth`` (rad, about the shaft's z, the rotor turning
in its sense ``s``: ``ψ = s · azimuth``); the transmission (``transmission.angle``: the main
gearbox, shafts and the engines' power turbines as one disc on the shaft axis with the file's
``transmission_inertia``, referred to rotor speed); the tail hub's azimuth, geared to the
transmission, ``tail_hub.azimuth = s_t g s · transmission.angle`` (``g`` the gear ratio, ``s_t``
the tail rotor's sense). A rigid drive train makes the transmission's angle the main hub's; a
flexible one keeps it a state and joins them by the main shaft's torsion spring and damper
(:class:`mbs.drivetrain.TorsionShaft`; the damper only where the scene has dampers). The blades' pitch follows the swashplate's law in the
actual azimuth, ``θ = θ0 + θ1c cos ψ_b + θ1s sin ψ_b`` (``ψ_b = ψ + 2πk/N``): a dependent
coordinate of the main hub's azimuth, exactly as the driven hub's pitch law is in time.

Engines act on ``transmission.angle`` (positive: driving the rotors in their sense), so their
torque reaches the rotors through the map of the dependent coordinates: main rotor, tail rotor
(times ``g``) and the transmission share one speed; the drive train's inertia is theirs
referred to the main rotor (:func:`inertia_about_axes`).
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from mbs.drivetrain.shaft import TorsionShaft
from mbs.forces import ForceElement
from mbs.joints import Hinge

DRIVE_TRAINS = ("rigid", "flexible")
TRANSMISSION = "transmission"
MAIN, TAIL = "main_hub.azimuth", "tail_hub.azimuth"
TRANSMISSION_MASS = 1.0  # kg: the disc that carries the transmission's inertia (taken from the airframe's mass)


@dataclass(frozen=True)
class DriveTrain:
    """The data of a drive train: ``transmission_inertia`` (kg m², referred to rotor speed),
    main shaft ``stiffness`` (N m/rad) and ``damping`` (N m s/rad), tail ``gear_ratio``,
    senses of rotation of the main and tail rotors."""

    transmission_inertia: float
    stiffness: float
    damping: float
    gear_ratio: float
    main_sense: int
    tail_sense: int

    @classmethod
    def of(cls, d) -> "DriveTrain":
        """From the aircraft data ``d`` (its ``[drive_train]`` section); ValueError without it."""
        from mbs.models.helicopter import frames as fr

        if not d.get("drive_train"):
            raise ValueError("the aircraft data have no [drive_train] section (transmission_inertia, shaft_stiffness, "
                             "shaft_damping): a scene with the rotor speed as a state needs it")
        dt = d["drive_train"]
        return cls(dt["transmission_inertia"], dt["shaft_stiffness"], dt["shaft_damping"],
                   d["tail_rotor"]["gear_ratio"], fr.main_sense(d), fr.tail_sense(d))

    @property
    def tail_factor(self) -> float:
        """``d(tail_hub.azimuth)/d(transmission.angle)``."""
        return self.tail_sense * self.gear_ratio * self.main_sense


def check(cfg) -> None:
    """ValueError when ``cfg`` asks for a drive train where it cannot work."""
    if cfg.engines and cfg.drive_train is None:
        raise ValueError("engines drive the rotors through a drive train whose speed is a state: set drive_train "
                         "('rigid' or 'flexible'); a constant-speed scene has no engine to fail")
    if cfg.failure_time is not None and not cfg.engines:
        raise ValueError(f"failure_time = {cfg.failure_time!r}: the scene has no engines to fail (engines = True)")
    if cfg.drive_train is None:
        return
    if cfg.drive_train not in DRIVE_TRAINS:
        raise ValueError(f"drive_train = {cfg.drive_train!r}: choose None (rotors at constant speed), 'rigid' or "
                         "'flexible' (a torsionally flexible main shaft)")
    needs = [("rotors", "driven", "the pilot's pitch inputs on hubs whose azimuth the drive train frees"),
             ("swashplate", None, "the swashplate's loops follow a prescribed azimuth"),
             ("blade_segments", 0, "rigid blades"), ("blade_modes", 0, "rigid blades")]
    for name, value, why in needs:
        if getattr(cfg, name) != value:
            raise ValueError(f"drive_train = {cfg.drive_train!r} needs {name} = {value!r} ({why}), not "
                             f"{getattr(cfg, name)!r}")


def pitch_law(psi0: float, sense: int):
    """The blade's pitch ``θ0 + θ1c cos ψ_b + θ1s sin ψ_b`` as a dependent coordinate of the main
    hub's azimuth (``ψ_b = s · azimuth + psi0``)."""
    def pitch(q, t, p):
        psi = sense * q[MAIN] + psi0
        return p["collective"] + p["lateral_cyclic"] * ca.cos(psi) + p["longitudinal_cyclic"] * ca.sin(psi)
    return pitch


def add_drive_train(m, d, cfg, parent: str) -> DriveTrain:
    """The transmission body and the drive train's dependent coordinates and shaft on the model
    ``m`` (the hubs and blades already built with free hinges)."""
    from mbs.models.helicopter import frames as fr

    train = DriveTrain.of(d)
    tilt = d["main_rotor"]["shaft_tilt"] if cfg.shaft_tilt else 0.0
    at = fr.main_hub_position(d) if parent != "world" else np.zeros(3)
    i_t = train.transmission_inertia
    m.add_body(TRANSMISSION, parent, Hinge((0, 0, 1), name="angle"), mass=TRANSMISSION_MASS,
               inertia=np.diag([i_t / 2, i_t / 2, i_t]), at=at, frame=fr.shaft_frame(tilt))
    angle = f"{TRANSMISSION}.angle"
    if cfg.drive_train == "rigid":
        m.add_dependent(angle, lambda q, t, p: q[MAIN])
    else:
        m.add_force(TorsionShaft("main shaft", angle, MAIN, train.stiffness, train.damping if cfg.dampers else 0.0))
    if cfg.tail_rotor:
        m.add_dependent(TAIL, lambda q, t, p: train.tail_factor * q[angle])
    return train


class DriveTorque(ForceElement):
    """The run-time parameter ``drive_torque`` (N m) on the transmission's coordinate, driving the
    rotors in their sense ``sense``."""

    def __init__(self, coordinate: str, sense: int):
        self.name, self.coordinate, self.sense = "drive torque", coordinate, sense

    def apply(self, state, loads):
        loads.add_generalized(self.coordinate + "_rate", self.sense * state.p["drive_torque"])


def transmission_mass(cfg) -> float:
    """kg of the transmission body a scene builds (0 without a drive train)."""
    return TRANSMISSION_MASS if cfg.drive_train else 0.0




def inertia_about_axes(poses: dict, bodies: dict, d) -> float:
    """The drive train's inertia referred to the main rotor (kg m²), a closed form from the
    bodies: each main-rotor body and the transmission about the main shaft's axis, each
    tail-rotor body about the tail shaft's axis times the gear ratio squared. ``poses``: body
    name -> (origin (3,) m, rotation (3, 3)) in world; ``bodies``: name -> :class:`mbs.tree.Body`."""
    hub_o, hub_r = poses["main_hub"]
    total = _about(poses, bodies, _subtree(bodies, "main_hub") + [TRANSMISSION], hub_o, hub_r[:, 2])
    if "tail_hub" in poses:
        tail_o, tail_r = poses["tail_hub"]
        total += d["tail_rotor"]["gear_ratio"] ** 2 * _about(poses, bodies, _subtree(bodies, "tail_hub"), tail_o,
                                                             tail_r[:, 2])
    return total


def _subtree(bodies: dict, root: str) -> list[str]:
    out, frontier = [root], [root]
    while frontier:
        frontier = [b.name for b in bodies.values() if b.parent in frontier]
        out += frontier
    return out


def _about(poses: dict, bodies: dict, names: list[str], point, axis) -> float:
    """Sum of the bodies' moments of inertia (kg m²) about the line through ``point`` along ``axis``."""
    total = 0.0
    for n in names:
        b, (o, r) = bodies[n], poses[n]
        c = o + r @ b.com - point
        lever = c - (c @ axis) * axis
        total += axis @ (r @ b.inertia @ r.T) @ axis + b.mass * lever @ lever
    return float(total)


def add_outputs(m, d, cfg) -> None:
    """The rotors' speeds (rad/s, in their senses) and, flexible, the main shaft's twist and torque."""
    train = DriveTrain.of(d)
    m.add_output("main_rotor.speed", lambda s: train.main_sense * s.v(MAIN + "_rate"), "rad/s",
                 "main-rotor speed (the hub's, in its sense of rotation)")
    angle = f"{TRANSMISSION}.angle"
    if cfg.tail_rotor:
        m.add_output("tail_rotor.speed", lambda s: abs(train.tail_factor) * train.main_sense * s.v(angle + "_rate"),
                     "rad/s", "tail-rotor speed, gear_ratio times the transmission's")
    if cfg.drive_train == "flexible":
        shaft = next(f for f in m.forces if isinstance(f, TorsionShaft))
        m.add_output("main_shaft.twist", lambda s: train.main_sense * shaft.twist(s), "rad",
                     "main shaft's twist, hub ahead of the transmission in the rotor's sense")
