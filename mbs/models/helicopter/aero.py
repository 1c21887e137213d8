"""The helicopter's aerodynamic force elements: both rotors' blade elements with their inflow
states, and the airframe (fuselage polynomials, tail surfaces, download, hub drag)."""
from __future__ import annotations

import numpy as np

from mbs.aero import (Airfoil, Compressibility, Download, FuselageAero, FuselageTables, HubDrag, LiftingSurface, Rotor,
                      RotorAero, RotorModel, WakeGeometry)
from mbs.aero.empennage import TailSurface
from mbs.aero.sections import TableSection, ZeroLiftShift
from mbs.aircraft.airframe_data import fuselage_table, has_horizontal_tail, interference_tables, stabilator_schedule
from mbs.aero.tables import BladeAirfoils
from mbs.models.modal_blade import rotor_pieces
from mbs.models.helicopter import frames as fr
from mbs.tree import Model

INFLOW_TEXT = {"": "uniform induced velocity", "_1s": "induced velocity, sine (lateral) component at the tip",
               "_1c": "induced velocity, cosine (longitudinal) component at the tip"}


def rotor_model(d, cfg, section: str) -> RotorModel:
    """The switches of ``cfg`` with their data for the rotor ``section`` ("main_rotor" or
    "tail_rotor"; Pitt-Peters inflow on the main rotor only)."""
    sec = d[section]
    comp = Compressibility(d["environment"]["speed_of_sound"], sec["mach_dd"], sec["mach_limit"])
    wake = main_rotor_wake(d)
    return RotorModel(inflow=cfg.inflow if section == "main_rotor" else "uniform",
                      tip_loss=sec["tip_loss"] if cfg.tip_loss else 1.0,
                      compressibility=comp if cfg.compressibility else None,
                      wake=wake if section == "main_rotor" and (cfg.tail_wake or cfg.download) else None,
                      ground_effect=cfg.ground_effect and section == "main_rotor",
                      duct_exit_ratio=sec.get("duct_exit_ratio", 0.0))


def main_rotor_wake(d) -> WakeGeometry:
    """The main rotor's wake geometry: Landgrebe's coefficients at the hover thrust coefficient."""
    mr, w = d["main_rotor"], d["wake"]
    tip = mr["omega"] * mr["radius"]
    ct = d["aircraft"]["mass"] * d["environment"]["g"] / (d["environment"]["rho"] * np.pi * mr["radius"] ** 2 * tip**2)
    sigma = mr["n_blades"] * mr["chord"] / (np.pi * mr["radius"])
    return WakeGeometry.landgrebe(w["width"], w["core"] * mr["radius"], ct, sigma, np.degrees(mr["twist"]),
                                  mr["n_blades"])


def _add_inflow_states(m: Model, name: str, model: RotorModel, v0: float) -> None:
    what = name.replace("_", "-")
    for state in model.inflow_states(name):
        suffix = state[len(name) + len(".inflow"):]
        m.add_state(state, v0 if not suffix else 0.0, "m/s", f"{what} {INFLOW_TEXT[suffix]}")


def main_rotor(d, cfg, parent: str) -> Rotor:
    """The main rotor's blade-element geometry."""
    mr = d["main_rotor"]
    tilt = mr["shaft_tilt"] if cfg.shaft_tilt else 0.0
    blades = [f"blade{k + 1}" for k in range(cfg.blade_count(mr["n_blades"]))]
    return Rotor("main_rotor", "main_hub", blades, mr["radius"], mr["chord"], mr["twist"], mr["root_cutout"],
                 int(cfg.elements or mr["elements"]), _main_hinge_radius(mr), None if parent == "world" else parent,
                 fr.azimuth_frame(fr.shaft_frame(tilt), fr.main_sense(d)), pieces=rotor_pieces(d, cfg),
                 **_distributions(mr))


def _main_hinge_radius(mr: dict) -> float:
    """Where a main blade's body is jointed (m from the axis): its flap hinge, or a teetering
    hub's coning hinge (none: the axis)."""
    return mr.get("coning_hinge_offset", 0.0) if mr["hub_type"] == "teetering" else mr["flap_hinge_offset"]


def tail_rotor(d, parent: str) -> Rotor:
    """The tail rotor's blade-element geometry (the blades of a flapping hub jointed at the hinge
    offset, the others at the axis)."""
    tr = d["tail_rotor"]
    hinge = tr["flap_hinge_offset"] if tr["hub_type"] == "flapping" else 0.0
    return Rotor("tail_rotor", "tail_hub", [f"tail_blade{k + 1}" for k in range(int(tr["n_blades"]))], tr["radius"],
                 tr["chord"], tr["twist"], tr["root_cutout"], int(tr["elements"]), hinge,
                 None if parent == "world" else parent, fr.azimuth_frame(fr.tail_frame(d), fr.tail_sense(d)),
                 tr["gear_ratio"], **_distributions(tr))


def _distributions(sec: dict) -> dict:
    """The chord and twist tables and the tip sweep of a rotor section that gives them (none:
    constant chord, linear twist, a straight blade)."""
    out = {k: tuple(map(tuple, sec[k])) for k in ("chord_table", "twist_table") if sec.get(k)}
    if sec.get("tip_sweep"):
        out.update(sweep_angle=sec["tip_sweep"], sweep_start=sec["sweep_start"])
    return out


def add_rotor_aero(m: Model, d, cfg, trim, parent: str) -> None:
    """Blade elements and inflow states of the main rotor and, when built, the tail rotor."""
    rho = d["environment"]["rho"]
    main_model = rotor_model(d, cfg, "main_rotor")
    _add_inflow_states(m, "main_rotor", main_model, trim.inflow_main)
    m.add_force(RotorAero(main_rotor(d, cfg, parent), airfoil(d["main_rotor"]), rho, d["main_rotor"]["kappa"],
                          main_model, blade_airfoils(d, cfg, "main_rotor")))
    if cfg.tail_rotor:
        tail_model = rotor_model(d, cfg, "tail_rotor")
        _add_inflow_states(m, "tail_rotor", tail_model, trim.inflow_tail)
        m.add_force(RotorAero(tail_rotor(d, parent), airfoil(d["tail_rotor"]), rho, d["tail_rotor"]["kappa"],
                              tail_model, blade_airfoils(d, cfg, "tail_rotor")))


def blade_airfoils(d, cfg, section: str) -> BladeAirfoils | None:
    """The airfoil tables of the rotor ``section`` per radial segment (None: the analytic
    section); the tables' Mach dependence with the compressibility switch, their lowest Mach
    number without."""
    segments = d[section].get("airfoils", ())
    if not segments:
        return None
    return BladeAirfoils(tuple(s.start for s in segments), tuple(s.airfoil for s in segments),
                         d["environment"]["speed_of_sound"], cfg.compressibility)


def airfoil(sec: dict) -> Airfoil | TableSection | ZeroLiftShift:
    """The section of a rotor or a tail surface: its published coefficient table, else the analytic
    section (about its zero-lift line when the file gives one)."""
    table = sec.get("coefficient_table")
    if table:
        return TableSection(*(tuple(column) for column in zip(*table)))
    section = Airfoil(sec["lift_slope"], sec["cd0"], sec["cd2"], sec["alpha_stall"], sec["cd_stalled"], sec["cd1"])
    return ZeroLiftShift(section, sec["zero_lift_angle"]) if sec.get("zero_lift_angle") else section


def tail_surface(d, cfg, section: str, name: str, normal, wake: str | None) -> LiftingSurface:
    """The horizontal tail or the fin: of fixed incidence in the free stream or the wake, or a
    :class:`mbs.aero.empennage.TailSurface` with the file's stabilator schedule (horizontal tail)
    or, with the wake switched on, its published interference tables in place of the wake."""
    sec, rho = d[section], d["environment"]["rho"]
    schedule = stabilator_schedule(d) if section == "horizontal_tail" else None
    interference = interference_tables(d, section) if cfg.tail_wake else None
    args = (name, "fuselage", (sec["x"], sec["y"], sec["z"]), (1, 0, 0), normal, sec["incidence"], sec["area"],
            airfoil(sec), rho, None if interference else wake)
    if schedule is None and interference is None:
        return LiftingSurface(*args)
    return TailSurface(*args, schedule=schedule, interference=interference)


def wing_panels(d) -> list[tuple[float, float, float]]:
    """The points (m, body axes from the CG) of the wing's panels: one on the centre line, or two
    a quarter of its span to either side; none without a wing."""
    wing = d.get("wing") or {}
    if "area" not in wing:
        return []
    half = wing.get("span", 0.0) / 4
    return [(wing["x"], 0.0, wing["z"])] if not half else [(wing["x"], -half, wing["z"]), (wing["x"], half, wing["z"])]


def add_airframe_aero(m: Model, d, cfg) -> None:
    fa, rho = d["fuselage_aero"], d["environment"]["rho"]
    wake = "main_rotor" if cfg.tail_wake else None
    if fa["model"] == "tables":
        m.add_force(FuselageTables("fuselage", fuselage_table(d), rho))
    else:
        m.add_force(FuselageAero("fuselage", {k: fa[k] for k in "XYZMN"}, fa["v_ref"], fa["angle_limit"], rho))
    if has_horizontal_tail(d):
        m.add_force(tail_surface(d, cfg, "horizontal_tail", "horizontal tail", (0, 0, -1), wake))
    m.add_force(tail_surface(d, cfg, "vertical_fin", "fin", (0, 1, 0), wake))
    for k, panel in enumerate(wing_panels(d)):
        m.add_force(LiftingSurface(f"wing{k + 1}" if len(wing_panels(d)) > 1 else "wing", "fuselage", panel,
                                   (1, 0, 0), (0, 0, -1), d["wing"]["incidence"], d["wing"]["area"] / len(wing_panels(d)),
                                   airfoil(d["wing"]), rho, wake))
    if cfg.download:
        m.add_force(Download("fuselage", "main_rotor", d["download"]["panels"], rho))
    if cfg.hub_drag:
        m.add_force(HubDrag("fuselage", fr.main_hub_position(d), d["hub_drag"]["flat_plate_area"], rho))
