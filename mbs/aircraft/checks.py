"""Physical checks across entries, after each entry is read and within its own bounds.

Each check returns the problems it finds, one line each, naming the entry to change.
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

MAX_PERIOD_REVS = 12
"""A periodic trim shoots over the rotors' common period; longer than this is refused."""


def problems(values: dict) -> list[str]:
    """Every physical problem of the completed ``values`` (defaults and derived values in)."""
    out = []
    for check in (_inertia, _blades, _controls, _rotor_speed, _tail_hub, _airframe_mass, _tip_mach, _airfoils,
                  _distributions):
        out += check(values)
    return out


def _inertia(v: dict) -> list[str]:
    a = v["aircraft"]
    tensor = np.array([[a["Ixx"], 0, -a["Ixz"]], [0, a["Iyy"], 0], [-a["Ixz"], 0, a["Izz"]]])
    p = np.linalg.eigvalsh(tensor)
    if p[0] <= 0:
        return [f"aircraft.Ixz: {a['Ixz']:g} kg m^2 makes the inertia tensor not positive definite "
                f"(principal moments {', '.join(f'{x:.4g}' for x in p)})"]
    if p[0] + p[1] < p[2] * (1 - 1e-12):
        return [f"aircraft.Izz: principal moments {p[0]:.4g}, {p[1]:.4g}, {p[2]:.4g} kg m^2 violate the triangle "
                "inequality (no rigid body has them: the largest exceeds the sum of the other two)"]
    return []


def _blades(v: dict) -> list[str]:
    out = []
    for name in ("main_rotor", "tail_rotor"):
        sec = v[name]
        if sec["chord"] >= sec["radius"]:
            out.append(f"{name}.chord: {sec['chord']:g} m is not smaller than the radius {sec['radius']:g} m")
        if sec["blade_thickness"] > sec["chord"]:
            out.append(f"{name}.blade_thickness: {sec['blade_thickness']:g} m exceeds the chord {sec['chord']:g} m")
    mr = v["main_rotor"]
    if mr["flap_hinge_offset"] >= mr["radius"] * (1 - 1e-9):
        out.append(f"main_rotor.flap_hinge_offset: {mr['flap_hinge_offset']:g} m puts the hinge outside the blade "
                   f"(radius {mr['radius']:g} m)")
    tr = v["tail_rotor"]
    if tr["hub_type"] == "teetering" and tr["n_blades"] != 2:
        out.append(f"tail_rotor.n_blades: a teetering tail rotor has 2 blades, not {tr['n_blades']}; "
                   "use hub_type = \"rigid\" for more")
    return out


def _controls(v: dict) -> list[str]:
    out = []
    for section, names in (("main_rotor", ("collective", "lateral_cyclic", "longitudinal_cyclic")),
                           ("tail_rotor", ("collective",))):
        for name in names:
            low, high = v[section][f"{name}_min"], v[section][f"{name}_max"]
            if low >= high:
                out.append(f"{section}.{name}_min: {math.degrees(low):.4g} deg is not below {name}_max "
                           f"({math.degrees(high):.4g} deg)")
    return out


def _rotor_speed(v: dict) -> list[str]:
    mr = v["main_rotor"]
    if not mr["omega_min"] < mr["omega"] < mr["omega_max"]:
        return [f"main_rotor.omega: {mr['omega']:g} rad/s outside the range omega_min..omega_max "
                f"({mr['omega_min']:g}..{mr['omega_max']:g} rad/s)"]
    return []


def _tail_hub(v: dict) -> list[str]:
    mr, tr = v["main_rotor"], v["tail_rotor"]
    clearance = abs(mr["hub_x"] - tr["hub_x"]) - mr["radius"] - tr["radius"]
    if clearance < 0 and abs(tr["hub_z"] - mr["hub_z"]) < tr["radius"]:
        return [f"tail_rotor.hub_x: {tr['hub_x']:g} m puts the tail-rotor disc inside the main rotor's "
                f"({-clearance:.3g} m overlap)"]
    return []


def _airfoils(v: dict) -> list[str]:
    out = []
    for name in ("main_rotor", "tail_rotor"):
        segments, cutout = v[name].get("airfoils", ()), v[name]["root_cutout"]
        if segments and segments[0].start > cutout + 1e-12:
            out.append(f"{name}.airfoils: the first segment starts at r/R = {segments[0].start:g}, outboard of the "
                       f"root cut-out {cutout:g}: the blade elements between have no airfoil")
    return out


SPAN_TABLES = {"main_rotor": ("chord_table", "twist_table", "mass_table", "section_inertia_table"),
               "tail_rotor": ("chord_table", "twist_table")}
POSITIVE_COLUMNS = {"chord_table": "the chord", "mass_table": "the mass per length"}


def _distributions(v: dict) -> list[str]:
    """Stations r/R within [0, 1] and increasing; chords and masses positive; a mass table that
    reaches the tip; section inertias only with a mass table."""
    out = []
    for name, keys in SPAN_TABLES.items():
        for key in keys:
            rows = np.asarray(v[name].get(key) or np.zeros((0, 2)), float)
            if not len(rows):
                continue
            r = rows[:, 0]
            if len(r) < 2 or r.min() < 0 or r.max() > 1 or np.any(np.diff(r) <= 0):
                out.append(f"{name}.{key}: the stations r/R ({', '.join(f'{x:g}' for x in r)}) must be at least two, "
                           "increasing, within 0..1")
            elif key in POSITIVE_COLUMNS and rows[:, 1].min() <= 0:
                out.append(f"{name}.{key}: {POSITIVE_COLUMNS[key]} {rows[:, 1].min():g} at r/R = "
                           f"{r[np.argmin(rows[:, 1])]:g} is not positive")
            elif key == "mass_table" and r[-1] != 1.0:
                out.append(f"{name}.mass_table: the last station is r/R = {r[-1]:g}; give the mass up to the tip, "
                           "r/R = 1")
    for name in SPAN_TABLES:
        if v[name]["sweep_start"] != 1.0 and not v[name]["tip_sweep"]:
            out.append(f"{name}.sweep_start: {v[name]['sweep_start']:g} starts a tip sweep of 0 deg; give "
                       f"{name}.tip_sweep or leave sweep_start out")
    mr = v["main_rotor"]
    if mr.get("section_inertia_table") and not mr.get("mass_table"):
        out.append("main_rotor.section_inertia_table: applies with main_rotor.mass_table only (the blade without a "
                   "mass table is the uniform box of I_flap)")
    return out


def rotor_masses(v: dict) -> tuple[float, float]:
    """Masses (kg) of the main rotor (hub and blades) and of the tail rotor (hub, seesaw, blades)."""
    mr, tr = v["main_rotor"], v["tail_rotor"]
    seesaw = tr.get("seesaw_mass", 0.0) if tr["hub_type"] == "teetering" else 0.0
    return (mr["hub_mass"] + mr["n_blades"] * mr["blade_mass"],
            tr["hub_mass"] + seesaw + tr["n_blades"] * tr["blade_mass"])


def _airframe_mass(v: dict) -> list[str]:
    main, tail = rotor_masses(v)
    left = v["aircraft"]["mass"] - main - tail
    if left <= 0:
        return [f"aircraft.mass: {v['aircraft']['mass']:g} kg leaves {left:.4g} kg for the airframe after the "
                f"rotors' {main + tail:.4g} kg"]
    return []


def _tip_mach(v: dict) -> list[str]:
    out = []
    for name, speed in (("main_rotor", 1.0), ("tail_rotor", v["tail_rotor"]["gear_ratio"])):
        mach = speed * v["main_rotor"]["omega"] * v[name]["radius"] / v["environment"]["speed_of_sound"]
        if mach >= 0.95:
            out.append(f"{name}.radius: tip Mach number {mach:.3f} in hover (tip speed over "
                       "environment.speed_of_sound): the blade-element model needs subsonic tips (< 0.95)")
    return out


def rotor_period(gear_ratio: float, tail_blades: int = 1) -> tuple[int, bool]:
    """Main-rotor revolutions after which both rotors are back in place (a tail rotor of
    ``tail_blades`` identical blades without states of their own repeats after ``1/tail_blades``
    of its revolution), and whether that period is exact (a ratio with denominator <= 1000)."""
    turns = gear_ratio * tail_blades
    ratio = Fraction(turns).limit_denominator(1000)
    return ratio.denominator, abs(float(ratio) - turns) <= 1e-9 * turns


def tail_blade_symmetry(tr: dict) -> int:
    """Identical tail blades that repeat the rotor's state: all of a rigid hub's, one of a teetering hub."""
    return 1 if tr["hub_type"] == "teetering" else tr["n_blades"]


def period_problem(gear_ratio: float, tail_blades: int = 1) -> str | None:
    """Why ``gear_ratio`` gives no periodic trim within :data:`MAX_PERIOD_REVS`, or None."""
    revs, exact = rotor_period(gear_ratio, tail_blades)
    if exact and revs <= MAX_PERIOD_REVS:
        return None
    near = Fraction(gear_ratio * tail_blades).limit_denominator(MAX_PERIOD_REVS) / tail_blades
    return (f"tail_rotor.gear_ratio: {gear_ratio:.8g} repeats the rotors' relative position only every "
            f"{revs if exact else 'more than 1000'} main-rotor revolutions, too long for a periodic trim; give a "
            f"ratio with a small denominator, e.g. {float(near):.8g} ({near.numerator}/{near.denominator})")
