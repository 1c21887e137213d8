"""The Bo105 helicopter as an open-loop tree, and its scenes.

Tree (paper, Fig. 1)::

    world -6DOF-> fuselage -driven hinge-> main_hub -flap, lag, pitch-> blade1..4
                           -driven hinge-> tail_hub -teeter-> seesaw -pitch-> tail_blade1..2

Frames: fuselage body axes at the total centre of gravity (x forward, y starboard, z down);
world x north, y east, z down. The main-rotor hub frame has z along the shaft (up, tilted
forward) and x aft at zero azimuth; the rotor turns counter-clockwise seen from above and
the azimuth ψ is measured from the tail. Blade frames: x along the span, y towards the
leading edge, z the lift direction at zero pitch. Positive flap is tip up, positive lag is
lagging (against the rotation), positive pitch is nose up. The tail-rotor hub frame has z
along the thrust (starboard) and the upper blade moves aft.

All numbers come from ``bo105.toml`` (values with units and sources); this module only
assembles them. A :class:`Config` says which bodies and forces a scene needs.
"""
from __future__ import annotations

import sys
from dataclasses import dataclass, replace
from pathlib import Path

import casadi as ca
import numpy as np

from mbs import _rotation as rot
from mbs.aero import (Airfoil, Compressibility, Download, FuselageAero, HubDrag, LiftingSurface, Rotor,
                      RotorAero, RotorModel, WakeGeometry, momentum_inflow)
from mbs.joints import DrivenHinge, Fixed, FreeJoint, Hinge, Serial
from mbs.loads.rotorcraft import add_load_outputs
from mbs.models.elastic_blade import add_elastic_blade, rotor_pieces
from mbs.scenes import Scene, register
from mbs.tree import Model

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

DATA_FILE = Path(__file__).with_name("bo105.toml")
TRIM_FILE = Path(__file__).with_name("bo105_trim.toml")


class Data(dict):
    """``data["main_rotor"]["radius"]`` -> value; ``data.meta[...]`` -> unit, source, note."""

    meta: dict


def load_data(path: Path = DATA_FILE) -> Data:
    """Read the parameter file: every entry is ``{value, unit, source, note}``."""
    raw = tomllib.loads(Path(path).read_text())
    data = Data({sec: {k: e["value"] for k, e in entries.items()} for sec, entries in raw.items()})
    data.meta = {sec: {k: {f: e.get(f, "") for f in ("unit", "source", "note")} for k, e in entries.items()}
                 for sec, entries in raw.items()}
    return data


# -- scene configuration -----------------------------------------------------------------

@dataclass(frozen=True)
class Config:
    """What a scene builds.

    fuselage: "free" (6 DOF), "clamped" (fixed to the world) or "none" (hub on the world).
    rotors: "driven" (hubs at constant speed, swashplate pitch) or "free" (every driven joint
    replaced by a free hinge; speeds from the initial condition). blades: main-rotor blades
    built. speed: initial forward speed, m/s.

    Rotor aerodynamics switches (README, "Simplifications"): inflow "uniform" (one state per
    rotor) or "pitt-peters" (three states on the main rotor); tip_loss (effective blade radius
    B R on both rotors); compressibility (Prandtl-Glauert lift slope and drag divergence on
    both rotors); tail_wake (the main rotor's wake on the horizontal tail and fin); download
    (the wake's vertical drag on the fuselage); hub_drag (drag of the main-rotor hub). All off:
    the model of the paper's scenes. blade_segments: main-rotor blades as elastic chains of
    that many segments (:mod:`mbs.models.elastic_blade`); 0: rigid blades.
    """

    fuselage: str = "free"
    rotors: str = "driven"
    blades: int = 4
    tail_rotor: bool = True
    rotor_aero: bool = True
    airframe_aero: bool = True
    dampers: bool = True
    shaft_tilt: bool = True
    pitch_hinge: bool = True
    speed: float = 10.0
    elements: int | None = None
    trim: str | None = None  # key of the stored trim (bo105_trim.toml) giving defaults
    inflow: str = "uniform"
    tip_loss: bool = False
    compressibility: bool = False
    tail_wake: bool = False
    download: bool = False
    hub_drag: bool = False
    blade_segments: int = 0

    def __post_init__(self):
        needs_rotor = [n for n in ("tail_wake", "download", "tip_loss", "compressibility") if getattr(self, n)]
        needs_rotor += ["inflow"] if self.inflow != "uniform" else []
        if needs_rotor and not self.rotor_aero:
            raise ValueError(f"{needs_rotor[0]} needs the main rotor's aerodynamics, which this scene does not model")
        needs_airframe = [n for n in ("tail_wake", "download", "hub_drag") if getattr(self, n)]
        if needs_airframe and not (self.airframe_aero and self.fuselage == "free"):
            raise ValueError(f"{needs_airframe[0]} acts on the airframe's aerodynamics, which this scene does not model")


# -- trim estimate -------------------------------------------------------------------------

@dataclass
class TrimEstimate:
    """Controls and attitudes for steady level flight from momentum and blade-element theory.

    Angles in rad: collective (at the root, r = 0), cyclics (Padfield: θ1s > 0 tilts the disc
    back, θ1c > 0 left), tail collective, fuselage pitch and roll, coning, flapping relative to
    the shaft; inflow velocities in m/s.
    """

    speed: float
    collective: float
    lateral_cyclic: float
    longitudinal_cyclic: float
    tail_collective: float
    pitch: float
    roll: float
    coning: float
    a1s: float
    inflow_main: float
    inflow_tail: float
    tail_thrust: float


def estimate_trim(d: Data, speed: float) -> TrimEstimate:
    """Classical closed-form estimates (uniform inflow, linear twist, small angles)."""
    mr, tr, env = d["main_rotor"], d["tail_rotor"], d["environment"]
    weight = d["aircraft"]["mass"] * env["g"]
    rho, big_r, omega = env["rho"], mr["radius"], mr["omega"]
    tip, area = omega * big_r, np.pi * big_r**2
    sigma = mr["n_blades"] * mr["chord"] / (np.pi * big_r)
    drag = -d["fuselage_aero"]["X"][0] * (speed / d["fuselage_aero"]["v_ref"]) ** 2
    drag += 0.5 * rho * d["hub_drag"]["flat_plate_area"] * speed**2
    tilt = drag / weight
    ct, mu = weight / (rho * area * tip**2), speed / tip
    lam_i = momentum_inflow(weight, rho, big_r, speed, speed * tilt) / tip
    lam = mu * tilt + mr["kappa"] * lam_i
    theta0 = (2 * ct / (sigma * mr["lift_slope"]) - mr["twist"] / 4 * (1 + mu**2) + lam / 2) / (1 / 3 + mu**2 / 2)
    lock = rho * mr["lift_slope"] * mr["chord"] * big_r**4 / mr["I_flap"]
    nu2 = 1 + mr["flap_stiffness"] / (mr["I_flap"] * omega**2)
    coning = lock / (8 * nu2) * (theta0 * (1 + mu**2) + 0.8 * mr["twist"] * (1 + 5 / 6 * mu**2) - 4 / 3 * lam)
    blowback = 2 * mu * (4 / 3 * theta0 + mr["twist"] - lam) / (1 - mu**2 / 2)
    hub_moment_tilt = weight * -mr["hub_x"] / (mr["n_blades"] / 2 * mr["flap_stiffness"] - weight * mr["hub_z"])
    cl_mean = 6 * ct / sigma
    delta = mr["cd0"] + mr["cd2"] * (cl_mean / mr["lift_slope"]) ** 2
    torque = rho * area * tip**2 * big_r * (ct * lam + sigma * delta / 8 * (1 + 3 * mu**2))
    t_thrust = torque / (mr["hub_x"] - tr["hub_x"])
    theta_t, v_tail = _tail_collective(d, t_thrust, speed)
    return TrimEstimate(speed, theta0, 0.0, hub_moment_tilt - blowback, theta_t,
                        mr["shaft_tilt"] - (tilt + hub_moment_tilt), -t_thrust / weight, coning,
                        hub_moment_tilt, lam_i * tip, v_tail, t_thrust)


def _tail_collective(d: Data, thrust: float, speed: float) -> tuple[float, float]:
    tr, rho = d["tail_rotor"], d["environment"]["rho"]
    omega_t = tr["gear_ratio"] * d["main_rotor"]["omega"]
    tip = omega_t * tr["radius"]
    sigma = tr["n_blades"] * tr["chord"] / (np.pi * tr["radius"])
    ct, mu = thrust / (rho * np.pi * tr["radius"] ** 2 * tip**2), speed / tip
    v = momentum_inflow(thrust, rho, tr["radius"], speed)
    theta = (2 * ct / (sigma * tr["lift_slope"]) + tr["kappa"] * v / tip / 2) / (1 / 3 + mu**2 / 2)
    return theta, v


def stored_trim(key: str | None, speed: float) -> dict | None:
    """The trim stored under ``key`` in ``bo105_trim.toml`` if it is for ``speed`` (m/s)."""
    if not key or not TRIM_FILE.exists():
        return None
    entry = tomllib.loads(TRIM_FILE.read_text()).get(key)
    return entry if entry and abs(entry["speed"] - speed) < 1e-6 else None


# -- the tree ------------------------------------------------------------------------------

def _box_inertia(mass: float, lx: float, ly: float, lz: float) -> np.ndarray:
    return mass / 12 * np.diag([ly**2 + lz**2, lx**2 + lz**2, lx**2 + ly**2])


def _rz(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def shaft_frame(tilt: float) -> np.ndarray:
    """Main-rotor hub frame in body axes: columns x (aft), y (starboard), z (shaft, up)."""
    return np.array([[-np.cos(tilt), 0, np.sin(tilt)], [0, 1.0, 0], [-np.sin(tilt), 0, -np.cos(tilt)]])


TAIL_FRAME = np.array([[0, -1.0, 0], [0, 0, 1.0], [-1.0, 0, 0]])  # columns x up, y aft, z starboard


def main_hub_position(d: Data) -> np.ndarray:
    return np.array([d["main_rotor"]["hub_x"], 0.0, d["main_rotor"]["hub_z"]])


def tail_hub_position(d: Data) -> np.ndarray:
    tr = d["tail_rotor"]
    return np.array([tr["hub_x"], tr["hub_y"], tr["hub_z"]])


def _add_fuselage(m: Model, d: Data, cfg: Config) -> str:
    if cfg.fuselage == "none":
        return "world"
    a = d["aircraft"]
    inertia = [[a["Ixx"], 0, -a["Ixz"]], [0, a["Iyy"], 0], [-a["Ixz"], 0, a["Izz"]]]
    joint = FreeJoint() if cfg.fuselage == "free" else Fixed()
    mass, com = _fuselage_mass_and_com(d, cfg)
    m.add_body("fuselage", "world", joint, mass=mass, com=com, inertia=inertia, shape=_fuselage_shape(d))
    return "fuselage"


def _fuselage_mass_and_com(d: Data, cfg: Config) -> tuple[float, np.ndarray]:
    """Total mass minus the rotors' parts; centre of mass so that the aircraft CG is the origin."""
    mr, tr = d["main_rotor"], d["tail_rotor"]
    m_main = mr["hub_mass"] + mr["n_blades"] * mr["blade_mass"]
    m_tail = tr["hub_mass"] + tr["seesaw_mass"] + tr["n_blades"] * tr["blade_mass"]
    mass = d["aircraft"]["mass"] - m_main - m_tail
    com = -(m_main * main_hub_position(d) + m_tail * tail_hub_position(d)) / mass
    return mass, com


def _fuselage_shape(d: Data) -> dict:
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


def _blade_joint(d: Data, cfg: Config, psi0: float):
    mr = d["main_rotor"]
    parts = [Hinge((0, -1, 0), name="flap", stiffness=mr["flap_stiffness"]),
             Hinge((0, 0, -1), name="lag", stiffness=mr["lag_stiffness"],
                   damping=mr["lag_damping"] if cfg.dampers else 0.0)]
    if cfg.pitch_hinge:
        parts.append(DrivenHinge((1, 0, 0), _pitch_law(psi0), name="pitch") if cfg.rotors == "driven"
                     else Hinge((1, 0, 0), name="pitch"))
    return Serial(*parts)


def _add_main_rotor(m: Model, d: Data, cfg: Config, parent: str) -> None:
    mr = d["main_rotor"]
    tilt = mr["shaft_tilt"] if cfg.shaft_tilt else 0.0
    at = main_hub_position(d) if parent != "world" else np.zeros(3)
    joint = (DrivenHinge((0, 0, 1), lambda t, p: p["omega"] * t, name="azimuth") if cfg.rotors == "driven"
             else Hinge((0, 0, 1), name="azimuth"))
    rh = mr["hub_radius"]
    m.add_body("main_hub", parent, joint, mass=mr["hub_mass"], inertia=mr["hub_mass"] / 4 * np.diag([rh**2, rh**2, 2 * rh**2]),
               at=at, frame=shaft_frame(tilt), shape={"kind": "cylinder", "radius": rh, "length": d["geometry"]["hub_height"],
                                                      "axis": [0, 0, 1], "color": "#50565e"})
    big_r, c, t = mr["radius"], mr["chord"], mr["blade_thickness"]
    e = mr["flap_hinge_offset"]
    for k in range(cfg.blades):
        psi0 = 2 * np.pi * k / mr["n_blades"]
        if cfg.blade_segments:  # elastic, after the pitch bearing (the rigid blade joint's last part)
            add_elastic_blade(m, d, cfg, k, _rz(psi0), _blade_joint(d, cfg, psi0).parts[2:])
            continue
        m.add_body(f"blade{k + 1}", "main_hub", _blade_joint(d, cfg, psi0), mass=mr["blade_mass"],
                   com=((big_r - e) / 2, 0, 0), inertia=_box_inertia(mr["blade_mass"], big_r - e, c, t),
                   at=e * _rz(psi0)[:, 0], frame=_rz(psi0),
                   shape={"kind": "box", "size": [big_r - e, c, t], "offset": [(big_r - e) / 2, 0, 0],
                          "color": ["#d62728", "#1f77b4", "#2ca02c", "#ff7f0e"][k % 4]})


def _add_tail_rotor(m: Model, d: Data, cfg: Config, parent: str) -> None:
    tr = d["tail_rotor"]
    driven = cfg.rotors == "driven"
    joint = (DrivenHinge((0, 0, 1), lambda t, p: tr["gear_ratio"] * p["omega"] * t, name="azimuth") if driven
             else Hinge((0, 0, 1), name="azimuth"))
    radius, length = d["geometry"]["tail_hub"]
    m.add_body("tail_hub", parent, joint, mass=tr["hub_mass"], inertia=_box_inertia(tr["hub_mass"], *[tr["hub_size"]] * 3),
               at=tail_hub_position(d), frame=TAIL_FRAME,
               shape={"kind": "cylinder", "radius": radius, "length": length, "axis": [0, 0, 1], "color": "#50565e"})
    m.add_body("seesaw", "tail_hub", Hinge((0, -1, 0), name="teeter", stiffness=tr["teeter_stiffness"]),
               mass=tr["seesaw_mass"], inertia=_box_inertia(tr["seesaw_mass"], *tr["seesaw_size"]),
               shape={"kind": "box", "size": tr["seesaw_size"], "color": "#50565e"})
    big_r, c, t = tr["radius"], tr["chord"], tr["blade_thickness"]
    for k in range(int(tr["n_blades"])):
        pitch = (DrivenHinge((1, 0, 0), lambda t, p: p["tail_collective"], name="pitch") if driven
                 else Hinge((1, 0, 0), name="pitch"))
        m.add_body(f"tail_blade{k + 1}", "seesaw", pitch, mass=tr["blade_mass"], com=(big_r / 2, 0, 0),
                   inertia=_box_inertia(tr["blade_mass"], big_r, c, t), frame=_rz(np.pi * k),
                   shape={"kind": "box", "size": [big_r, c, t], "offset": [big_r / 2, 0, 0], "color": "#7f7f7f"})


def rotor_model(d: Data, cfg: Config, section: str) -> RotorModel:
    """The switches of ``cfg`` with their data for the rotor ``section`` ("main_rotor" or
    "tail_rotor"; Pitt-Peters inflow on the main rotor only)."""
    sec = d[section]
    comp = Compressibility(d["environment"]["speed_of_sound"], sec["mach_dd"], sec["mach_limit"])
    wake = main_rotor_wake(d)
    return RotorModel(inflow=cfg.inflow if section == "main_rotor" else "uniform",
                      tip_loss=sec["tip_loss"] if cfg.tip_loss else 1.0,
                      compressibility=comp if cfg.compressibility else None,
                      wake=wake if section == "main_rotor" and (cfg.tail_wake or cfg.download) else None)


def main_rotor_wake(d: Data) -> WakeGeometry:
    """The main rotor's wake geometry: Landgrebe's coefficients at the hover thrust coefficient."""
    mr, w = d["main_rotor"], d["wake"]
    tip = mr["omega"] * mr["radius"]
    ct = d["aircraft"]["mass"] * d["environment"]["g"] / (d["environment"]["rho"] * np.pi * mr["radius"] ** 2 * tip**2)
    sigma = mr["n_blades"] * mr["chord"] / (np.pi * mr["radius"])
    return WakeGeometry.landgrebe(w["width"], w["core"] * mr["radius"], ct, sigma, np.degrees(mr["twist"]),
                                  mr["n_blades"])


INFLOW_TEXT = {"": "uniform induced velocity", "_1s": "induced velocity, sine (lateral) component at the tip",
               "_1c": "induced velocity, cosine (longitudinal) component at the tip"}


def _add_inflow_states(m: Model, name: str, model: RotorModel, v0: float) -> None:
    what = name.replace("_", "-")
    for state in model.inflow_states(name):
        suffix = state[len(name) + len(".inflow"):]
        m.add_state(state, v0 if not suffix else 0.0, "m/s", f"{what} {INFLOW_TEXT[suffix]}")


def _add_rotor_aero(m: Model, d: Data, cfg: Config, trim: TrimEstimate, parent: str) -> None:
    rho = d["environment"]["rho"]
    mr, tr = d["main_rotor"], d["tail_rotor"]
    tilt = mr["shaft_tilt"] if cfg.shaft_tilt else 0.0
    shaft_body = None if parent == "world" else parent
    main = Rotor("main_rotor", "main_hub", [f"blade{k + 1}" for k in range(cfg.blades)], mr["radius"], mr["chord"],
                 mr["twist"], mr["root_cutout"], int(cfg.elements or mr["elements"]), mr["flap_hinge_offset"],
                 shaft_body, shaft_frame(tilt), pieces=rotor_pieces(d, cfg))
    main_model = rotor_model(d, cfg, "main_rotor")
    _add_inflow_states(m, "main_rotor", main_model, trim.inflow_main)
    m.add_force(RotorAero(main, _airfoil(mr), rho, mr["kappa"], main_model))
    if cfg.tail_rotor:
        tail = Rotor("tail_rotor", "tail_hub", [f"tail_blade{k + 1}" for k in range(int(tr["n_blades"]))],
                     tr["radius"], tr["chord"], tr["twist"], tr["root_cutout"], int(tr["elements"]), 0.0,
                     shaft_body, TAIL_FRAME, tr["gear_ratio"])
        tail_model = rotor_model(d, cfg, "tail_rotor")
        _add_inflow_states(m, "tail_rotor", tail_model, trim.inflow_tail)
        m.add_force(RotorAero(tail, _airfoil(tr), rho, tr["kappa"], tail_model))


def _airfoil(sec: dict) -> Airfoil:
    return Airfoil(sec["lift_slope"], sec["cd0"], sec.get("cd2", 0.0), sec["alpha_stall"],
                   sec.get("cd_stalled", Airfoil.cd_stalled))


def _add_airframe_aero(m: Model, d: Data, cfg: Config) -> None:
    fa, ht, fin, rho = d["fuselage_aero"], d["horizontal_tail"], d["vertical_fin"], d["environment"]["rho"]
    wake = "main_rotor" if cfg.tail_wake else None
    m.add_force(FuselageAero("fuselage", {k: fa[k] for k in "XYZMN"}, fa["v_ref"], fa["angle_limit"]))
    m.add_force(LiftingSurface("horizontal tail", "fuselage", (ht["x"], 0, ht["z"]), (1, 0, 0), (0, 0, -1),
                               ht["incidence"], ht["area"], _airfoil(ht), rho, wake))
    m.add_force(LiftingSurface("fin", "fuselage", (fin["x"], 0, fin["z"]), (1, 0, 0), (0, 1, 0),
                               fin["incidence"], fin["area"], _airfoil(fin), rho, wake))
    if cfg.download:
        m.add_force(Download("fuselage", "main_rotor", d["download"]["panels"], rho))
    if cfg.hub_drag:
        m.add_force(HubDrag("fuselage", main_hub_position(d), d["hub_drag"]["flat_plate_area"], rho))


def _add_parameters(m: Model, d: Data, cfg: Config, trim: TrimEstimate, stored: dict | None) -> None:
    mr, tr = d["main_rotor"], d["tail_rotor"]
    if stored:
        trim = replace(trim, **{k: stored[k] for k in ("collective", "lateral_cyclic", "longitudinal_cyclic",
                                                      "tail_collective") if k in stored})
    m.add_parameter("omega", mr["omega"], "rad/s", "main-rotor speed (tail rotor turns gear_ratio times faster)",
                    low=mr["omega_min"], high=mr["omega_max"])
    if not cfg.pitch_hinge:
        return
    for name, value, what in (("collective", trim.collective, "main-rotor collective pitch at the blade root"),
                              ("lateral_cyclic", trim.lateral_cyclic, "main-rotor lateral cyclic θ1c"),
                              ("longitudinal_cyclic", trim.longitudinal_cyclic, "main-rotor longitudinal cyclic θ1s")):
        low, high = mr[f"{name}_min"], mr[f"{name}_max"]  # the estimate beyond the controls' reach: clipped
        m.add_parameter(name, float(np.clip(value, low, high)), "rad", what, control=True, low=low, high=high)
    if cfg.tail_rotor:
        low, high = tr["collective_min"], tr["collective_max"]
        m.add_parameter("tail_collective", float(np.clip(trim.tail_collective, low, high)), "rad",
                        "tail-rotor collective pitch", control=True, low=low, high=high)


def _add_outputs(m: Model, d: Data, cfg: Config) -> None:
    gear = d["tail_rotor"]["gear_ratio"]
    if cfg.rotors == "driven":
        m.add_output("main_rotor.azimuth", lambda s: s.p["omega"] * s.t, "rad", "azimuth of blade 1 from the tail")
        if cfg.tail_rotor:
            m.add_output("tail_rotor.azimuth", lambda s: gear * s.p["omega"] * s.t, "rad", "azimuth of tail blade 1")
    else:
        m.add_output("main_rotor.azimuth", lambda s: s.q("main_hub.azimuth"), "rad", "azimuth of blade 1 from the tail")
        if cfg.tail_rotor:
            m.add_output("tail_rotor.azimuth", lambda s: s.q("tail_hub.azimuth"), "rad", "azimuth of tail blade 1")
    if cfg.rotor_aero:
        _add_rotor_outputs(m, d, cfg, "main_rotor", 1.0)
        if cfg.tail_rotor:
            _add_rotor_outputs(m, d, cfg, "tail_rotor", gear)
    _add_airframe_outputs(m, cfg)


def _add_airframe_outputs(m: Model, cfg: Config) -> None:
    """The main rotor's wake at the tail surfaces and the fuselage download, when modelled."""
    if cfg.tail_wake:
        m.add_output("horizontal_tail.downwash", lambda s: s.signals["horizontal tail.wake"][2], "m/s",
                     "main-rotor wake velocity at the horizontal tail along body z (positive down)")
        m.add_output("fin.sidewash", lambda s: s.signals["fin.wake"][1], "m/s",
                     "main-rotor wake velocity at the fin along body y (positive to starboard)")
    if cfg.download:
        m.add_output("fuselage.download", lambda s: s.signals["fuselage.download"], "N",
                     "vertical drag of the fuselage in the main-rotor wake (positive down)")


ROTOR_OUTPUTS = (("thrust", "N", "thrust along the shaft"),
                 ("torque", "N m", "aerodynamic shaft torque (the drive's torque on the rotor)"),
                 ("power", "W", "aerodynamic shaft power, torque times rotor speed"))


def _add_rotor_outputs(m: Model, d: Data, cfg: Config, name: str, speed_ratio: float) -> None:
    """Thrust, torque, power (signals of the rotor's aerodynamics) and its inflow ratios
    ``λ = v / (Ω R)`` (the inflow states made dimensionless)."""
    what, tip = name.replace("_", "-"), speed_ratio * d[name]["radius"]
    for key, unit, text in ROTOR_OUTPUTS:
        m.add_output(f"{name}.{key}", lambda s, k=f"{name}.{key}": s.signals[k], unit, f"{what} {text}")
    for state in rotor_model(d, cfg, name).inflow_states(name) if "omega" in m.parameters else ():
        suffix = state[len(name) + len(".inflow"):]
        m.add_output(f"{name}.inflow_ratio{suffix}", lambda s, z=state: s.z(z) / (tip * s.p["omega"]), "1",
                     f"{what} inflow ratio: {INFLOW_TEXT[suffix]} per tip speed")


def _set_initial(m: Model, d: Data, cfg: Config, trim: TrimEstimate, stored: dict | None) -> None:
    """Trimmed attitude and inflow when stored; blades start at the estimated coning and
    flapping with zero lag, so the lag transient of the paper's Fig. 2 shows."""
    mr, omega = d["main_rotor"], d["main_rotor"]["omega"]
    if stored:
        trim = replace(trim, roll=stored["roll"], pitch=stored["pitch"])
        m.set_initial(**{k: stored[k] for k in m.states if k in stored})
    if cfg.fuselage == "free":
        q = rot.euler_to_quat(trim.roll, trim.pitch, 0.0)
        r = np.array(ca.DM(rot.quat_to_matrix(ca.DM(q))))
        u, v, w = r.T @ np.array([cfg.speed, 0.0, 0.0])
        m.set_initial(**{"fuselage.qw": q[0], "fuselage.qx": q[1], "fuselage.qy": q[2], "fuselage.qz": q[3],
                         "fuselage.u": u, "fuselage.v": v, "fuselage.w": w})
    for k in range(cfg.blades):
        psi = 2 * np.pi * k / mr["n_blades"]
        m.set_initial(**{f"blade{k + 1}.flap": trim.coning - trim.a1s * np.cos(psi),
                         f"blade{k + 1}.flap_rate": trim.a1s * omega * np.sin(psi)})
        if cfg.rotors == "free" and cfg.pitch_hinge:
            m.set_initial(**{f"blade{k + 1}.pitch": trim.collective})
    if cfg.rotors == "free":
        m.set_initial(**{"main_hub.azimuth_rate": omega})
        if cfg.tail_rotor:
            m.set_initial(**{"tail_hub.azimuth_rate": d["tail_rotor"]["gear_ratio"] * omega})


def build(cfg: Config = Config(), data: Data | None = None, name: str = "bo105") -> Model:
    """The Bo105 model with exactly the bodies and forces ``cfg`` asks for."""
    d = data or load_data()
    trim, stored = estimate_trim(d, cfg.speed), stored_trim(cfg.trim, cfg.speed)
    m = Model(name, gravity=(0.0, 0.0, d["environment"]["g"]))
    parent = _add_fuselage(m, d, cfg)
    _add_main_rotor(m, d, cfg, parent)
    if cfg.tail_rotor:
        _add_tail_rotor(m, d, cfg, parent)
    if cfg.rotor_aero:
        _add_rotor_aero(m, d, cfg, trim, parent)
    if cfg.airframe_aero and cfg.fuselage == "free":
        _add_airframe_aero(m, d, cfg)
    if cfg.rotors == "driven":
        _add_parameters(m, d, cfg, trim, stored)
    _add_outputs(m, d, cfg)
    add_load_outputs(m, d, cfg)
    _set_initial(m, d, cfg, trim, stored)
    return m


# -- scenes --------------------------------------------------------------------------------

AERO_SWITCHES = {"pitt-peters": ("inflow", "pitt-peters", "uniform"), "tip-loss": ("tip_loss", True, False),
                 "compressibility": ("compressibility", True, False), "tail-wake": ("tail_wake", True, False),
                 "download": ("download", True, False), "hub-drag": ("hub_drag", True, False)}
"""Aerodynamics switches: name -> (Config field, value when on, value when off)."""

FULL = {field: on for field, on, _ in AERO_SWITCHES.values()}
NONE = {field: off for field, _, off in AERO_SWITCHES.values()}


def applicable_switches(cfg: Config) -> list[str]:
    """The switches that apply to a scene configured by ``cfg`` (its rotors and airframe)."""
    def applies(name: str) -> bool:
        field, on, _ = AERO_SWITCHES[name]
        try:
            replace(cfg, **{**NONE, field: on})
        except ValueError:
            return False
        return True
    return [n for n in AERO_SWITCHES if applies(n)]


def aero_switches(scene: Scene) -> list[str]:
    """The aerodynamics switches that are on in ``scene``."""
    cfg = replace(_config(scene), **{k: v for k, v in scene.options.items() if k in NONE})
    return [n for n, (field, on, _) in AERO_SWITCHES.items() if getattr(cfg, field) == on]


def with_aero(scene: Scene, switches: str) -> Scene:
    """``scene`` with exactly the aerodynamics switches named in ``switches`` on: comma-separated
    names of :data:`AERO_SWITCHES`, "full" (every switch that applies to the scene) or "none"
    (the paper's model: uniform inflow, no tip loss, compressibility, wake on the airframe,
    download or hub drag)."""
    ok = applicable_switches(_config(scene))
    if not ok:
        raise ValueError(f"scene {scene.name!r} models no rotor or airframe aerodynamics: no switch applies")
    words = [n.strip() for n in switches.split(",") if n.strip()]
    names = ok if words == ["full"] else [] if words == ["none"] else words
    for n in names:
        if n not in AERO_SWITCHES:
            raise ValueError(f"unknown aerodynamics switch {n!r}; known: {', '.join(AERO_SWITCHES)}, full, none")
        if n not in ok:
            raise ValueError(f"aerodynamics switch {n!r} does not apply to scene {scene.name!r}, which models "
                             f"{'only ' + ', '.join(ok) if ok else 'no rotor or airframe aerodynamics'}")
    options = {**NONE, **{AERO_SWITCHES[n][0]: AERO_SWITCHES[n][1] for n in names}}
    return replace(scene, options={**scene.options, **options})


def _config(scene: Scene) -> Config:
    cfg = getattr(scene.builder, "config", None)
    if cfg is None:
        raise ValueError(f"scene {scene.name!r} is not a Bo105 scene: it has no aerodynamics switches")
    return cfg


def _builder(cfg: Config, name: str):
    def make(**options) -> Model:
        return build(replace(cfg, **options), name=f"bo105-{name}")
    make.config = cfg
    return make


def _plots(cfg: Config) -> dict:
    panels = {"main-rotor flap (rad)": [f"blade{k + 1}.flap" for k in range(cfg.blades)],
              "main-rotor lag (rad)": [f"blade{k + 1}.lag" for k in range(cfg.blades)]}
    if cfg.tail_rotor:
        panels["tail-rotor seesaw (rad)"] = ["seesaw.teeter"]
    return panels


SCENE_CONFIGS = {
    "structural": (Config(rotors="free", rotor_aero=False, airframe_aero=False, dampers=False),
                   "the paper's conservative case: free fuselage, free hubs spinning from the initial "
                   "condition, free pitch hinges, no aerodynamics, no dampers", True),
    "forward-flight": (Config(speed=10.0, trim="forward-flight", **FULL),
                       "the paper's aeromechanic case: free flight at 10 m/s with blade-element rotors (Pitt-Peters "
                       "inflow, tip loss, compressibility), lag dampers, fuselage, hub and empennage loads in the rotor's "
                       "wake, trimmed controls and attitude", False),
    "hover": (Config(speed=0.0, trim="hover", **FULL), "as forward-flight, at zero speed", False),
    "ground-run": (Config(fuselage="clamped", airframe_aero=False, speed=0.0, trim="hover",
                          **{k: v for k, v in FULL.items() if k not in ("tail_wake", "download", "hub_drag")}),
                   "fuselage clamped to the ground, both rotors with aerodynamics (Pitt-Peters inflow, tip loss, "
                   "compressibility) and dampers, hover controls", False),
    "single-blade": (Config(fuselage="none", blades=1, tail_rotor=False, rotor_aero=False, airframe_aero=False,
                            dampers=False, shaft_tilt=False, pitch_hinge=False),
                     "hub clamped and driven (vertical shaft), one blade on flap and lag hinges with springs, "
                     "no aerodynamics: for frequency checks", False),
    "single-blade-aero": (Config(fuselage="none", blades=1, tail_rotor=False, airframe_aero=False, dampers=False,
                                 shaft_tilt=False, speed=0.0),
                          "hub clamped and driven (vertical shaft), one blade on flap, lag and driven pitch "
                          "hinges with blade-element aerodynamics and uniform dynamic inflow, in hover: for the "
                          "Lock-number check of the flap mode", False),
}

for _name, (_cfg, _text, _conservative) in SCENE_CONFIGS.items():
    register(Scene(_name, _text, _builder(_cfg, _name), omega=load_data()["main_rotor"]["omega"],
                   conservative=_conservative, plots=_plots(_cfg)))

ELASTIC_ROTOR = Config(fuselage="none", tail_rotor=False, airframe_aero=False, shaft_tilt=False, speed=0.0,
                       trim="hover", blade_segments=8)
register(Scene("elastic-rotor", "hub clamped and driven (vertical shaft), four elastic blades of 8 segments on flap, "
               "lag and torsion hinges with springs (first frequencies 1.117, 0.68 and 3.7/rev), blade-element "
               "aerodynamics with uniform dynamic inflow, hover controls; RK4 at 200 steps per revolution",
               _builder(ELASTIC_ROTOR, "elastic-rotor"), omega=load_data()["main_rotor"]["omega"], steps_per_rev=200,
               plots=_plots(ELASTIC_ROTOR)))
