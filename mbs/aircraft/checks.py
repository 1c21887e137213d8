"""Physical checks across entries, after each entry is read and within its own bounds.

Each check returns the problems it finds, one line each, naming the entry to change.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from mbs.aircraft.mass import rotor_masses
from mbs.aircraft.performance import profile_drag
from mbs.aircraft.schema import SURFACES

MAX_PERIOD_REVS = 16
"""Longest common period of the rotors (main-rotor revolutions) a periodic analysis shoots over;
a gear ratio that repeats later is replaced there by the nearest one that repeats within it."""

GEAR_TOLERANCE = 1e-4
"""Tail-rotor speed error accepted to shorten the periodic analyses' period (relative)."""


def problems(values: dict) -> list[str]:
    """Every physical problem of the completed ``values`` (defaults and derived values in)."""
    out = []
    from mbs.aircraft.airframe_data import table_problems, tail_problems

    for check in (_inertia, _blades, _controls, _rotor_speed, _tail_hub, _duct, _airframe_mass, _tip_mach,
                  _airframe_inertia, _rigging, _lag_damper, _airfoils, _polars, _distributions, _surface_tables,
                  table_problems, tail_problems, _stabilizer_bar):
        out += check(values)
    return out


def _stabilizer_bar(v: dict) -> list[str]:
    """A stabilizer bar brought round by its paddles or its dampers, whose mixer passes the cyclic on."""
    from mbs.models.helicopter.stabilizer_bar import aero_damping, cyclic_gain, has_stabilizer_bar

    if not has_stabilizer_bar(v):
        return []
    bar = v["stabilizer_bar"]
    if v["main_rotor"]["n_blades"] != 2:
        return [f"stabilizer_bar: on a main rotor of {v['main_rotor']['n_blades']} blades; the model's mixer pitches "
                "two blades, each from the bar's end 90 deg ahead of it (a Bell, Hiller or model helicopter's rotor)"]
    if bar["paddle_area"] > 0 and bar["paddle_lift_slope"] == 0:
        return ["stabilizer_bar.paddle_lift_slope: the paddles (paddle_area "
                f"{bar['paddle_area']:g} m^2) need their lift-curve slope"]
    if bar["time_constant"] and bar["damping"]:
        return ["stabilizer_bar.time_constant: the hinge's damping is derived from it; leave damping out (or give "
                "damping and leave the time constant out)"]
    omega, rho = v["main_rotor"]["omega"], v["environment"]["rho"]
    if bar["time_constant"] and 2 * bar["inertia"] / bar["time_constant"] < aero_damping(bar, omega, rho):
        return [f"stabilizer_bar.time_constant: {bar['time_constant']:g} s, while the paddles alone damp the bar in "
                f"{2 * bar['inertia'] / aero_damping(bar, omega, rho):.4g} s (its hinge would need negative damping): "
                "check the time constant, the inertia and the paddles"]
    if bar["paddle_area"] == 0 and bar["damping"] == 0 and not bar["time_constant"]:
        return ["stabilizer_bar: neither paddles (paddle_area) nor dampers (damping, or its time_constant): nothing "
                "brings the bar round to the shaft; give the one it has"]
    gain = cyclic_gain(bar, omega, rho)
    if gain <= 0:
        entry = "hiller_gain" if bar["paddle_area"] else "bell_gain"  # without paddles the direct path alone
        return [f"stabilizer_bar.{entry}: the blades get {gain:.3g} rad of cyclic per rad of the swashplate's in "
                "hover (bell_gain + hiller_gain x paddle_gain x the paddles' share of the damping; without paddles "
                "bell_gain alone): the cyclic must reach them with a positive gain"]
    return []


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


def _airframe_inertia(v: dict) -> list[str]:
    """A whole-aircraft inertia must leave a positive-definite airframe once the rotors' is subtracted."""
    if v["aircraft"]["inertia"] != "whole-aircraft" or _airframe_mass(v):
        return []
    from mbs.aircraft import mass

    p = np.linalg.eigvalsh(mass.airframe(v).inertia)
    if p[0] > 0:
        return []
    return [f"aircraft.Ixx: the whole-aircraft inertia less the rotors' leaves the airframe principal moments "
            f"{', '.join(f'{x:.4g}' for x in p)} kg m^2 (not positive definite): the rotors carry more inertia "
            "than the aircraft; check the inertias, the blades' mass and I_flap, or set inertia = \"airframe\""]


def inertia_warnings(v: dict) -> list[str]:
    """What is physically doubtful about the airframe's inertia but usable: a whole-aircraft
    inertia that leaves an airframe violating the triangle inequality (the published inertias and
    the blades' data do not belong to one real aircraft)."""
    if v["aircraft"]["inertia"] != "whole-aircraft":
        return []
    from mbs.aircraft import mass

    p = np.linalg.eigvalsh(mass.airframe(v).inertia)
    if p[0] <= 0 or p[0] + p[1] >= p[2] * (1 - 1e-12):
        return []
    return [f"aircraft.inertia: the whole-aircraft inertia less the rotors' leaves airframe principal moments "
            f"{p[0]:.4g}, {p[1]:.4g}, {p[2]:.4g} kg m^2, which violate the triangle inequality by "
            f"{p[2] - p[0] - p[1]:.4g} kg m^2: no real airframe has them, so the published inertias and the blades' "
            "mass and I_flap are not of one aircraft. The model keeps the published total (the aircraft's rigid-body "
            "motion is as published); check the sources"]


ROTOR_INERTIA_SHARE = 0.10
"""Share of an airframe moment that the rotors add, above which an inertia read as the airframe's
by default is warned of."""


def default_inertia_warnings(v) -> list[str]:
    """Inertias read as the airframe's alone only because ``aircraft.inertia`` was left out, to
    which the rotors add more than :data:`ROTOR_INERTIA_SHARE`: most reports print the whole
    aircraft's, and then the rotors would be counted twice."""
    if getattr(v, "meta", {}).get("aircraft", {}).get("inertia", {}).get("origin") != "default":
        return []
    from mbs.aircraft import mass

    given = np.diag(mass.published_inertia(v))
    whole = np.diag(mass.whole_aircraft(v).inertia)
    added = (whole - given) / given
    if added.max() <= ROTOR_INERTIA_SHARE:
        return []
    axes = ", ".join(f"I{a} {100 * x:+.0f} %" for a, x in zip(("xx", "yy", "zz"), added) if x > ROTOR_INERTIA_SHARE)
    return [f"aircraft.inertia: not given, so Ixx, Iyy, Izz are read as the airframe's alone and the rotors are added "
            f"({axes} on the whole aircraft): if the source prints the whole aircraft's inertias (most reports do), "
            "give inertia = \"whole-aircraft\"; if they are the airframe's, give inertia = \"airframe\""]


def lag_damper_figures(v: dict) -> tuple[float, float, float] | None:
    """``(arm, c, c_zeta)`` of a ``[lag_damper]``: its moment arm about the lag hinge at zero lag (m),
    its force curve's slope at rest (N s/m, the natural spline through the rows) and the rotational
    damping it gives the lag hinge there, ``c arm²`` (N m s/rad); None without a damper."""
    ld = v.get("lag_damper", {})
    if not ld.get("force_curve"):
        return None
    from scipy.interpolate import CubicSpline

    e = v["main_rotor"]["flap_hinge_offset"]
    line = np.asarray(ld["blade_point"], dtype=float) - ld["hub_point"]
    lever = np.asarray(ld["blade_point"], dtype=float) - [e, 0.0, 0.0]
    arm = abs(np.cross(lever, line / np.linalg.norm(line))[2])
    rows = np.array(ld["force_curve"], dtype=float)
    slope = float(CubicSpline(rows[:, 0], rows[:, 1], bc_type="natural")(0.0, 1)) if len(rows) > 2 else \
        float((rows[1, 1] - rows[0, 1]) / (rows[1, 0] - rows[0, 0]))
    return float(arm), slope, slope * arm**2


def _lag_damper(v: dict) -> list[str]:
    """A damper's ends apart, its curve's rates increasing."""
    ld = v.get("lag_damper", {})
    if not ld.get("force_curve"):
        return []
    rows = np.array(ld["force_curve"], dtype=float)
    if len(rows) < 2 or np.any(np.diff(rows[:, 0]) <= 0):
        return ["lag_damper.force_curve: give at least two rows with the rate of extension increasing"]
    if np.linalg.norm(np.asarray(ld["blade_point"]) - ld["hub_point"]) < 1e-3:
        return ["lag_damper.blade_point: the damper's two ends coincide; give the hub and blade ends apart"]
    return []


GAIN_DIMS = {"m": (-1, 0, 0, 1), "rad": (0, 0, 0, 0), "-": (0, 0, 0, 1)}
"""The dimensions of a mixing gain (an angle per position) for each kind of control position."""


def _rigging(v: dict) -> list[str]:
    """Each mixing gain is an angle per its own control's position unit; the mixing is invertible."""
    c, meta = v.get("controls", {}), getattr(v, "meta", {}).get("controls", {})
    if "collective_lever" not in c or not meta:
        return []
    from mbs.aircraft import rigging, units
    from mbs.aircraft.units import position_kind

    out = []
    kinds = [position_kind(meta[k]["unit"]) for k in rigging.PILOT]
    for row in rigging.BLADE:
        gains = [u.strip() for u in meta[row]["unit"].split(",")][1:]
        for control, kind, text in zip(rigging.PILOT, kinds, gains):
            if units.parse(text).dims != GAIN_DIMS[kind]:
                out.append(f"controls.{row}: the gain per {control} is in {text!r}, but {control}'s position is "
                           f"in {meta[control]['unit']!r}: give it in deg/{meta[control]['unit']}")
    if not out and abs(np.linalg.det(np.array([c[k] for k in rigging.BLADE])[:, 1:])) < 1e-300:
        out.append("controls.collective: the mixing's gains (4 x 4) are singular: some blade angle combination no "
                   "pilot input reaches, so a trim has no pilot positions; check the rows")
    return out


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
    elif not mr.get("mass_table"):
        out += _blade_body(mr)
    return out + _main_hub_type(v) + _tail_hub_type(v["tail_rotor"]) + _delta3_once(v)


def _delta3_once(v: dict) -> list[str]:
    """A main rotor's pitch-flap coupling given as its skewed hinge and as the swashplate's horn."""
    if v["main_rotor"].get("delta3") and v.get("swashplate", {}).get("delta3"):
        return ["main_rotor.delta3: the swashplate's delta3 is the same coupling, made by its pitch horn: give it "
                "once (main_rotor.delta3 for every scene, or swashplate.delta3 for the swashplate scenes)"]
    return []


def _main_hub_type(v: dict) -> list[str]:
    """A teetering main rotor: two blades on a seesaw on the axis, and none of the sections that
    act on per-blade flap and lag hinges."""
    mr = v["main_rotor"]
    if mr["hub_type"] != "teetering":
        return []
    out = []
    if mr["flap_hinge_offset"] != 0.0:
        out.append(f"main_rotor.flap_hinge_offset: {mr['flap_hinge_offset']:g} m on a teetering hub, whose blades "
                   "start at the teeter hinge on the axis: give 0 (their height below it is undersling)")
    if mr.get("coning_stiffness") and not mr.get("coning_hinge_offset"):
        out.append(f"main_rotor.coning_stiffness: {mr['coning_stiffness']:g} N m/rad does nothing without coning hinges "
                   "(coning_hinge_offset 0): give the hinges' offset, or leave it out")
    if 0.0 < mr.get("coning_hinge_offset", 0.0) < 0.01 * mr["radius"]:
        out.append(f"main_rotor.coning_hinge_offset: {mr['coning_hinge_offset']:g} m is within 1 % of the radius "
                   "of the teeter hinge, which then moves the blades as the coning hinges do: give the hinges' "
                   "offset, or 0 for none")
    if "lag_stiffness" in mr:
        out.append("main_rotor.lag_stiffness: applies only when main_rotor.hub_type = 'flapping' (a teetering "
                   "rotor has no lag hinge); leave it out")
    if v.get("lag_damper", {}).get("force_curve"):
        out.append("[lag_damper]: a lag-damper strut on a teetering main rotor, which has no lag hinge: leave the "
                   "section out, or give hub_type = \"flapping\"")
    return out


def _blade_body(mr: dict) -> list[str]:
    """A blade given by its mass, first moment and flap inertia (:func:`mbs.aircraft.mass.main_blade`):
    its centre of mass on the span, a positive flap inertia about it."""
    from mbs.aircraft.mass import own_flap_inertia

    span, m, first = mr["radius"] - mr["flap_hinge_offset"], mr["blade_mass"], mr["first_moment"]
    given = "from lock_number" if mr.get("lock_number") else "as given"
    if not 0.0 < first / m < span:
        return [f"main_rotor.first_moment: {first:g} kg m puts the blade's centre of mass {first / m:g} m from the "
                f"flap hinge, off the blade (span {span:g} m)"]
    if own_flap_inertia(mr) <= 0.0:
        return [f"main_rotor.blade_mass: {m:g} kg with the first moment {first:g} kg m (centre of mass "
                f"{first / m:.4g} m from the hinge) needs a flap inertia above S^2/m = {first**2 / m:.5g} kg m^2 "
                f"about the hinge, but I_flap is {mr['I_flap']:.5g} kg m^2 ({given}): the blade would have a "
                f"negative inertia about its own centre of mass. Mass, first moment and flap inertia are not of one "
                f"blade: check them (a uniform blade of this I_flap weighs {3 * mr['I_flap'] / span**2:.5g} kg), or "
                f"give a mass_table"]
    return []


def _tail_hub_type(tr: dict) -> list[str]:
    """The tail rotor's hub: two blades on a seesaw, a hinge inside the blade, δ3 only where it flaps."""
    out = []
    if tr["hub_type"] == "flapping" and tr["flap_hinge_offset"] >= tr["root_cutout"] * tr["radius"] + 1e-12:
        out.append(f"tail_rotor.flap_hinge_offset: {tr['flap_hinge_offset']:g} m lies outboard of the aerodynamic "
                   f"root ({tr['root_cutout']:g} R = {tr['root_cutout'] * tr['radius']:g} m): the blade elements "
                   "must start outboard of the hinge")
    if tr["hub_type"] == "rigid" and tr["delta3"] != 0.0:
        out.append(f"tail_rotor.delta3: {math.degrees(tr['delta3']):.4g} deg on a rigid hub, which does not flap: "
                   "pitch-flap coupling needs hub_type = \"teetering\" or \"flapping\" (or delta3 = 0)")
    return out


def main_rotor_notes(mr: dict) -> list[str]:
    """Entries of the main rotor that are valid but act less than they may seem to, or more."""
    if mr["precone"] != 0.0 and mr["flap_stiffness"] == 0.0 and mr["hub_type"] == "flapping":
        return [f"main_rotor.precone: {math.degrees(mr['precone']):.4g} deg without a flap spring does nothing (it "
                "is the spring's rest angle; an articulated blade cones freely): give flap_stiffness, or leave "
                "precone out"]
    return _undersling_note(mr) if mr["hub_type"] == "teetering" else []


UNDERSLING_SLACK = 0.05
"""m: an undersling more than twice the balancing one and this much is warned of."""


def _undersling_note(mr: dict) -> list[str]:
    """An undersling far below the one that puts the coned blades' centre of mass at the teeter
    hinge, ``x_cg sin(precone)`` (the UH-1H's 0.176 m is its 3.7 m and 2.75 deg)."""
    balance = mr["first_moment"] / mr["blade_mass"] * math.sin(mr["precone"])
    if mr["undersling"] <= 2 * balance + UNDERSLING_SLACK or mr.get("coning_hinge_offset"):
        return []  # blades on coning hinges cone with the thrust, not at the precone: no balance to name
    return [f"main_rotor.undersling: {mr['undersling']:.4g} m puts the blades' centre of mass "
            f"{mr['undersling'] - balance:.3g} m below the teeter hinge, where {balance:.3g} m (x_cg sin(precone)) "
            "would put it at the hinge: check the value (the blades' roots below the hinge, in m)"]


SECTION_SLOPE = 5.0
"""1/rad: a tail surface's lift-curve slope from which it reads as a section's (2-D) slope: a surface
of aspect ratio 6 has 4.5 by Helmbold's formula with a section's 2 pi."""


def surface_slope_notes(v: dict) -> list[str]:
    """Surfaces whose ``lift_slope`` (the whole surface's) reads as a section's."""
    out = []
    for section in SURFACES:
        sec = v.get(section, {})
        slope = sec.get("lift_slope")
        if slope is None or sec.get("aspect_ratio") or sec.get("coefficient_table") or slope < SECTION_SLOPE:
            continue
        out.append(f"{section}.lift_slope: {slope:.4g} 1/rad reads as a section's (2-D) slope, and the model takes it "
                   "as the whole surface's, which is less by its aspect ratio (2 pi becomes 4.5 at aspect ratio 6, "
                   "2.4 at 1.8): give aspect_ratio to have a section's converted; a surface's as measured stays as "
                   "it is")
    return out


def station_convention_notes(d) -> list[str]:
    """Conventions of the file's stations (:data:`mbs.aircraft.stations.POSITIVE`) set away from
    their usual sense in a file that gives no position as a station: they change nothing."""
    from mbs.aircraft.stations import POSITIVE

    conventions = d.get("conventions", {})
    turned = [key for key, usual in POSITIVE.values() if conventions.get(key, usual) != usual]
    used = len(d["fuselage_aero"].get("reference_station", ())) or any(
        str(meta.get("how", "")).startswith("from station") for entries in d.meta.values() for meta in entries.values())
    if not turned or used:
        return []
    return [f"conventions.{key}: no position is given as a station, so it changes nothing: give the positions as "
            "stations ({ station = ..., unit = ..., source = ... } with aircraft.cg_station), or leave it out"
            for key in turned]


def control_range_notes(d) -> list[str]:
    """The control ranges, which are the model's (root collective, θ1c/θ1s, anti-torque tail
    pitch), as the file's conventions state published angles, when those differ: a range copied
    from a report in its own conventions then shows as not the report's."""
    from mbs.aircraft import rigging

    conv = rigging.conventions(d)
    if conv == rigging.Conventions():
        return []
    out = []
    for key, (section, entry) in (("collective", ("main_rotor", "collective")),
                                  ("lateral_cyclic", ("main_rotor", "lateral_cyclic")),
                                  ("longitudinal_cyclic", ("main_rotor", "longitudinal_cyclic")),
                                  ("tail_collective", ("tail_rotor", "collective"))):
        low, high = d[section][f"{entry}_min"], d[section][f"{entry}_max"]
        ends = sorted(conv.to_published({key: v})[key] for v in (low, high))
        if ends != [low, high]:
            out.append(f"{section}.{entry}_min, _max: the model's {key} range {math.degrees(low):.4g} to "
                       f"{math.degrees(high):.4g} deg is {math.degrees(ends[0]):.4g} to {math.degrees(ends[1]):.4g} deg "
                       "in the file's [conventions] (published angles): the ranges are given as the model's "
                       "(collective at the root, theta_1c/theta_1s, anti-torque tail pitch); check them against "
                       "the report's")
    return out


COEFFICIENT_SIZE = 3.0
"""A tail surface's lift or drag coefficient beyond which the check warns (a flat plate's c_D at
90 deg is about 2; a table in per cent read as numbers is a hundred times too large)."""


def surface_coefficient_notes(d) -> list[str]:
    """A surface's coefficient table with a lift or drag coefficient no surface has, or a
    negative drag: a per-cent table read as numbers, or a sign."""
    out = []
    for section in SURFACES:
        rows = np.asarray((d.get(section) or {}).get("coefficient_table") or np.zeros((0, 3)), float)
        if not len(rows):
            continue
        cl, cd = np.abs(rows[:, 1]).max(), rows[:, 2]
        if cl > COEFFICIENT_SIZE or cd.max() > COEFFICIENT_SIZE:
            out.append(f"{section}.coefficient_table: c_L up to {cl:.4g} and c_D up to {cd.max():.4g}, beyond what "
                       f"surfaces have (about {COEFFICIENT_SIZE:g} at most): check the columns' unit (% or -)")
        if cd.min() < 0:
            out.append(f"{section}.coefficient_table: c_D {cd.min():.4g} at {np.degrees(rows[np.argmin(cd), 0]):.4g} "
                       "deg is negative: a drag that pushes forward; check the table (or the law's fit)")
    return out


def no_horizontal_tail_note(d) -> list[str]:
    """A file without ``[horizontal_tail]``: the aircraft flies without one (said, since a section
    left out by mistake would fly the same)."""
    from mbs.aircraft.airframe_data import has_horizontal_tail

    if has_horizontal_tail(d):
        return []
    return ["horizontal_tail: the file has no [horizontal_tail], so the aircraft flies without one (as an S-51 or "
            "an R-4 did): its pitch is held by the rotor and the fuselage alone; give the section if it has one"]


def stabilator_notes(d) -> list[str]:
    """A horizontal tail's fixed incidence in a file whose stabilator schedule sets it, and a
    stabilator convention in a file without one: they change nothing."""
    from mbs.aircraft.airframe_data import has_stabilator

    origin = d.meta.get("horizontal_tail", {}).get("incidence", {}).get("origin")
    out = []
    if has_stabilator(d) and origin in ("file", "override"):
        out.append(f"horizontal_tail.incidence: {math.degrees(d['horizontal_tail']['incidence']):.4g} deg is not used: "
                   "the [stabilator] schedule sets the tail's incidence; leave it out")
    table = (d.get("stabilator") or {}).get("incidence_table")
    if table and has_stabilator(d):
        from mbs.aircraft.airframe_data import schedule_collective

        try:
            rows = schedule_collective(d)
        except ValueError:
            rows = []  # a problem of the file's already
        low, high = d["main_rotor"]["collective_min"], d["main_rotor"]["collective_max"]
        if rows and (rows[0] < low or rows[-1] > high):
            out.append(f"stabilator.incidence_table: its collectives {np.degrees(rows[0]):.4g} to "
                       f"{np.degrees(rows[-1]):.4g} deg reach beyond the collective's range {np.degrees(low):.4g} to "
                       f"{np.degrees(high):.4g} deg (main_rotor.collective_min, _max): check the rows' unit")
    if not has_stabilator(d) and d.get("conventions", {}).get("stabilator_positive", "leading edge up") != \
            "leading edge up":
        out.append("conventions.stabilator_positive: the file has no [stabilator], so it changes nothing; leave it out")
    return out


def tail_rotor_notes(tr: dict) -> list[str]:
    """Entries of the tail rotor that are valid but act less than they may seem to."""
    if tr["hub_type"] == "flapping" and tr["precone"] != 0.0 and tr["flap_stiffness"] == 0.0:
        return [f"tail_rotor.precone: {math.degrees(tr['precone']):.4g} deg on a flapping hub without a flap spring "
                "does nothing (it is the spring's rest angle): give flap_stiffness, or leave precone out"]
    return []


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


def _duct(v: dict) -> list[str]:
    """A fan-in-fin's duct exit ratio: 0 (open) or within :data:`mbs.aero.inflow.DUCT_EXIT_RATIO`."""
    from mbs.aero.inflow import DUCT_EXIT_RATIO

    ratio, (low, high) = v["tail_rotor"]["duct_exit_ratio"], DUCT_EXIT_RATIO
    if ratio == 0.0 or low <= ratio <= high:
        return []
    return [f"tail_rotor.duct_exit_ratio: {ratio:g} below {low:g}: the duct would pull against the fan in hover "
            f"(it carries 2 sigma_d - 1 times the fan's thrust); give the exit over the disc area, {low:g} to "
            f"{high:g}, or 0 for an open rotor"]


def _tail_hub(v: dict) -> list[str]:
    """The tail-rotor hub inside the main rotor's disc (in plan view, within a tail radius of its
    height): surely a wrong position."""
    mr, tr = v["main_rotor"], v["tail_rotor"]
    if abs(mr["hub_x"] - tr["hub_x"]) < mr["radius"] and abs(tr["hub_z"] - mr["hub_z"]) < tr["radius"]:
        return [f"tail_rotor.hub_x: {tr['hub_x']:g} m puts the tail-rotor hub under the main rotor's disc "
                f"({abs(mr['hub_x'] - tr['hub_x']):.4g} m from the main-rotor shaft, radius {mr['radius']:g} m): check "
                "the position and its sign (x forward from the CG)"]
    return []


def tail_clearance_note(v: dict) -> list[str]:
    """The discs overlapping in plan view at the main rotor's hub plane (the tail disc's half-width
    there ``sqrt(R_t² − Δz²)``), as on aircraft whose blades clear only by coning and height: the
    model flies them (it has no blade collision), so this is a warning."""
    mr, tr = v["main_rotor"], v["tail_rotor"]
    dz, dx = abs(tr["hub_z"] - mr["hub_z"]), abs(mr["hub_x"] - tr["hub_x"])
    if dz >= tr["radius"] or dx < mr["radius"]:
        return []
    overlap = mr["radius"] + math.sqrt(tr["radius"] ** 2 - dz**2) - dx
    if overlap <= 0:
        return []
    return [f"tail_rotor.hub_x: the tail-rotor disc overlaps the main rotor's by {overlap:.3g} m in plan view at the "
            f"main-rotor hub's height ({dz:.3g} m from the tail hub's): the blades clear only by coning, flapping or "
            "height, which the model does not check (it has no blade collision); check the position if it is not "
            "the aircraft's"]


def _polars(v: dict) -> list[str]:
    """An analytic section's drag polar ``cd0 + cd1 α + cd2 α²`` positive over ±alpha_stall."""
    out = []
    for name in ("main_rotor", "tail_rotor", *SURFACES):
        sec = v.get(name, {})
        if "cd0" not in sec or sec.get("coefficient_table") or sec.get("airfoils"):
            continue
        alpha = np.linspace(-sec["alpha_stall"], sec["alpha_stall"], 401)
        cd = profile_drag(sec, alpha)
        if cd.min() <= 0:
            at = alpha[np.argmin(cd)]
            out.append(f"{name}: the drag polar cd0 + cd1 alpha + cd2 alpha^2 = {cd.min():.4g} at alpha = "
                       f"{np.degrees(at):.2f} deg, within the stall angle {np.degrees(sec['alpha_stall']):.2f} deg: "
                       "a section drag must stay positive; check cd1 and cd2 (or the fit's range of alpha)")
    return out


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


def _surface_tables(v: dict) -> list[str]:
    """A surface's coefficient table: two rows or more, the angles increasing within ±90 deg."""
    out = []
    for section in SURFACES:
        rows = np.asarray(v.get(section, {}).get("coefficient_table") or np.zeros((0, 3)), float)
        if not len(rows):
            continue
        alpha, where = rows[:, 0], f"{section}.coefficient_table"
        degrees = np.degrees(alpha)
        if len(alpha) < 2:
            out.append(f"{where}: one row; give at least two angles of attack")
        elif np.any(np.diff(alpha) <= 0):
            k = int(np.argmax(np.diff(alpha) <= 0))
            out.append(f"{where}: the angles of attack must increase; row {k + 2} ({degrees[k + 1]:.4g} deg) follows "
                       f"row {k + 1} ({degrees[k]:.4g} deg)")
        elif np.abs(alpha).max() > np.pi / 2 + 1e-12 and not _full_circle(rows):
            out.append(f"{where}: angles of attack {degrees[0]:.4g} to {degrees[-1]:.4g} deg; give them within "
                       "-90..90 deg (flow from the trailing edge is folded onto that range), or over the full "
                       "circle from -180 to 180 deg with the same c_L and c_D at both ends")
    return out


def _full_circle(rows: np.ndarray) -> bool:
    """A coefficient table from -180 to 180 deg that closes (its first and last rows' c_L, c_D equal)."""
    return (abs(rows[0, 0] + np.pi) < 1e-9 and abs(rows[-1, 0] - np.pi) < 1e-9
            and np.allclose(rows[0, 1:], rows[-1, 1:], rtol=0.0, atol=1e-12))


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
    if mr.get("lock_number") and mr.get("mass_table"):
        out.append("main_rotor.lock_number: the mass table gives the flap inertia (and so the Lock number); give one "
                   "of lock_number and mass_table")
    if mr.get("section_inertia_table") and not mr.get("mass_table"):
        out.append("main_rotor.section_inertia_table: applies with main_rotor.mass_table only (the blade without a "
                   "mass table is the uniform box of I_flap)")
    return out


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
    ``tail_blades`` identical blades repeats after ``1/tail_blades`` of its revolution, its
    blades' own states exchanged), and whether that period is exact (a ratio with denominator
    <= 1000)."""
    turns = gear_ratio * tail_blades
    ratio = Fraction(turns).limit_denominator(1000)
    return ratio.denominator, abs(float(ratio) - turns) <= 1e-9 * turns


def tail_blade_symmetry(tr: dict) -> int:
    """Identical tail blades that repeat the rotor's state: all of a rigid or flapping hub's (a
    flapping hub's blades exchanging their states), one of a teetering hub."""
    return 1 if tr["hub_type"] == "teetering" else tr["n_blades"]


@dataclass(frozen=True)
class PeriodicGear:
    """The tail-rotor gear ratio of the periodic analyses (trim, Floquet, derivatives, loads).

    ratio: the aircraft's; used: the ratio the analyses' model turns at, ``ratio`` itself when
    the rotors repeat within :data:`MAX_PERIOD_REVS` main-rotor revolutions, otherwise the
    nearest ratio that does (the smallest period whose tail-rotor speed is within
    :data:`GEAR_TOLERANCE`, else the closest within the bound); revs: its period in main-rotor
    revolutions; exact_revs: the aircraft ratio's own period (None beyond 1000 revolutions)."""

    ratio: float
    used: float
    revs: int
    exact_revs: int | None

    @property
    def exact(self) -> bool:
        return self.used == self.ratio

    @property
    def speed_error(self) -> float:
        """Relative tail-rotor speed error of the analyses' model, ``used / ratio - 1``."""
        return self.used / self.ratio - 1.0

    def text(self) -> str:
        """One line: which ratio the periodic analyses use, its period and speed error."""
        if self.exact:
            return (f"tail-rotor gear ratio {self.ratio:.8g}: the rotors repeat after {self.revs} main-rotor "
                    f"revolution{'s' if self.revs > 1 else ''}")
        own = f"{self.exact_revs}" if self.exact_revs else "more than 1000"
        return (f"tail-rotor gear ratio {self.ratio:.8g} repeats the rotors only every {own} main-rotor revolutions; "
                f"the periodic analyses turn the tail rotor at {self.used:.8g} instead (period {self.revs} "
                f"revolutions, tail-rotor speed {100 * self.speed_error:+.4f} %)")


def periodic_gear(gear_ratio: float, tail_blades: int = 1, max_revs: int = MAX_PERIOD_REVS) -> PeriodicGear:
    """The gear ratio of the periodic analyses for ``gear_ratio`` and ``tail_blades`` identical
    blades (:func:`tail_blade_symmetry`) with a period of at most ``max_revs``."""
    revs, exact = rotor_period(gear_ratio, tail_blades)
    if exact and revs <= max_revs:
        return PeriodicGear(gear_ratio, gear_ratio, revs, revs)
    turns = gear_ratio * tail_blades
    near = [(abs(round(turns * q) / (turns * q) - 1), q) for q in range(1, max_revs + 1)]
    q = next((q for err, q in near if err <= GEAR_TOLERANCE), min(near)[1])
    return PeriodicGear(gear_ratio, round(turns * q) / q / tail_blades, q, revs if exact else None)
