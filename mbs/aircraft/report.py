"""``heli aircraft check``: an aircraft file's problems, warnings, derived values and figures."""
from __future__ import annotations

import math

import numpy as np
from dataclasses import dataclass, field
from pathlib import Path

from mbs.aircraft import airframe_data, checks, derived, mass, performance
from mbs.aircraft._aircraft import AircraftError, Data, _text, evaluate, resolve
from mbs.aircraft.schema import DERIVED, FROM_TABLES
from mbs.aircraft.reader import printed

TEMPLATE_SOURCE = "TEMPLATE"
OVERRIDE_TOLERANCE = 0.01  # relative difference of an override from its derived value that is worth a warning


@dataclass
class Report:
    """What :func:`check` finds: ``problems`` (the file cannot be used), ``warnings`` (it can,
    but look), ``derived`` rows ``(entry, value, unit, how)`` and ``figures`` rows
    ``(name, value, unit)``; SI units."""

    path: Path
    name: str = ""
    problems: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    derived: list[tuple] = field(default_factory=list)
    figures: list[tuple] = field(default_factory=list)
    converted: list[tuple] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return not self.problems

    def summary(self) -> dict:
        return {"file": str(self.path), "name": self.name, "ok": self.ok, "problems": self.problems,
                "warnings": self.warnings,
                "derived": [{"entry": e, "value": v, "unit": u, "how": h} for e, v, u, h in self.derived],
                "figures": {n: {"value": v, "unit": u} for n, v, u in self.figures},
                "converted": [{"entry": e, "value": v, "unit": u, "how": h, "source": s}
                              for e, v, u, h, s in self.converted]}


def check(source) -> Report:
    """Every problem of the aircraft file ``source`` (a packaged name or a path), never raising
    for the file's content; with none, its derived values and hover figures."""
    try:
        path = resolve(source)
        text = _text(path)
    except AircraftError as exc:
        return Report(exc.path, problems=exc.problems)
    data, problems = evaluate(text, path.parent)
    report = Report(path, str(data.get("aircraft", {}).get("name", "")), problems)
    if not problems:
        report.derived = _derived_rows(data)
        report.figures = figures(data)
        report.warnings = _warnings(data, report.derived)
        report.converted = converted_rows(data) + airframe_data.converted(data)
    return report


def _derived_rows(data: Data) -> list[tuple]:
    rows = []
    for section in [*DERIVED, *(s for s in FROM_TABLES if s not in DERIVED)]:
        entries = {**DERIVED.get(section, {}), **{k: v for k, v in FROM_TABLES.get(section, {}).items()
                                                  if data.meta.get(section, {}).get(k, {}).get("origin") == "derived"}}
        for key, spec in entries.items():
            if key not in data.get(section, {}):
                continue
            how = "overridden in the file" if data.meta[section][key]["origin"] == "override" else spec.text
            rows.append((f"{section}.{key}", data[section][key], spec.unit, how))
    return rows


def converted_rows(data: Data) -> list[tuple]:
    """Rows ``(entry, value, unit, how, source)`` of the entries converted on loading: units to SI
    (``in`` to m, ``deg`` to rad, ``slug ft^2`` to kg m^2 ...) and a whole-aircraft inertia to the
    airframe's (the tables' conversions: :func:`mbs.aircraft.airframe_data.converted`)."""
    from mbs.aircraft.schema import ENTRIES

    rows = []
    for section, entries in data.meta.items():
        for key, meta in entries.items():
            spec = ENTRIES.get(section, {}).get(key) or DERIVED.get(section, {}).get(key)  # an override: DERIVED
            written = str(meta.get("unit", ""))
            kind = getattr(spec, "kind", "number")  # tables (lookup) are listed by airframe_data.converted
            if meta.get("origin") not in ("file", "override") or spec is None or kind in ("text", "choice", "lookup"):
                continue
            plain = written.replace(" ", "") == spec.unit.replace(" ", "") or written in ("-", "1", "")
            if plain and "how" not in meta:
                continue
            unit = {"travel": "m, rad or -", "mixing": "rad, rad per position"}.get(kind, spec.unit)
            how = meta.get("how") or f"from {printed(meta)}" + _how_read(written, spec)
            rows.append((f"{section}.{key}", data[section][key], unit, how, meta.get("source", "")))
    return rows + _inertia_conversion(data)


def _how_read(written: str, spec) -> str:
    """What the check says of a unit read with ``lb`` as the pound-force or ``A/B/C`` as
    ``A/(B/C)`` (per column of a table)."""
    from mbs.aircraft import units

    pairs = zip(written.split(","), spec.columns) if getattr(spec, "kind", "") == "table" else [(written, spec.unit)]
    try:
        return "".join(dict.fromkeys(units.how_read(w.strip(), u) for w, u in pairs))
    except units.UnitError:
        return ""


def _inertia_conversion(data: Data) -> list[tuple]:
    """A whole-aircraft inertia becomes the airframe's (about its own centre of mass)."""
    if data["aircraft"]["inertia"] != "whole-aircraft":
        return []
    from mbs.aircraft import mass

    frame = mass.airframe(data).inertia
    return [(f"aircraft.{n}", float(s * frame[i, j]), "kg m^2",
             f"the airframe's about its centre of mass: the whole aircraft's {data['aircraft'][n]:.6g} kg m^2 about "
             "the CG less the rotors' hubs and blades (averaged over a revolution)", data.meta["aircraft"][n]["source"])
            for n, i, j, s in (("Ixx", 0, 0, 1), ("Iyy", 1, 1, 1), ("Izz", 2, 2, 1), ("Ixz", 0, 2, -1))]


def _recomputed(data: Data, entry: str) -> float | None:
    """The derived value of an overridden ``entry`` as the formula gives it."""
    section, key = entry.split(".")
    fresh = Data({s: {k: v for k, v in e.items() if not (s == section and k == key)} for s, e in data.items()})
    derived.complete(fresh)
    return fresh.get(section, {}).get(key)


def _warnings(data: Data, rows: list[tuple]) -> list[str]:
    out = []
    for entry, value, unit, how in rows:
        if how.startswith("overridden"):
            fresh = _recomputed(data, entry)
            if fresh and abs(value / fresh - 1) > OVERRIDE_TOLERANCE:
                out.append(f"{entry}: the override {value:.6g} {unit} differs by {100 * (value / fresh - 1):+.1f} % "
                           f"from the derived {fresh:.6g} {unit}; remove the override unless it is meant")
    template = [f"{s}.{k}" for s, m in data.meta.items() for k, e in m.items() if e.get("source") == TEMPLATE_SOURCE]
    if template:
        out.append(f"{len(template)} entries still carry the template's Bo105 values (source {TEMPLATE_SOURCE}), "
                   f"e.g. {', '.join(template[:3])}: replace them with your aircraft's data and sources")
    out += checks.inertia_warnings(data) + checks.default_inertia_warnings(data)
    damper = checks.lag_damper_figures(data)
    if damper and data["main_rotor"].get("lag_damping", 0.0) > 0:
        out.append(f"main_rotor.lag_damping: {data['main_rotor']['lag_damping']:g} N m s/rad on the lag hinge as well as "
                   f"the [lag_damper] strut ({damper[2]:.4g} N m s/rad at rest): both act; set lag_damping to the "
                   "blade's structural damping only (or 0)")
    out += _unused_with_tables(data)
    tr = data["tail_rotor"]
    out += checks.main_rotor_notes(data["main_rotor"]) + checks.tail_rotor_notes(tr)
    out += checks.tail_clearance_note(data) + checks.surface_slope_notes(data) + _drag_area_note(data)
    out += _hub_drag_note(data) + _accessory_note(data)
    out += checks.station_convention_notes(data) + checks.stabilator_notes(data) + checks.control_range_notes(data)
    out += checks.no_horizontal_tail_note(data) + checks.surface_coefficient_notes(data)
    gear = checks.periodic_gear(tr["gear_ratio"], checks.tail_blade_symmetry(tr))
    if not gear.exact:
        out.append(f"tail_rotor.gear_ratio: {gear.text()}; simulations keep {gear.ratio:.8g}")
    return out


DRAG_AREA_SHARE = 0.04
"""Fuselage drag area per main-rotor disc area beyond which the check warns: helicopters have
about 0.008-0.02 (the shipped Bo105 0.0135, Puma 0.0082, Lynx 0.0135)."""
SMALL = (2.0, 0.1)
"""Below this main-rotor radius (m), the share beyond which the check warns: a small unmanned
helicopter's fuselage is large for its rotor (Gavrilets et al.'s X-Cell 60: 0.1 m^2 frontal area
on a 0.775 m rotor, 0.053), and ft^2 read as m^2 still lands past it (ten times)."""


def _drag_area_note(data: Data) -> list[str]:
    """A fuselage whose drag at zero angles is no helicopter's: more than :data:`DRAG_AREA_SHARE`
    of the disc area (:data:`SMALL` for a small rotor; a table in ft² read as m²: ten times), or
    not a drag."""
    f, radius = airframe_data.drag_area(data), data["main_rotor"]["radius"]
    share = f / (math.pi * radius**2)
    limit, who = (SMALL[1], "small unmanned helicopters up to about 0.06") if radius < SMALL[0] else (
        DRAG_AREA_SHARE, "helicopters about 0.008-0.02")
    if 0.0 < share <= limit:
        return []
    what = "is not a drag (it pushes forward)" if f <= 0 else (
        f"is {share:.3g} of the main rotor's disc area, where {who} (above {limit:g} this check warns)")
    return [f"fuselage_aero: the drag area at zero angle of attack and sideslip, {f:.4g} m^2, {what}: check the "
            "tables' or polynomials' unit (ft^2 or m^2, N at v_ref) and their sign"]


def _hub_drag_note(data: Data) -> list[str]:
    """A hub with more drag than the fuselage (the shipped aircraft's hubs: 0.2-0.4 of it)."""
    hub, f = data["hub_drag"]["flat_plate_area"], airframe_data.drag_area(data)
    if not 0.0 < f < hub:
        return []
    return [f"hub_drag.flat_plate_area: {hub:.4g} m^2, more than the fuselage's drag area at zero angles ({f:.4g} m^2), "
            "where the hubs of the shipped aircraft have 0.2-0.4 of it: check the value (the template's is the Bo105's)"]


def _accessory_note(data: Data) -> list[str]:
    """Accessory power above the rotors' whole hover power."""
    acc, hover = data["engine"]["accessory_power"], performance.hover(data).power
    if acc <= hover:
        return []
    return [f"engine.accessory_power: {acc:.4g} W, more than both rotors' hover power ({hover:.4g} W): check the value "
            "(the template's is the Bo105's)"]


def _unused_with_tables(data: Data) -> list[str]:
    """The analytic-section entries that a rotor with airfoil tables keeps only for estimates."""
    return [f"{section}.airfoils: the blade elements use the tables; lift_slope, cd0, cd1, cd2, alpha_stall, "
            f"cd_stalled and zero_lift_angle serve the trim estimate, Lock number and performance figures only, and "
            f"mach_dd and mach_limit nothing (the tables carry the Mach dependence)"
            for section in ("main_rotor", "tail_rotor") if data[section].get("airfoils")]


def figures(data: Data) -> list[tuple]:
    """Rotor solidity, Lock number, frequencies, disc loading, tip Mach numbers and the hover
    power estimate (:mod:`mbs.aircraft.performance`)."""
    mr, tr, env = data["main_rotor"], data["tail_rotor"], data["environment"]
    hov = performance.hover(data)
    main_mass, tail_mass = mass.rotor_masses(data)
    revs, exact = checks.rotor_period(tr["gear_ratio"], checks.tail_blade_symmetry(tr))
    periods = [("rotor period (both rotors back in place)", revs, "rev")] if exact else []  # beyond 1000: a warning
    return [*airfoil_rows(data),
        ("main-rotor solidity", hov.main.solidity, "-"), ("tail-rotor solidity", hov.tail.solidity, "-"),
        ("Lock number", performance.lock_number(mr, env["rho"]), "-"),
        ("teeter frequency" if mr["hub_type"] == "teetering" else "flap frequency", derived.flap_frequency(mr),
         "1/rev"), *([("lag frequency", mr["lag_frequency"], "1/rev")] if mr["hub_type"] == "flapping" else []),
        ("disc loading", hov.main.disc_loading, "N/m^2"),
        ("main-rotor tip speed", hov.main.tip_speed, "m/s"),
        ("main-rotor tip Mach number", hov.main.tip_speed / env["speed_of_sound"], "-"),
        ("tail-rotor tip Mach number", hov.tail.tip_speed / env["speed_of_sound"], "-"),
        ("hover thrust coefficient C_T", hov.main.thrust_coefficient, "-"),
        ("hover blade loading C_T/sigma", hov.main.blade_loading, "-"),
        ("hover induced velocity", hov.main.induced_velocity, "m/s"),
        ("hover power estimate, main rotor", hov.main.power, "W"),
        ("hover power estimate, tail rotor", hov.tail.power, "W"),
        ("hover power estimate, both rotors", hov.power, "W"),
        ("hover power estimate, engines",
         hov.power / data["engine"]["transmission_efficiency"] + data["engine"]["accessory_power"], "W"),
        ("fuselage drag area at zero angles", airframe_data.drag_area(data), "m^2"),
        ("fuselage drag area per disc area", airframe_data.drag_area(data) / (math.pi * mr["radius"] ** 2), "-"),
        *([("hover tail-rotor thrust", hov.tail.thrust, "N")] if not hov.tail.duct_thrust else [
            ("hover tail-rotor thrust, fan and duct together", hov.tail.thrust + hov.tail.duct_thrust, "N"),
            ("hover tail-rotor thrust, the fan's blades", hov.tail.thrust, "N"),
            ("hover tail-rotor duct thrust", hov.tail.duct_thrust, "N")]),
        ("main-rotor mass (hub and blades" + (", stabilizer bar)" if "hiller_gain" in data.get("stabilizer_bar", {})
                                              else ")"), main_mass, "kg"), ("tail-rotor mass", tail_mass, "kg"),
        ("airframe mass", data["aircraft"]["mass"] - main_mass - tail_mass, "kg"),
        *_inertia_figures(data), *_damper_figures(data),
        *periods,
        ("period of the periodic analyses", checks.periodic_gear(tr["gear_ratio"], checks.tail_blade_symmetry(tr)).revs,
         "rev"),
        *([("tail-rotor flap frequency", derived.tail_flap_frequency(tr, mr["omega"]), "1/rev")]
          if tr["hub_type"] == "flapping" else []),
        ("main-rotor revolution", 2 * math.pi / mr["omega"], "s"),
        *_bar_figures(data),
    ]


def _bar_figures(data: Data) -> list[tuple]:
    from mbs.models.helicopter.stabilizer_bar import (aero_damping, cyclic_gain, has_stabilizer_bar, hinge_damping,
                                                      time_constant)

    if not has_stabilizer_bar(data):
        return []
    bar, omega, rho = data["stabilizer_bar"], data["main_rotor"]["omega"], data["environment"]["rho"]
    paddles = aero_damping(bar, omega, rho)
    return [("stabilizer bar time constant (hover)", time_constant(bar, omega, rho), "s"),
            *([("stabilizer bar paddles' damping", paddles, "N m s/rad"),
               ("stabilizer bar time constant, paddles alone", 2 * bar["inertia"] / paddles, "s")] if paddles else []),
            ("stabilizer bar hinge damping" + (" (from its time constant)" if bar["time_constant"] else ""),
             hinge_damping(bar, omega, rho), "N m s/rad"),
            ("blade cyclic per swashplate cyclic (hover)", cyclic_gain(bar, omega, rho), "-")]


def _damper_figures(data: Data) -> list[tuple]:
    damper = checks.lag_damper_figures(data)
    if damper is None:
        return []
    return [("lag damper arm about the lag hinge", damper[0], "m"), ("lag damper slope at rest", damper[1], "N s/m"),
            ("lag damper as hinge damping at rest", damper[2], "N m s/rad")]


def _inertia_figures(data: Data) -> list[tuple]:
    """The airframe's inertia about its centre of mass and the whole aircraft's about the CG,
    body axes (:mod:`mbs.aircraft.mass`), with the rotors' share."""
    from mbs.aircraft import mass

    frame, whole = mass.airframe(data).inertia, mass.whole_aircraft(data)
    rows = [(f"airframe {n} (about its centre of mass)", float(s * frame[i, j]), "kg m^2")
            for n, i, j, s in (("Ixx", 0, 0, 1), ("Iyy", 1, 1, 1), ("Izz", 2, 2, 1), ("Ixz", 0, 2, -1))]
    rows += [(f"whole-aircraft {n} (about the CG)", float(s * whole.about(np.zeros(3))[i, j]), "kg m^2")
             for n, i, j, s in (("Ixx", 0, 0, 1), ("Iyy", 1, 1, 1), ("Izz", 2, 2, 1), ("Ixz", 0, 2, -1))]
    return rows


def airfoil_rows(data: Data) -> list[tuple]:
    """One figure per airfoil segment: where it starts and what its C81 file holds."""
    return [(f"{section.replace('_', '-')} airfoil from r/R = {seg.start:g}", seg.describe(), "-")
            for section in ("main_rotor", "tail_rotor") for seg in data[section].get("airfoils", ())]


def lines(report: Report) -> list[str]:
    """The human-readable report."""
    if not report.ok:
        return [f"{report.path}: {p}" for p in report.problems]
    out = [f"{report.path}: {report.name}: no problems"]
    out += ["  derived values:"] + [f"    {e:34s} {_fmt(v)} {u}  ({h})" for e, v, u, h in report.derived]
    out += ["  figures:"] + [f"    {n:40s} {_fmt(v)} {u}" for n, v, u in report.figures]
    if report.converted:
        out += ["  converted by the program:"] + [f"    {e:34s} {_brief(v)} {u}  ({h}; source {s})"
                                                  for e, v, u, h, s in report.converted]
    return out + [f"  warning: {w}" for w in report.warnings]


def _brief(v) -> str:
    """A converted table in one line: its range and length (``--json`` gives every value)."""
    if isinstance(v, dict) and "airspeed" in v:  # a schedule in collective and airspeed
        what = "lever fraction" if v["lever"] else "collective (rad)"
        return (f"{what} {min(v['collective']):.6g} .. {max(v['collective']):.6g} ({len(v['collective'])} rows) x "
                f"airspeed {min(v['airspeed']):.6g} .. {max(v['airspeed']):.6g} m/s ({len(v['airspeed'])} columns), "
                f"values {np.min(v['values']):.6g} .. {np.max(v['values']):.6g}; --json lists them")
    if isinstance(v, list) and len(v) > 6:
        if isinstance(v[0], list):  # a table: each column's range
            ranges = ", ".join(f"{min(c):.6g} .. {max(c):.6g}" for c in zip(*v))
            return f"columns {ranges} ({len(v)} rows; --json lists them)"
        return f"{min(v):.6g} .. {max(v):.6g} ({len(v)} values; --json lists them)"
    return _fmt(v)


def _fmt(v) -> str:
    return f"{v + 0.0:.6g}" if isinstance(v, float) else str(v)  # + 0.0: no "-0" of a sign times zero
