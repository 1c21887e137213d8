"""The helicopter's outputs: rotor azimuths, thrust, torque, power, inflow ratios, wake values."""
from __future__ import annotations

from mbs.aircraft.airframe_data import has_horizontal_tail
from mbs.models.helicopter import frames as fr
from mbs.models.helicopter.aero import INFLOW_TEXT, rotor_model
from mbs.models.helicopter.stabilizer_bar import add_stabilizer_bar_outputs, has_stabilizer_bar
from mbs.tree import Model

ROTOR_OUTPUTS = (("thrust", "N", "thrust along the shaft"),
                 ("torque", "N m", "aerodynamic torque of the blade elements about the shaft (the drive's torque is "
                                   "shaft_torque)"),
                 ("power", "W", "aerodynamic power, torque times rotor speed"))


def add_outputs(m: Model, d, cfg) -> None:
    gear = d["tail_rotor"]["gear_ratio"]
    _add_azimuth(m, cfg, "main_rotor", "main_hub", 1.0, fr.main_sense(d), "azimuth of blade 1 from the tail")
    if cfg.tail_rotor:
        _add_azimuth(m, cfg, "tail_rotor", "tail_hub", gear, fr.tail_sense(d), "azimuth of tail blade 1")
    if cfg.rotor_aero:
        _add_rotor_outputs(m, d, cfg, "main_rotor", 1.0)
        if cfg.tail_rotor:
            _add_rotor_outputs(m, d, cfg, "tail_rotor", gear)
    _add_airframe_outputs(m, d, cfg)
    if cfg.airframe_aero and cfg.fuselage == "free":
        _add_tail_outputs(m, d, cfg)
    if cfg.turbulence:
        field = next(f for f in m.air.motions if hasattr(f, "at_station"))
        for i, axis in enumerate(("north", "east", "down")):
            m.add_output(f"turbulence.{axis}", lambda s, i=i: field.at_station(s, 0)[i], "m/s",
                         f"the turbulence's air velocity towards {axis} at the main rotor's hub")
            m.add_output(f"turbulence.tail_{axis}", lambda s, i=i: field.at_station(s, 1)[i], "m/s",
                         f"the turbulence's air velocity towards {axis} at the tail rotor's hub")
    if cfg.ground_effect:
        m.add_output("main_rotor.ground_factor", lambda s: s.signals["main_rotor.ground_factor"], "1",
                     "share of the induced velocity the main rotor's blades see near the ground (1 far from it)")
    if cfg.drive_train:
        from mbs.drivetrain.train import add_outputs as add_drive_train_outputs
        add_drive_train_outputs(m, d, cfg)
    if has_stabilizer_bar(d):
        add_stabilizer_bar_outputs(m, d, cfg)


def _add_azimuth(m: Model, cfg, rotor: str, hub: str, ratio: float, sense: int, text: str) -> None:
    """The azimuth (rad) in the rotor's sense of rotation."""
    if cfg.rotors == "driven" and not cfg.drive_train:
        m.add_output(f"{rotor}.azimuth", lambda s: ratio * s.p["omega"] * s.t, "rad", text)
    else:
        m.add_output(f"{rotor}.azimuth", lambda s: sense * s.q(f"{hub}.azimuth"), "rad", text)


def _add_airframe_outputs(m: Model, d, cfg) -> None:
    """The main rotor's wake at the tail surfaces and the fuselage download, when modelled."""
    tail = has_horizontal_tail(d)
    if cfg.tail_wake:
        if tail:
            m.add_output("horizontal_tail.downwash", lambda s: s.signals["horizontal tail.wake"][2], "m/s",
                         "main-rotor wake velocity at the horizontal tail along body z (positive down)")
        m.add_output("fin.sidewash", lambda s: s.signals["fin.wake"][1], "m/s",
                     "main-rotor wake velocity at the fin along body y (positive to starboard)")
        for key, name in (("horizontal_tail", "horizontal tail"), ("fin", "fin"))[0 if tail else 1:]:
            m.add_output(f"{key}.wake_immersion", lambda s, name=name: s.signals.get(f"{name}.immersion", 0), "1",
                         f"share of the main-rotor wake the {name} is in: 0 outside, 1 inside, between at the "
                         "wake's edge (smoothed over wake.width); 0 where interference tables replace the wake")
    if cfg.download:
        m.add_output("fuselage.download", lambda s: s.signals["fuselage.download"], "N",
                     "vertical drag of the fuselage in the main-rotor wake (positive down)")


def _add_tail_outputs(m: Model, d, cfg) -> None:
    """A stabilator's incidence, and each scheduled or interfered surface's angle of attack."""
    from mbs.aircraft.airframe_data import has_stabilator, interference_tables

    if has_stabilator(d):
        m.add_output("stabilator.incidence", lambda s: s.signals["horizontal tail.incidence"], "rad",
                     "stabilator incidence from its schedule, leading edge up positive")
        m.add_output("stabilator.incidence_unlimited", lambda s: s.signals["horizontal tail.incidence_raw"], "rad",
                     "stabilator incidence the schedule asks for before the stops")
    for section, name, key in (("horizontal_tail", "horizontal tail", "horizontal_tail"), ("vertical_fin", "fin", "fin")):
        if not has_horizontal_tail(d) and section == "horizontal_tail":
            continue
        special = (section == "horizontal_tail" and has_stabilator(d)) or (
            cfg.tail_wake and interference_tables(d, section) is not None)
        if special:
            m.add_output(f"{key}.alpha", lambda s, n=name: s.signals[f"{n}.alpha"], "rad",
                         f"angle of attack of the {name} section as it is read (air from behind its trailing edge "
                         "folded into +-90 deg, as a flat plate's)")
    _add_wing_outputs(m, d, cfg)


def _add_wing_outputs(m: Model, d, cfg) -> None:
    """Each wing panel's angle of attack and, in the wake, its immersion in it."""
    from mbs.models.helicopter.aero import wing_panels

    panels = wing_panels(d)
    for k in range(len(panels)):
        name = f"wing{k + 1}" if len(panels) > 1 else "wing"
        side = ("" if len(panels) == 1 else (" (port panel)" if k == 0 else " (starboard panel)"))
        m.add_output(f"{name}.alpha", lambda s, n=name: s.signals[f"{n}.alpha"], "rad",
                     f"angle of attack of the wing{side} as its section is read (air from behind its trailing "
                     "edge folded into +-90 deg: near 90 deg the sign flips with the air crossing the normal)")
        if cfg.tail_wake:
            m.add_output(f"{name}.wake_immersion", lambda s, n=name: s.signals.get(f"{n}.immersion", 0), "1",
                         f"share of the main-rotor wake the wing{side} is in: 0 outside, 1 inside")


def _add_rotor_outputs(m: Model, d, cfg, name: str, speed_ratio: float) -> None:
    """Thrust, torque, power (signals of the rotor's aerodynamics) and its inflow ratios
    ``λ = v / (Ω R)`` (the inflow states made dimensionless)."""
    what, tip = name.replace("_", "-"), speed_ratio * d[name]["radius"]
    for key, unit, text in ROTOR_OUTPUTS:
        m.add_output(f"{name}.{key}", lambda s, k=f"{name}.{key}": s.signals[k], unit, f"{what} {text}")
    if not d[name].get("airfoils"):  # tables hold their own stall
        m.add_output(f"{name}.stalled_share", lambda s, k=f"{name}.stalled_share": s.signals[k], "1",
                     f"{what}: share of the blades' dynamic pressure (the sum of U^2 dr over the elements) at angles "
                     "of attack between the analytic section's stall angle (alpha_stall) and 45 deg, where its lift "
                     "is only bounded (the retreating blade at speed)")
    if rotor_model(d, cfg, name).duct_exit_ratio:
        m.add_output(f"{name}.duct_thrust", lambda s, k=f"{name}.duct_thrust": s.signals[k], "N",
                     f"{what} duct thrust along the fan's thrust axis (the blades' is {name}.thrust)")
    for state in rotor_model(d, cfg, name).inflow_states(name) if "omega" in m.parameters else ():
        suffix = state[len(name) + len(".inflow"):]
        m.add_output(f"{name}.inflow_ratio{suffix}", lambda s, z=state: s.z(z) / (tip * s.p["omega"]), "1",
                     f"{what} inflow ratio: {INFLOW_TEXT[suffix]} per tip speed")
