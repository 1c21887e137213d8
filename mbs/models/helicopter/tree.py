"""The helicopter's bodies and joints (paper, Fig. 1)::

    world -6DOF-> fuselage -driven hinge-> main_hub -flap, lag, pitch-> blade1..N
                           -driven hinge-> tail_hub -teeter-> seesaw -pitch-> tail_blade1..2   (teetering)
                                                    -pitch-> tail_blade1..N                    (rigid hub)
                                                    -flap, pitch-> tail_blade1..N              (flapping hub)

The tail hub's frame carries the shaft's cant and toe; the teeter and tail flap hinges are
skewed by δ3 (:func:`mbs.models.helicopter.frames.delta3_axis`).

Positive flap is tip up, positive lag is lagging (against the rotation), positive pitch is
nose up, whichever way the rotor turns (:mod:`mbs.models.helicopter.frames`). Inertias are
those of boxes and discs sized from the aircraft data.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from mbs.aircraft import mass as mass_props
from mbs.aircraft.airframe_data import has_horizontal_tail
from mbs.aircraft.mass import box_inertia  # noqa: F401 (re-exported)
from mbs.drivetrain.train import transmission_mass
from mbs.joints import DrivenHinge, Fixed, FreeJoint, Hinge, Serial
from mbs.models.elastic_blade import add_elastic_blade
from mbs.models.modal_blade import add_modal_blade
from mbs.models.helicopter import frames as fr
from mbs.models.helicopter.hinges import main_flap_hinge
from mbs.models.helicopter.lag_damper import add_lag_damper, has_damper
from mbs.models.helicopter.stabilizer_bar import add_stabilizer_bar, has_stabilizer_bar
from mbs.models.helicopter.swashplate import blade_joint
from mbs.tree import Model

BLADE_COLORS = ["#d62728", "#1f77b4", "#2ca02c", "#ff7f0e"]


def add_fuselage(m: Model, d, cfg) -> str:
    """The airframe (free, clamped, or none: the hub then sits on the world); its name."""
    if cfg.fuselage == "none":
        return "world"
    joint = FreeJoint() if cfg.fuselage == "free" else Fixed()
    body = mass_props.airframe(d, transmission_mass(cfg))
    m.add_body("fuselage", "world", joint, mass=body.mass, com=body.com, inertia=body.inertia,
               shape=_fuselage_shape(d), physical=d["aircraft"]["inertia"] == "airframe")
    return "fuselage"


def _fuselage_shape(d) -> dict:
    g, ht, fin = d["geometry"], d["horizontal_tail"], d["vertical_fin"]
    boom_start = g["cabin_x"] - g["cabin"][0] / 2
    boom_len = boom_start - d["tail_rotor"]["hub_x"]
    fin_height, t = fin["area"] / fin["chord"], g["plate_thickness"]
    tail = has_horizontal_tail(d)
    return {"parts": [
        {"kind": "box", "size": g["cabin"], "offset": [g["cabin_x"], 0, 0], "color": "#c8ccd2"},
        {"kind": "cylinder", "radius": g["boom_radius"], "length": boom_len, "axis": [1, 0, 0],
         "offset": [boom_start - boom_len / 2, 0, ht["z"] if tail else fin["z"]], "color": "#c8ccd2"},
        *([{"kind": "box", "size": [ht["chord"], ht["area"] / ht["chord"], t], "offset": [ht["x"], ht["y"], ht["z"]],
            "color": "#9aa3ad"}] if tail else []),
        {"kind": "box", "size": [fin["chord"], t, fin_height], "offset": [fin["x"], fin["y"], fin["z"] - fin_height / 2],
         "color": "#9aa3ad"},
    ]}


def _pitch_law(psi0: float):
    def angle(t, p):
        psi = p["omega"] * t + psi0
        return p["collective"] + p["lateral_cyclic"] * ca.cos(psi) + p["longitudinal_cyclic"] * ca.sin(psi)
    return angle


def _pitch_bearing(d, cfg, psi0: float, sense: int):
    """A main blade's pitch bearing: driven by the pitch law, free, or None (no pitch hinges). With
    a stabilizer bar it is free, its angle the bar's mixer's (a dependent coordinate, :mod:`build`)."""
    if not cfg.pitch_hinge:
        return None
    if cfg.rotors == "driven" and not cfg.drive_train and not has_stabilizer_bar(d):
        return DrivenHinge((sense, 0, 0), _pitch_law(psi0), name="pitch")
    return Hinge((sense, 0, 0), name="pitch")


def _blade_joint(d, cfg, psi0: float, sense: int):
    mr = d["main_rotor"]
    parts = [main_flap_hinge(mr, sense),
             Hinge((0, 0, -sense), name="lag", stiffness=mr["lag_stiffness"],
                   damping=mr["lag_damping"] if cfg.dampers else 0.0)]
    pitch = _pitch_bearing(d, cfg, psi0, sense)
    return Serial(*parts, *([pitch] if pitch else []))


def _azimuth_joint(cfg, speed_ratio: float, sense: int):
    if cfg.rotors != "driven" or cfg.drive_train:
        return Hinge((0, 0, 1), name="azimuth")
    return DrivenHinge((0, 0, 1), lambda t, p: sense * speed_ratio * p["omega"] * t, name="azimuth")


def add_main_rotor(m: Model, d, cfg, parent: str) -> None:
    mr, sense = d["main_rotor"], fr.main_sense(d)
    tilt = mr["shaft_tilt"] if cfg.shaft_tilt else 0.0
    at = fr.main_hub_position(d) if parent != "world" else np.zeros(3)
    hub = mass_props.main_hub(d)
    m.add_body("main_hub", parent, _azimuth_joint(cfg, 1.0, sense), mass=hub.mass, inertia=hub.inertia, at=at,
               frame=fr.shaft_frame(tilt), shape={"kind": "cylinder", "radius": mr["hub_radius"], "length": d["geometry"]["hub_height"], "axis": [0, 0, 1],
                      "color": "#50565e"})
    if has_stabilizer_bar(d):
        add_stabilizer_bar(m, d, cfg, sense)
    if mr["hub_type"] == "teetering":
        _add_teetering_blades(m, d, cfg, sense)
        return
    big_r, c, t = mr["radius"], mr["chord"], mr["blade_thickness"]
    e, blade = mr["flap_hinge_offset"], mass_props.main_blade(d)
    for k, psi0 in enumerate(fr.blade_azimuths(mr["n_blades"])[:cfg.blade_count(mr["n_blades"])]):
        frame = fr.rz(sense * psi0)
        if (cfg.blade_segments or cfg.blade_modes) and has_damper(d) and cfg.dampers:
            raise ValueError("the aircraft's [lag_damper] strut is built on rigid blades only; an elastic blade "
                             "takes its lag damping as main_rotor.lag_damping: leave [lag_damper] out for it")
        if cfg.blade_segments or cfg.blade_modes:  # elastic, after the pitch bearing (the blade joint's last part)
            add = add_elastic_blade if cfg.blade_segments else add_modal_blade
            add(m, d, cfg, k, frame, _blade_joint(d, cfg, psi0, sense).parts[2:], sense)
            continue
        joint = blade_joint(d, cfg, k + 1, psi0, sense) if cfg.swashplate else _blade_joint(d, cfg, psi0, sense)
        m.add_body(f"blade{k + 1}", "main_hub", joint, mass=blade.mass, com=blade.com, inertia=blade.inertia,
                   at=e * frame[:, 0], frame=frame,
                   shape={"kind": "box", "size": [big_r - e, c, t], "offset": [(big_r - e) / 2, 0, 0],
                          "color": BLADE_COLORS[k % 4]})
        if has_damper(d) and cfg.dampers:
            add_lag_damper(m, d, f"blade{k + 1}", frame, sense)


def _add_teetering_blades(m: Model, d, cfg, sense: int) -> None:
    """A teetering main rotor: the yoke on the teeter hinge across the shaft (its spring the
    file's flap_stiffness), both blades on it at their precone and the undersling below the
    hinge, each on its pitch bearing only (stiff in plane: no lag hinge), or on a coning hinge
    (``blade<k>.flap``, about the precone) ``coning_hinge_offset`` out along it first (a
    Robinson's three-hinge rotor; the blade's mass as along its span from the axis). The teeter
    angle lifts blade 1 and lowers blade 2."""
    mr = d["main_rotor"]
    if cfg.swashplate or cfg.blade_segments or cfg.blade_modes or cfg.blade_count(2) != 2:
        raise ValueError("main_rotor.hub_type: a teetering main rotor is built with its two rigid blades and their "
                         "pitch law; this scene needs per-blade hinges (swashplate, elastic or single blades): fly "
                         "another scene, or give hub_type = \"flapping\"")
    yoke = mass_props.seesaw(d, "main_rotor")
    m.add_body("main_seesaw", "main_hub", Hinge(fr.delta3_axis(mr.get("delta3", 0.0), sense), name="teeter",
                                                 stiffness=mr["flap_stiffness"]),
               mass=yoke.mass, inertia=yoke.inertia,
               shape={"kind": "box", "size": mr["seesaw_size"], "color": "#50565e"})
    big_r, c, t = mr["radius"], mr["chord"], mr["blade_thickness"]
    blade, e = mass_props.main_blade(d), mr.get("coning_hinge_offset", 0.0)
    for k, psi0 in enumerate(fr.blade_azimuths(2)):
        frame = fr.rz(sense * psi0) @ fr.precone_frame(mr["precone"])
        pitch = _pitch_bearing(d, cfg, psi0, sense)
        joint = Serial(Hinge((0, -1, 0), name="flap", stiffness=mr.get("coning_stiffness", 0.0)),
                       *([pitch] if pitch else [])) if e else pitch or Fixed()
        m.add_body(f"blade{k + 1}", "main_seesaw", joint, mass=blade.mass, com=blade.com - [e, 0.0, 0.0],
                   inertia=blade.inertia, frame=frame, at=np.array([0.0, 0.0, -mr["undersling"]]) + e * frame[:, 0],
                   shape={"kind": "box", "size": [big_r - e, c, t], "offset": [(big_r - e) / 2, 0, 0],
                          "color": BLADE_COLORS[k % 4]})


def add_tail_rotor(m: Model, d, cfg, parent: str) -> None:
    """The tail hub on its canted shaft and the blades of the aircraft's hub type."""
    tr, sense = d["tail_rotor"], fr.tail_sense(d)
    radius, length = d["geometry"]["tail_hub"]
    hub = mass_props.tail_hub(d)
    m.add_body("tail_hub", parent, _azimuth_joint(cfg, tr["gear_ratio"], sense), mass=hub.mass,
               inertia=hub.inertia, at=fr.tail_hub_position(d),
               frame=fr.tail_frame(d),
               shape={"kind": "cylinder", "radius": radius, "length": length, "axis": [0, 0, 1], "color": "#50565e"})
    blades_on = "tail_hub"
    if tr["hub_type"] == "teetering":
        m.add_body("seesaw", "tail_hub", Hinge(fr.delta3_axis(tr["delta3"], sense), name="teeter",
                                               stiffness=tr["teeter_stiffness"]),
                   mass=tr["seesaw_mass"], inertia=mass_props.seesaw(d).inertia,
                   shape={"kind": "box", "size": tr["seesaw_size"], "color": "#50565e"})
        blades_on = "seesaw"
    blade = mass_props.tail_blade(d)
    for k, psi0 in enumerate(fr.blade_azimuths(tr["n_blades"])):
        if tr["hub_type"] == "flapping":
            _add_flapping_tail_blade(m, tr, cfg, k, fr.rz(sense * psi0), sense, blade)
            continue
        big_r, c, t = tr["radius"], tr["chord"], tr["blade_thickness"]
        frame = fr.rz(sense * psi0) if tr["precone"] == 0.0 else fr.rz(sense * psi0) @ fr.precone_frame(tr["precone"])
        m.add_body(f"tail_blade{k + 1}", blades_on, _tail_pitch(cfg, sense), mass=blade.mass,
                   com=blade.com, inertia=blade.inertia, frame=frame,
                   shape={"kind": "box", "size": [big_r, c, t], "offset": [big_r / 2, 0, 0], "color": "#7f7f7f"})


def _tail_pitch(cfg, sense: int):
    """The tail blade's pitch bearing: driven by the tail collective, free, or none (a scene
    without pitch hinges)."""
    if not cfg.pitch_hinge:
        return Fixed()
    return (DrivenHinge((sense, 0, 0), lambda t, p: p["tail_collective"], name="pitch") if cfg.rotors == "driven"
            else Hinge((sense, 0, 0), name="pitch"))


def _add_flapping_tail_blade(m: Model, tr, cfg, k: int, frame: np.ndarray, sense: int, blade) -> None:
    """Tail blade ``k`` (from 0) on its own flap hinge at the hinge offset, skewed by δ3, with
    the flap spring relaxed at the precone; the blade a box from the hinge to the tip."""
    e, span, c, t = tr["flap_hinge_offset"], tr["radius"] - tr["flap_hinge_offset"], tr["chord"], tr["blade_thickness"]
    flap = Hinge(fr.delta3_axis(tr["delta3"], sense), name="flap", stiffness=tr["flap_stiffness"],
                 rest_angle=tr["precone"])
    m.add_body(f"tail_blade{k + 1}", "tail_hub", Serial(flap, _tail_pitch(cfg, sense)), mass=blade.mass,
               com=blade.com, inertia=blade.inertia, at=e * frame[:, 0],
               frame=frame,
               shape={"kind": "box", "size": [span, c, t], "offset": [span / 2, 0, 0], "color": "#7f7f7f"})
