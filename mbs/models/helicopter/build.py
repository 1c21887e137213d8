"""Build a helicopter model from an aircraft and a scene :class:`Config`."""
from __future__ import annotations

from dataclasses import replace

import casadi as ca
import numpy as np

from mbs import _rotation as rot
from mbs.loads.rotorcraft import add_load_outputs
from mbs.models.helicopter import frames as fr
from mbs.models.helicopter.aero import add_airframe_aero, add_rotor_aero
from mbs.models.helicopter.config import Config
from mbs.models.helicopter.estimate import TrimEstimate, estimate_trim
from mbs.models.helicopter.outputs import add_outputs
from mbs.models.helicopter.swashplate import add_actuator_inputs, add_elastic_links, add_swashplate_outputs
from mbs.models.helicopter.tree import add_fuselage, add_main_rotor, add_tail_rotor
from mbs.tree import Model

CONTROLS = (("collective", "main-rotor collective pitch at the blade root"),
            ("lateral_cyclic", "main-rotor lateral cyclic θ1c"),
            ("longitudinal_cyclic", "main-rotor longitudinal cyclic θ1s"))


def build(cfg: Config = Config(), aircraft=None, name: str | None = None) -> Model:
    """The helicopter of ``aircraft`` (an :class:`mbs.aircraft.Aircraft`, its ``data``, or None:
    the Bo105) with exactly the bodies and forces ``cfg`` asks for."""
    from mbs import aircraft as ac

    aircraft = ac.load() if aircraft is None else aircraft
    d = getattr(aircraft, "data", aircraft)
    _check_distributions(d, cfg)
    stored = stored_trim(aircraft, cfg.trim, cfg.speed)
    trim = estimate_trim(d, cfg.speed)
    m = Model(name or f"{getattr(aircraft, 'key', 'aircraft')}-model", gravity=(0.0, 0.0, d["environment"]["g"]))
    parent = add_fuselage(m, d, cfg)
    add_main_rotor(m, d, cfg, parent)
    if cfg.tail_rotor:
        add_tail_rotor(m, d, cfg, parent)
    if cfg.rotor_aero:
        add_rotor_aero(m, d, cfg, trim, parent)
    if cfg.airframe_aero and cfg.fuselage == "free":
        add_airframe_aero(m, d, cfg)
    if cfg.rotors == "driven":
        _add_parameters(m, d, cfg, trim, stored)
    add_outputs(m, d, cfg)
    add_load_outputs(m, d, cfg)
    if cfg.swashplate:
        add_swashplate_outputs(m, d, cfg)
    _set_initial(m, d, cfg, trim, stored)
    if cfg.pitch_link == "elastic":
        add_elastic_links(m, d, cfg)
    return m


def _check_distributions(d, cfg: Config) -> None:
    """The elastic and modal blades are uniform beams: refuse a mass distribution they would ignore."""
    given = [k for k in ("mass_table", "section_inertia_table") if d["main_rotor"].get(k)]
    if given and (cfg.blade_segments or cfg.blade_modes):
        kind = "segmented elastic" if cfg.blade_segments else "modal"
        raise ValueError(f"main_rotor.{given[0]}: the {kind} blade is a uniform beam of main_rotor.blade_mass; it "
                         "does not take a mass distribution yet: fly rigid blades, or leave the table out for this "
                         "scene")


def stored_trim(aircraft, key: str | None, speed: float) -> dict | None:
    """The trim stored under ``key`` beside the aircraft's file if it is for ``speed`` (m/s)."""
    if not key or not hasattr(aircraft, "stored_trims"):
        return None
    entry = aircraft.stored_trims().get(key)
    return entry if entry and abs(entry["speed"] - speed) < 1e-6 else None


def _add_parameters(m: Model, d, cfg: Config, trim: TrimEstimate, stored: dict | None) -> None:
    mr, tr = d["main_rotor"], d["tail_rotor"]
    if stored:
        trim = replace(trim, **{k: stored[k] for k in ("collective", "lateral_cyclic", "longitudinal_cyclic",
                                                      "tail_collective") if k in stored})
    m.add_parameter("omega", mr["omega"], "rad/s", "main-rotor speed (tail rotor turns gear_ratio times faster)",
                    low=mr["omega_min"], high=mr["omega_max"])
    if not cfg.pitch_hinge:
        return
    if cfg.swashplate == "actuators":
        add_actuator_inputs(m, d, {name: getattr(trim, name) for name, _ in CONTROLS})
    for name, what in CONTROLS if cfg.swashplate != "actuators" else ():
        low, high = mr[f"{name}_min"], mr[f"{name}_max"]  # the estimate beyond the controls' reach: clipped
        m.add_parameter(name, float(np.clip(getattr(trim, name), low, high)), "rad", what, control=True,
                        low=low, high=high)
    if cfg.tail_rotor:
        low, high = tr["collective_min"], tr["collective_max"]
        m.add_parameter("tail_collective", float(np.clip(trim.tail_collective, low, high)), "rad",
                        "tail-rotor collective pitch", control=True, low=low, high=high)


def _set_initial(m: Model, d, cfg: Config, trim: TrimEstimate, stored: dict | None) -> None:
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
    for k, psi in enumerate(fr.blade_azimuths(mr["n_blades"])[:cfg.blade_count(mr["n_blades"])]):
        m.set_initial(**{f"blade{k + 1}.flap": trim.coning - trim.a1s * np.cos(psi),
                         f"blade{k + 1}.flap_rate": trim.a1s * omega * np.sin(psi)})
        if cfg.rotors == "free" and cfg.pitch_hinge:
            m.set_initial(**{f"blade{k + 1}.pitch": trim.collective})
    if cfg.rotors == "free":
        sense = fr.main_sense(d)
        m.set_initial(**{"main_hub.azimuth_rate": sense * omega})
        if cfg.tail_rotor:
            m.set_initial(**{"tail_hub.azimuth_rate": fr.tail_sense(d) * d["tail_rotor"]["gear_ratio"] * omega})
