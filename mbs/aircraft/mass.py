"""Mass properties of the aircraft's parts from its data: the rotors' hubs and blades, and the
airframe that remains of the aircraft's mass and inertia.

Each part is a rigid :class:`Part` in its own frame; the rotors' parts are summed in their hub
frame and averaged over a revolution (the inertia a slow motion of the aircraft feels), then
carried to body axes about the aircraft's centre of gravity (CG). ``aircraft.inertia`` says what
the file's ``Ixx … Ixz`` are: the airframe's alone about its own centre of mass, or the whole
aircraft's about the CG, from which the rotors' are subtracted here. SI units: kg, m, kg m².
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mbs.aircraft import geometry as geo

AVERAGE_AZIMUTHS = 36
"""Azimuths of the average over a revolution: exact for an inertia (a trigonometric polynomial of
degree 2 in the azimuth)."""


@dataclass(frozen=True)
class Part:
    """A rigid part: ``mass`` (kg), centre of mass ``com`` (3,) (m) and ``inertia`` (3, 3) about it
    (kg m²), both in the part's frame."""

    mass: float
    com: np.ndarray
    inertia: np.ndarray

    def placed(self, at, frame) -> "Part":
        """The part with its frame turned by ``frame`` (3, 3) and its origin moved to ``at`` (3,)."""
        frame = np.asarray(frame, dtype=float)
        return Part(self.mass, np.asarray(at, dtype=float) + frame @ self.com, frame @ self.inertia @ frame.T)

    def about(self, point) -> np.ndarray:
        """Inertia (3, 3) about ``point`` (3,) in the part's frame (parallel axes)."""
        r = self.com - np.asarray(point, dtype=float)
        return self.inertia + self.mass * (r @ r * np.eye(3) - np.outer(r, r))


def box_inertia(mass: float, lx: float, ly: float, lz: float) -> np.ndarray:
    """kg m²: a uniform box of edges ``lx, ly, lz`` (m) about its centre."""
    return mass / 12 * np.diag([ly**2 + lz**2, lx**2 + lz**2, lx**2 + ly**2])


def combine(parts: list[Part]) -> Part:
    """One part of ``parts`` (all in one frame): total mass, centre of mass and inertia about it."""
    mass = sum(p.mass for p in parts)
    com = sum(p.mass * p.com for p in parts) / mass
    return Part(mass, com, sum(p.about(com) for p in parts))


UNIFORM_TOLERANCE = 1e-3
"""Relative difference within which a blade's mass, first moment and flap inertia are the uniform
box's (a rounded override such as the Bo105's blade mass keeps the box)."""


def is_uniform_blade(mr: dict) -> bool:
    """Whether the main-rotor data's blade mass ``m``, first moment ``S`` and flap inertia ``I``
    (about the flap hinge) are a uniform blade's over the span ``R − e``: ``S = m (R − e)/2``,
    ``I = m (R − e)²/3``, each to :data:`UNIFORM_TOLERANCE`."""
    span, m = mr["radius"] - mr["flap_hinge_offset"], mr["blade_mass"]
    return (abs(m * span / 2 - mr["first_moment"]) <= UNIFORM_TOLERANCE * mr["first_moment"]
            and abs(m * span**2 / 3 - mr["I_flap"]) <= UNIFORM_TOLERANCE * mr["I_flap"])


def own_flap_inertia(mr: dict) -> float:
    """kg m²: the blade's flap inertia about its own centre of mass, ``I − S²/m`` (must be positive)."""
    return mr["I_flap"] - mr["first_moment"] ** 2 / mr["blade_mass"]


def main_blade(d) -> Part:
    """A main-rotor blade in its frame (x along the span from its flap hinge): integrated from its
    mass table (:class:`mbs.aircraft.blade.Distribution`); else the uniform box of the blade's
    mass, span, chord and thickness when its mass, first moment and flap inertia are a uniform
    blade's (:func:`is_uniform_blade`); else a body of exactly that mass, first moment and flap
    inertia about the hinge, with the box's chordwise and thickness terms (a blade whose mass is
    given beside its flap inertia or Lock number, as reports print them)."""
    mr = d["main_rotor"]
    if mr.get("mass_table"):
        from mbs.aircraft.blade import Distribution

        mass, com, inertia = Distribution(mr).body()
        return Part(mass, np.asarray(com, dtype=float), np.asarray(inertia, dtype=float))
    span, m = mr["radius"] - mr["flap_hinge_offset"], mr["blade_mass"]
    if is_uniform_blade(mr):
        return Part(m, np.array([span / 2, 0.0, 0.0]), box_inertia(m, span, mr["chord"], mr["blade_thickness"]))
    chord2, thick2 = mr["chord"] ** 2, mr["blade_thickness"] ** 2
    flap = own_flap_inertia(mr)
    return Part(m, np.array([mr["first_moment"] / m, 0.0, 0.0]),
                np.diag([m * (chord2 + thick2) / 12, flap, flap + m * (chord2 - thick2) / 12]))


def main_hub(d) -> Part:
    """The main-rotor hub, a solid disc about the shaft."""
    mr = d["main_rotor"]
    m, r = mr["hub_mass"], mr["hub_radius"]
    return Part(m, np.zeros(3), m / 4 * np.diag([r**2, r**2, 2 * r**2]))


def tail_blade(d) -> Part:
    """A tail-rotor blade in its frame (x along the span from the axis, or from the flap hinge
    of a flapping hub): a uniform box."""
    tr = d["tail_rotor"]
    span = tr["radius"] - tail_hinge(tr)
    return Part(tr["blade_mass"], np.array([span / 2, 0.0, 0.0]),
                box_inertia(tr["blade_mass"], span, tr["chord"], tr["blade_thickness"]))


def tail_hinge(tr) -> float:
    """The tail blade's flap hinge offset (m; zero unless the hub is flapping)."""
    return tr.get("flap_hinge_offset", 0.0) if tr["hub_type"] == "flapping" else 0.0


def tail_hub(d) -> Part:
    """The tail-rotor hub, a cube."""
    tr = d["tail_rotor"]
    return Part(tr["hub_mass"], np.zeros(3), box_inertia(tr["hub_mass"], *[tr["hub_size"]] * 3))


def seesaw(d, rotor: str = "tail_rotor") -> Part:
    """A teetering rotor's seesaw (the main rotor's yoke), a box along the blades."""
    sec = d[rotor]
    return Part(sec["seesaw_mass"], np.zeros(3), box_inertia(sec["seesaw_mass"], *sec["seesaw_size"]))


BAR_AXIAL = 1e-4
"""A stabilizer bar's inertia about its own length per its teeter inertia: a slender bar's (its
teeter frequency sqrt(1 - BAR_AXIAL) = 0.99995/rev)."""


def stabilizer_bar(d) -> Part:
    """A stabilizer bar in its frame (x along the bar, y its teeter axis), its centre of mass on the
    hinge, or None without one."""
    bar = d.get("stabilizer_bar") or {}
    if "hiller_gain" not in bar:
        return None
    return Part(bar["mass"], np.zeros(3), np.diag([BAR_AXIAL * bar["inertia"], bar["inertia"], bar["inertia"]]))


def main_rotor(d) -> Part:
    """The main rotor (hub, a teetering hub's yoke, a stabilizer bar on its hinge above the hub, and
    blades at their precone and undersling) in its hub frame, averaged over a revolution."""
    mr = d["main_rotor"]
    sense, e = geo.main_sense(d), mr["flap_hinge_offset"]
    below = np.array([0.0, 0.0, -mr.get("undersling", 0.0)]) if mr.get("hub_type") == "teetering" else np.zeros(3)
    cone = geo.precone_frame(mr.get("precone", 0.0))
    blades = [main_blade(d).placed(e * geo.rz(sense * psi)[:, 0] + below, geo.rz(sense * psi) @ cone)
              for psi in geo.blade_azimuths(mr["n_blades"])]
    yoke = [seesaw(d, "main_rotor")] if mr.get("hub_type") == "teetering" else []
    bar = stabilizer_bar(d)
    flybar = [bar.placed(np.array([0.0, 0.0, d["stabilizer_bar"]["height"]]), np.eye(3))] if bar else []
    return _averaged(combine([main_hub(d), *yoke, *flybar, *blades]))


def tail_rotor(d) -> Part:
    """The tail rotor (hub, seesaw, blades at their precone) in its hub frame, averaged over a revolution."""
    tr = d["tail_rotor"]
    sense = geo.tail_sense(d)
    parts = [tail_hub(d)] + ([seesaw(d)] if tr["hub_type"] == "teetering" else [])
    cone = geo.precone_frame(tr.get("precone", 0.0))
    frames = [geo.rz(sense * psi) for psi in geo.blade_azimuths(tr["n_blades"])]
    parts += [tail_blade(d).placed(tail_hinge(tr) * f[:, 0], f @ cone) for f in frames]
    return _averaged(combine(parts))


def _averaged(part: Part) -> Part:
    """``part`` averaged over its turns about the hub frame's z axis."""
    turns = [geo.rz(a) for a in 2 * np.pi * np.arange(AVERAGE_AZIMUTHS) / AVERAGE_AZIMUTHS]
    inertia = sum(t @ part.inertia @ t.T for t in turns) / len(turns)
    return Part(part.mass, np.array([0.0, 0.0, part.com[2]]), inertia)


def rotors(d) -> list[Part]:
    """Main and tail rotor in body axes about the CG (:func:`main_rotor`, :func:`tail_rotor` placed)."""
    tilt = d["main_rotor"]["shaft_tilt"]
    return [main_rotor(d).placed(geo.main_hub_position(d), geo.shaft_frame(tilt)),
            tail_rotor(d).placed(geo.tail_hub_position(d), geo.tail_frame(d))]


def published_inertia(d) -> np.ndarray:
    """The file's inertia tensor (3, 3), kg m²: ``[[Ixx, 0, -Ixz], [0, Iyy, 0], [-Ixz, 0, Izz]]``."""
    a = d["aircraft"]
    return np.array([[a["Ixx"], 0, -a["Ixz"]], [0, a["Iyy"], 0], [-a["Ixz"], 0, a["Izz"]]], dtype=float)


def rotor_masses(v: dict) -> tuple[float, float]:
    """Masses (kg) of the main rotor (hub, yoke, stabilizer bar, blades) and of the tail rotor (hub,
    seesaw, blades)."""
    mr, tr = v["main_rotor"], v["tail_rotor"]
    seesaw = tr.get("seesaw_mass", 0.0) if tr["hub_type"] == "teetering" else 0.0
    yoke = mr.get("seesaw_mass", 0.0) if mr.get("hub_type") == "teetering" else 0.0
    bar = stabilizer_bar(v)
    return (mr["hub_mass"] + yoke + (bar.mass if bar else 0.0) + mr["n_blades"] * mr["blade_mass"],
            tr["hub_mass"] + seesaw + tr["n_blades"] * tr["blade_mass"])


def airframe(d, transmission: float = 0.0) -> Part:
    """The airframe: the aircraft's mass less the rotors' (and a drive train's ``transmission``,
    kg, a body at the main hub), its centre of mass such that the aircraft's is the CG (the rotors'
    masses at their hubs), and its inertia about its own centre of mass: the file's (``inertia =
    "airframe"``) or the file's whole-aircraft inertia about the CG less the rotors' and the
    transmission's as a point mass (``"whole-aircraft"``)."""
    main, tail = rotor_masses(d)
    main += transmission
    mass = d["aircraft"]["mass"] - main - tail
    com = -(main * geo.main_hub_position(d) + tail * geo.tail_hub_position(d)) / mass
    if d["aircraft"].get("inertia", "airframe") == "airframe":
        return Part(mass, com, published_inertia(d))
    hub = Part(transmission, geo.main_hub_position(d), np.zeros((3, 3)))
    rest = published_inertia(d) - sum(p.about(np.zeros(3)) for p in [*rotors(d), hub])
    return Part(mass, com, rest - mass * (com @ com * np.eye(3) - np.outer(com, com)))


def whole_aircraft(d) -> Part:
    """The whole aircraft (airframe and rotors) about the CG in body axes."""
    return combine([airframe(d), *rotors(d)])
