"""The air a helicopter scene flies in: the aircraft file's or the ISA's density and speed of
sound, and a steady wind (:class:`mbs.environment.Air`, read by every aerodynamic element).

Scene options (:class:`mbs.models.helicopter.Config`): ``atmosphere`` "file" | "isa" with the
defaults ``altitude`` (m) and ``temperature_offset`` (K) of its run-time parameters; ``wind``
None or the defaults (north, east, down; m/s) of the parameters ``wind_north``, ``wind_east``,
``wind_down``. :func:`mbs.models.helicopter.air_options.with_environment` gives a scene with
them (the commands' ``--altitude``, ``--temperature-offset`` and ``--wind``).
"""
from __future__ import annotations

import math

import casadi as ca

from mbs.environment import Air
from mbs.environment import atmosphere as isa

ATMOSPHERES = ("file", "isa")


def check(cfg) -> None:
    """ValueError naming the option when ``cfg`` asks for air it cannot model."""
    if cfg.atmosphere not in ATMOSPHERES:
        raise ValueError(f"atmosphere = {cfg.atmosphere!r}: choose 'file' (the aircraft file's density and speed of "
                         "sound) or 'isa' (the ISA at the altitude and temperature offset parameters)")
    if cfg.atmosphere == "file" and (cfg.altitude or cfg.temperature_offset):
        raise ValueError(f"altitude = {cfg.altitude:g} m, temperature_offset = {cfg.temperature_offset:g} K: they set "
                         "the ISA, which the scene does not use (atmosphere = 'isa')")
    isa.check(cfg.altitude, cfg.temperature_offset)
    if cfg.atmosphere == "isa" and not _aerodynamic(cfg):
        raise ValueError("the ISA sets the air's density and speed of sound for the aerodynamics, which this scene "
                         "does not model (no rotor or airframe aerodynamics)")
    if cfg.wind is not None:
        _check_wind(cfg)
    _check_ground(cfg)
    _check_motions(cfg)
    if cfg.payload is not None and not (cfg.fuselage == "free" and math.isfinite(cfg.payload)
                                        and abs(cfg.payload) <= PAYLOAD_LIMIT):
        raise ValueError(f"payload = {cfg.payload!r} kg: a weight on a free fuselage, within ±{PAYLOAD_LIMIT:g} kg")
    if cfg.cg_shift and cfg.fuselage != "free":
        raise ValueError("cg_shift moves the weight of a free fuselage; this scene's fuselage is "
                         f"{cfg.fuselage!r}")


def _check_motions(cfg) -> None:
    from mbs.environment.turbulence import FORMS

    if cfg.turbulence_intensity is not None and not cfg.turbulence:
        raise ValueError(f"turbulence_intensity = {cfg.turbulence_intensity!r}: the scene has no turbulence")
    if cfg.turbulence is not None and cfg.turbulence not in FORMS:
        raise ValueError(f"turbulence = {cfg.turbulence!r}: choose None or one of {', '.join(FORMS)}")
    for name in ("turbulence", "gust"):
        if getattr(cfg, name) and cfg.fuselage != "free":
            raise ValueError(f"{name} is a field the aircraft flies through: it needs a free fuselage, which this "
                             f"scene does not have (fuselage = {cfg.fuselage!r})")
        if getattr(cfg, name) and not _aerodynamic(cfg):
            raise ValueError(f"{name} acts on the aerodynamics, which this scene does not model")


def _check_ground(cfg) -> None:
    if cfg.ground_effect and not cfg.rotor_aero:
        raise ValueError("ground_effect acts on the main rotor's inflow, which this scene does not model")
    if cfg.height is not None and not cfg.ground_effect and not getattr(cfg, "turbulence", None):
        raise ValueError(f"height = {cfg.height:g} m sets the ground for the ground effect (or the turbulence): turn "
                         "ground_effect on")
    if cfg.height is not None and not (math.isfinite(cfg.height) and 0 <= cfg.height <= HEIGHT_LIMIT):
        raise ValueError(f"height = {cfg.height!r} m: give a height above the ground from 0 to {HEIGHT_LIMIT:g} m")


HEIGHT_LIMIT = 10000.0  # m
PAYLOAD_LIMIT = 5000.0  # kg


def add_payload(m, d, cfg) -> None:
    """The run-time ``payload`` (kg): weight at the centre of gravity (the fuselage's origin)."""
    if cfg.payload is None:
        return
    from mbs.forces import PointForce

    g = d["environment"]["g"]
    m.add_parameter("payload", float(cfg.payload), "kg", "weight added at the centre of gravity (its inertia left "
                    "out: the aircraft's mass for trims and performance)", low=-PAYLOAD_LIMIT, high=PAYLOAD_LIMIT)
    m.add_force(PointForce("payload weight", "fuselage", [0.0, 0.0, lambda s: g * s.p["payload"]], frame="world"))
CG_SHIFT_LIMIT = 1.0  # m


def add_cg_shift(m, d, cfg) -> None:
    """The run-time ``cg_x`` (m, forward) and ``cg_y`` (m, starboard): the aircraft's weight
    (and the ``payload``'s) acting that far from the file's CG, as a torque ``r × W`` in body
    axes. In a steady trim (no rotation, so no inertial loads beyond the rotor's vibration) that is
    the CG moved there: every other load keeps its point on the airframe. The inertia stays the
    file's."""
    if not cfg.cg_shift:
        return
    from mbs.forces import BodyTorque

    g, mass = d["environment"]["g"], d["aircraft"]["mass"]
    for name, axis in (("cg_x", "forward"), ("cg_y", "starboard")):
        m.add_parameter(name, 0.0, "m", f"the CG this far {axis} of the aircraft file's, for trims: the weight acts "
                        "there (the inertia stays the file's)", low=-CG_SHIFT_LIMIT, high=CG_SHIFT_LIMIT)

    def torque(s):
        weight = g * (mass + (s.p["payload"] if cfg.payload is not None else 0.0))
        down = ca.mtimes(s.body("fuselage").rotation.T, ca.DM([0.0, 0.0, 1.0])) * weight  # body components
        return ca.cross(ca.vertcat(s.p["cg_x"], s.p["cg_y"], 0.0), down)

    m.add_force(BodyTorque("weight at the shifted CG", "fuselage", torque))


DEFAULT_HEIGHT = 100.0  # m: the default ground below a scene's start


def add_height(m, cfg) -> None:
    """The run-time ``height`` (m, of the world's origin above the ground) when the scene needs the ground."""
    if cfg.ground_effect or getattr(cfg, "turbulence", None):
        m.add_parameter("height", DEFAULT_HEIGHT if cfg.height is None else float(cfg.height), "m",
                        "height of the world's origin (the aircraft's start) above the ground: the ground plane is "
                        "at world z = height (z down)", low=0.0, high=HEIGHT_LIMIT)


def _aerodynamic(cfg) -> bool:
    return cfg.rotor_aero or (cfg.airframe_aero and cfg.fuselage == "free")


def _check_wind(cfg) -> None:
    wind = tuple(cfg.wind)
    if len(wind) != 3 or not all(isinstance(w, (int, float)) and math.isfinite(w) for w in wind):
        raise ValueError(f"wind = {cfg.wind!r}: give three finite numbers, north, east, down (m/s)")
    if max(abs(w) for w in wind) > WIND_LIMIT:
        raise ValueError(f"wind = {wind}: each component within ±{WIND_LIMIT:g} m/s")
    if not _aerodynamic(cfg):
        raise ValueError("wind acts on the aerodynamics, which this scene does not model (no rotor or airframe "
                         "aerodynamics)")


WIND_LIMIT = 60.0  # m/s, each component


def air_of(cfg, d=None) -> Air | None:
    """The model's :class:`Air` for ``cfg`` (``d`` the aircraft data: the turbulence's stations at
    the rotor hubs), None for still air at the file's values."""
    if cfg.atmosphere == "file" and cfg.wind is None and not cfg.turbulence and not cfg.gust:
        return None
    from mbs.environment.gust import DiscreteGust
    from mbs.environment.turbulence import TurbulenceField

    motions = []
    if cfg.turbulence:
        stations = (d["main_rotor"]["hub_x"], d["tail_rotor"]["hub_x"])
        intensity = {} if cfg.turbulence_intensity is None else {"intensity": float(cfg.turbulence_intensity)}
        motions.append(TurbulenceField(cfg.turbulence, stations, "fuselage", cfg.wind is not None, **intensity))
    if cfg.gust:
        motions.append(DiscreteGust(cfg.wind is not None))
    return Air(isa=cfg.atmosphere == "isa", wind=cfg.wind is not None, motions=motions)


def add_air(m, cfg, d=None) -> None:
    """Give the model ``m`` the air of ``cfg`` (aircraft data ``d``) and its run-time parameters."""
    m.air = air_of(cfg, d)
    if m.air is None:
        return
    m.air.add_parameters(m, cfg.altitude, cfg.temperature_offset)
    for name, value in zip(("wind_north", "wind_east", "wind_down"), cfg.wind or ()):
        m.parameters[name].default = float(value)


def isa_defaults(cfg) -> dict:
    """``{"altitude": m, "temperature_offset": K}`` of an ISA scene's defaults; {} otherwise."""
    return {"altitude": cfg.altitude, "temperature_offset": cfg.temperature_offset} if cfg.atmosphere == "isa" else {}


def data_in_air(d, parameters: dict):
    """The aircraft data ``d`` with the ``[environment]`` density and speed of sound of the ISA
    at ``parameters["altitude"]`` and ``["temperature_offset"]`` when given (closed-form
    estimates at altitude); ``d`` itself otherwise."""
    if "altitude" not in parameters:
        return d
    h, dt = parameters["altitude"], parameters.get("temperature_offset", 0.0)
    out = type(d)(d)
    out.meta = getattr(d, "meta", {})
    out["environment"] = {**d["environment"], "rho": isa.density(h, dt), "speed_of_sound": isa.speed_of_sound(h, dt)}
    return out


HINTS = (("engine", "an engine input: the scenes whose rotor speed is a state on engines have it (engine-failure, "
                    "engine-failure-cruise, hover-engines); a constant-speed scene has no engine to fail"),
         ("governor", "the engines' governor: scenes with engines (engine-failure, hover-engines)"),
         ("drive_torque", "the drive train's torque: scenes whose rotor speed is a state without engines (autorotation)"),
         ("turbulence", "turbulence: --turbulence dryden|von-karman (free flight)"), ("gust", "a gust: --gust"),
         ("wind", "a steady wind: --wind N,E,D"), ("altitude", "the ISA: --altitude M"),
         ("temperature_offset", "the ISA: --temperature-offset K"),
         ("height", "the ground: --ground-effect or --turbulence"))


def hint(name: str) -> str:
    """Where a run-time parameter ``name`` that a scene lacks comes from ("" when unknown)."""
    return next((f" ({text})" for prefix, text in HINTS if name.startswith(prefix)), "")
