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
from mbs.models.helicopter.environment import (add_air, add_cg_shift, add_height, add_payload, data_in_air,
                                               isa_defaults)
from mbs.models.helicopter.estimate import TrimEstimate, estimate_trim, flap_start
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
    stored = stored_trim(aircraft, cfg.trim, cfg.speed) if cfg.atmosphere == "file" else None
    m = Model(name or f"{getattr(aircraft, 'key', 'aircraft')}-model", gravity=(0.0, 0.0, d["environment"]["g"]))
    trim = estimate_trim(data_in_air(d, isa_defaults(cfg)), cfg.speed)
    parent = add_fuselage(m, d, cfg)
    add_main_rotor(m, d, cfg, parent)
    if cfg.tail_rotor:
        add_tail_rotor(m, d, cfg, parent)
    if cfg.drive_train:
        from mbs.drivetrain import train

        train.add_drive_train(m, d, cfg, parent)
    _add_pitch_laws(m, d, cfg)
    if cfg.rotor_aero:
        add_rotor_aero(m, d, cfg, trim, parent)
    if cfg.airframe_aero and cfg.fuselage == "free":
        add_airframe_aero(m, d, cfg)
    if cfg.rotors == "driven":
        _add_parameters(m, d, cfg, trim, stored)
    if cfg.drive_train:
        _add_drive(m, d, cfg, trim)
    add_air(m, cfg, d)
    add_height(m, cfg)
    add_payload(m, d, cfg)
    add_cg_shift(m, d, cfg)
    add_outputs(m, d, cfg)
    add_load_outputs(m, d, cfg)
    if cfg.swashplate:
        add_swashplate_outputs(m, d, cfg)
    _set_initial(m, d, cfg, trim, stored)
    if cfg.pitch_link == "elastic":
        add_elastic_links(m, d, cfg)
    return m


def _add_pitch_laws(m: Model, d, cfg: Config) -> None:
    """The blades' pitch as dependent coordinates: of the hub's azimuth with a drive train, and of
    the stabilizer bar's teeter through its mixer (:mod:`mbs.models.helicopter.stabilizer_bar`)."""
    from mbs.drivetrain import train
    from mbs.models.helicopter import stabilizer_bar as sb

    bar = sb.has_stabilizer_bar(d)
    if not cfg.pitch_hinge or not (cfg.drive_train or (bar and cfg.rotors == "driven")):
        return
    sense, blades = fr.main_sense(d), d["main_rotor"]["n_blades"]
    for k, psi0 in enumerate(fr.blade_azimuths(blades)[:cfg.blade_count(blades)]):
        law = sb.mixer(d, psi0, sb.hub_azimuth(cfg, sense)) if bar else train.pitch_law(psi0, sense)
        m.add_dependent(f"blade{k + 1}.pitch", law)


def _add_drive(m: Model, d, cfg: Config, trim: TrimEstimate) -> None:
    """What drives the drive train: the aircraft's engines and governor, or the run-time drive torque."""
    from mbs.drivetrain import engine, train

    sense, coordinate = fr.main_sense(d), f"{train.TRANSMISSION}.angle"
    if not cfg.engines:
        m.add_parameter("drive_torque", 0.0, "N m", "torque driving the transmission in the rotors' sense (an "
                        "engine holding a constant torque; 0: free-wheeling)", low=-1e6, high=1e6)
        m.add_force(train.DriveTorque(coordinate, sense))
        return
    eng = engine.Turboshaft.of(d)
    engine.add_parameters(m, eng, d["main_rotor"]["omega"], cfg.failure_time)
    element = engine.Engines(eng, coordinate, sense, d["main_rotor"]["collective_min"], air_ratios(cfg))
    share = float(np.clip(eng.anticipation * (trim.collective - d["main_rotor"]["collective_min"]), 0, 1))
    m.add_state("governor.lead", 0.0, "1", "governor: the lag state of its lead-lag compensation")
    for k in range(1, eng.count + 1):
        fuel, power = engine.names(k)
        m.add_state(fuel, share, "1", f"engine {k}: metered fuel flow, fraction of its take-off power")
        m.add_state(power, share, "1", f"engine {k}: gas generator power, fraction of its take-off power")
    m.add_force(element)
    engine.add_outputs(m, element)


def air_ratios(cfg: Config):
    """``state -> (δ, θ)``: the air's pressure and temperature over sea level's (1, 1 for the file's air)."""
    from mbs.environment import atmosphere as isa

    if cfg.atmosphere != "isa":
        return lambda state: (1.0, 1.0)

    def ratios(state):
        h, dt = state.p["altitude"], state.p["temperature_offset"]
        return isa.pressure(h) / isa.P0, isa.temperature(h, dt) / isa.T0
    return ratios


def _check_distributions(d, cfg: Config) -> None:
    """The elastic and modal blades are uniform beams: refuse a mass distribution they would ignore,
    and a stabilizer bar, whose mixer pitches rigid blades only."""
    from mbs.aircraft.mass import is_uniform_blade

    mr = d["main_rotor"]
    given = [k for k in ("mass_table", "section_inertia_table") if mr.get(k)]
    if not given and not is_uniform_blade(mr):
        given = ["blade_mass"]
    if mr.get("precone") and (cfg.blade_segments or cfg.blade_modes):
        raise ValueError(f"main_rotor.precone: the {'segmented elastic' if cfg.blade_segments else 'modal'} blade "
                         "is a straight beam from the hub; it does not take a precone yet: fly rigid blades, or "
                         "leave precone out for this scene")
    if "hiller_gain" in (d.get("stabilizer_bar") or {}) and (cfg.blade_segments or cfg.blade_modes or cfg.swashplate):
        raise ValueError("stabilizer_bar: its mixer sets the pitch of rigid blades flown by the pitch inputs; this "
                         "scene's blades are elastic or pitched by the swashplate's links: fly forward-flight, hover "
                         "or a drive-train scene, or leave [stabilizer_bar] out for this one")
    if given and (cfg.blade_segments or cfg.blade_modes):
        kind = "segmented elastic" if cfg.blade_segments else "modal"
        what = "a mass distribution" if given[0] != "blade_mass" else "a blade whose mass, first moment and I_flap " \
            "are not one uniform blade's"
        raise ValueError(f"main_rotor.{given[0]}: the {kind} blade is a uniform beam of main_rotor.blade_mass; it "
                         f"does not take {what} yet: fly rigid blades, or leave the table or override out for this "
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
    if not cfg.drive_train:  # with a drive train the rotor speed is a state
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
    m.set_initial(**flap_start(d, cfg.blade_count(mr["n_blades"]), trim.coning, trim.a1s, omega))
    for k in range(cfg.blade_count(mr["n_blades"])):
        if cfg.rotors == "free" and cfg.pitch_hinge:
            m.set_initial(**{f"blade{k + 1}.pitch": trim.collective})
    if cfg.rotors == "free" or cfg.drive_train:
        sense = fr.main_sense(d)
        m.set_initial(**{"main_hub.azimuth_rate": sense * omega})
        if cfg.drive_train == "flexible":
            m.set_initial(**{"transmission.angle_rate": sense * omega})
        if cfg.tail_rotor and not cfg.drive_train:
            m.set_initial(**{"tail_hub.azimuth_rate": fr.tail_sense(d) * d["tail_rotor"]["gear_ratio"] * omega})
