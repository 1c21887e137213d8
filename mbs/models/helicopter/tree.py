"""The helicopter's bodies and joints (paper, Fig. 1)::

    world -6DOF-> fuselage -driven hinge-> main_hub -flap, lag, pitch-> blade1..N
                           -driven hinge-> tail_hub -teeter-> seesaw -pitch-> tail_blade1..2   (teetering)
                                                    -pitch-> tail_blade1..N                    (rigid hub)

Positive flap is tip up, positive lag is lagging (against the rotation), positive pitch is
nose up, whichever way the rotor turns (:mod:`mbs.models.helicopter.frames`). Inertias are
those of boxes and discs sized from the aircraft data.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from mbs.aircraft.blade import Distribution
from mbs.aircraft.checks import rotor_masses
from mbs.joints import DrivenHinge, Fixed, FreeJoint, Hinge, Serial
from mbs.models.elastic_blade import add_elastic_blade
from mbs.models.modal_blade import add_modal_blade
from mbs.models.helicopter import frames as fr
from mbs.models.helicopter.swashplate import blade_joint
from mbs.tree import Model

BLADE_COLORS = ["#d62728", "#1f77b4", "#2ca02c", "#ff7f0e"]


def box_inertia(mass: float, lx: float, ly: float, lz: float) -> np.ndarray:
    return mass / 12 * np.diag([ly**2 + lz**2, lx**2 + lz**2, lx**2 + ly**2])


def add_fuselage(m: Model, d, cfg) -> str:
    """The airframe (free, clamped, or none: the hub then sits on the world); its name."""
    if cfg.fuselage == "none":
        return "world"
    a = d["aircraft"]
    inertia = [[a["Ixx"], 0, -a["Ixz"]], [0, a["Iyy"], 0], [-a["Ixz"], 0, a["Izz"]]]
    joint = FreeJoint() if cfg.fuselage == "free" else Fixed()
    mass, com = fuselage_mass_and_com(d)
    m.add_body("fuselage", "world", joint, mass=mass, com=com, inertia=inertia, shape=_fuselage_shape(d))
    return "fuselage"


def fuselage_mass_and_com(d) -> tuple[float, np.ndarray]:
    """Total mass minus the rotors' parts; centre of mass so that the aircraft CG is the origin."""
    m_main, m_tail = rotor_masses(d)
    mass = d["aircraft"]["mass"] - m_main - m_tail
    com = -(m_main * fr.main_hub_position(d) + m_tail * fr.tail_hub_position(d)) / mass
    return mass, com


def _fuselage_shape(d) -> dict:
    g, ht, fin = d["geometry"], d["horizontal_tail"], d["vertical_fin"]
    boom_start = g["cabin_x"] - g["cabin"][0] / 2
    boom_len = boom_start - d["tail_rotor"]["hub_x"]
    fin_height, t = fin["area"] / fin["chord"], g["plate_thickness"]
    return {"parts": [
        {"kind": "box", "size": g["cabin"], "offset": [g["cabin_x"], 0, 0], "color": "#c8ccd2"},
        {"kind": "cylinder", "radius": g["boom_radius"], "length": boom_len, "axis": [1, 0, 0],
         "offset": [boom_start - boom_len / 2, 0, ht["z"]], "color": "#c8ccd2"},
        {"kind": "box", "size": [ht["chord"], ht["area"] / ht["chord"], t], "offset": [ht["x"], 0, ht["z"]],
         "color": "#9aa3ad"},
        {"kind": "box", "size": [fin["chord"], t, fin_height], "offset": [fin["x"], 0, fin["z"] - fin_height / 2],
         "color": "#9aa3ad"},
    ]}


def _pitch_law(psi0: float):
    def angle(t, p):
        psi = p["omega"] * t + psi0
        return p["collective"] + p["lateral_cyclic"] * ca.cos(psi) + p["longitudinal_cyclic"] * ca.sin(psi)
    return angle


def _blade_joint(d, cfg, psi0: float, sense: int):
    mr = d["main_rotor"]
    parts = [Hinge((0, -1, 0), name="flap", stiffness=mr["flap_stiffness"]),
             Hinge((0, 0, -sense), name="lag", stiffness=mr["lag_stiffness"],
                   damping=mr["lag_damping"] if cfg.dampers else 0.0)]
    if cfg.pitch_hinge:
        parts.append(DrivenHinge((sense, 0, 0), _pitch_law(psi0), name="pitch") if cfg.rotors == "driven"
                     else Hinge((sense, 0, 0), name="pitch"))
    return Serial(*parts)


def _azimuth_joint(cfg, speed_ratio: float, sense: int):
    if cfg.rotors != "driven":
        return Hinge((0, 0, 1), name="azimuth")
    return DrivenHinge((0, 0, 1), lambda t, p: sense * speed_ratio * p["omega"] * t, name="azimuth")


def blade_body(mr: dict) -> tuple:
    """Mass (kg), centre of mass and inertia (blade axes from the flap hinge) of a rigid main-rotor
    blade: integrated from the mass table (:class:`mbs.aircraft.blade.Distribution`), else the
    uniform box of the blade's mass, span, chord and thickness."""
    if mr.get("mass_table"):
        return Distribution(mr).body()
    span = mr["radius"] - mr["flap_hinge_offset"]
    return mr["blade_mass"], (span / 2, 0, 0), box_inertia(mr["blade_mass"], span, mr["chord"], mr["blade_thickness"])


def add_main_rotor(m: Model, d, cfg, parent: str) -> None:
    mr, sense = d["main_rotor"], fr.main_sense(d)
    tilt = mr["shaft_tilt"] if cfg.shaft_tilt else 0.0
    at = fr.main_hub_position(d) if parent != "world" else np.zeros(3)
    rh = mr["hub_radius"]
    m.add_body("main_hub", parent, _azimuth_joint(cfg, 1.0, sense), mass=mr["hub_mass"],
               inertia=mr["hub_mass"] / 4 * np.diag([rh**2, rh**2, 2 * rh**2]), at=at, frame=fr.shaft_frame(tilt),
               shape={"kind": "cylinder", "radius": rh, "length": d["geometry"]["hub_height"], "axis": [0, 0, 1],
                      "color": "#50565e"})
    big_r, c, t = mr["radius"], mr["chord"], mr["blade_thickness"]
    e = mr["flap_hinge_offset"]
    for k, psi0 in enumerate(fr.blade_azimuths(mr["n_blades"])[:cfg.blade_count(mr["n_blades"])]):
        frame = fr.rz(sense * psi0)
        if cfg.blade_segments or cfg.blade_modes:  # elastic, after the pitch bearing (the blade joint's last part)
            add = add_elastic_blade if cfg.blade_segments else add_modal_blade
            add(m, d, cfg, k, frame, _blade_joint(d, cfg, psi0, sense).parts[2:], sense)
            continue
        joint = blade_joint(d, cfg, k + 1, psi0, sense) if cfg.swashplate else _blade_joint(d, cfg, psi0, sense)
        mass, com, inertia = blade_body(mr)
        m.add_body(f"blade{k + 1}", "main_hub", joint, mass=mass, com=com, inertia=inertia,
                   at=e * frame[:, 0], frame=frame,
                   shape={"kind": "box", "size": [big_r - e, c, t], "offset": [(big_r - e) / 2, 0, 0],
                          "color": BLADE_COLORS[k % 4]})


def add_tail_rotor(m: Model, d, cfg, parent: str) -> None:
    tr, sense = d["tail_rotor"], fr.tail_sense(d)
    radius, length = d["geometry"]["tail_hub"]
    m.add_body("tail_hub", parent, _azimuth_joint(cfg, tr["gear_ratio"], sense), mass=tr["hub_mass"],
               inertia=box_inertia(tr["hub_mass"], *[tr["hub_size"]] * 3), at=fr.tail_hub_position(d),
               frame=fr.tail_frame(d),
               shape={"kind": "cylinder", "radius": radius, "length": length, "axis": [0, 0, 1], "color": "#50565e"})
    blades_on = "tail_hub"
    if tr["hub_type"] == "teetering":
        m.add_body("seesaw", "tail_hub", Hinge((0, -1, 0), name="teeter", stiffness=tr["teeter_stiffness"]),
                   mass=tr["seesaw_mass"], inertia=box_inertia(tr["seesaw_mass"], *tr["seesaw_size"]),
                   shape={"kind": "box", "size": tr["seesaw_size"], "color": "#50565e"})
        blades_on = "seesaw"
    big_r, c, t = tr["radius"], tr["chord"], tr["blade_thickness"]
    for k, psi0 in enumerate(fr.blade_azimuths(tr["n_blades"])):
        pitch = (DrivenHinge((sense, 0, 0), lambda t, p: p["tail_collective"], name="pitch")
                 if cfg.rotors == "driven" else Hinge((sense, 0, 0), name="pitch"))
        m.add_body(f"tail_blade{k + 1}", blades_on, pitch, mass=tr["blade_mass"], com=(big_r / 2, 0, 0),
                   inertia=box_inertia(tr["blade_mass"], big_r, c, t), frame=fr.rz(sense * psi0),
                   shape={"kind": "box", "size": [big_r, c, t], "offset": [big_r / 2, 0, 0], "color": "#7f7f7f"})
