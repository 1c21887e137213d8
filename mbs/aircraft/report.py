"""``heli aircraft check``: an aircraft file's problems, warnings, derived values and figures."""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from mbs.aircraft import checks, derived, performance
from mbs.aircraft._aircraft import AircraftError, Data, _text, evaluate, resolve
from mbs.aircraft.schema import DERIVED, FROM_TABLES

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

    @property
    def ok(self) -> bool:
        return not self.problems

    def summary(self) -> dict:
        return {"file": str(self.path), "name": self.name, "ok": self.ok, "problems": self.problems,
                "warnings": self.warnings,
                "derived": [{"entry": e, "value": v, "unit": u, "how": h} for e, v, u, h in self.derived],
                "figures": {n: {"value": v, "unit": u} for n, v, u in self.figures}}


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
    out += _unused_with_tables(data)
    tr = data["tail_rotor"]
    period = checks.period_problem(tr["gear_ratio"], checks.tail_blade_symmetry(tr))
    if period:
        out.append(period + " (simulations run; trim, Floquet and derivatives refuse it)")
    return out


def _unused_with_tables(data: Data) -> list[str]:
    """The analytic-section entries that a rotor with airfoil tables keeps only for estimates."""
    return [f"{section}.airfoils: the blade elements use the tables; lift_slope, cd0, cd2, alpha_stall and "
            f"cd_stalled serve the trim estimate, Lock number and performance figures only, and mach_dd and "
            f"mach_limit nothing (the tables carry the Mach dependence)"
            for section in ("main_rotor", "tail_rotor") if data[section].get("airfoils")]


def figures(data: Data) -> list[tuple]:
    """Rotor solidity, Lock number, frequencies, disc loading, tip Mach numbers and the hover
    power estimate (:mod:`mbs.aircraft.performance`)."""
    mr, tr, env = data["main_rotor"], data["tail_rotor"], data["environment"]
    hov = performance.hover(data)
    main_mass, tail_mass = checks.rotor_masses(data)
    revs = checks.rotor_period(tr["gear_ratio"], checks.tail_blade_symmetry(tr))[0]
    return [*airfoil_rows(data),
        ("main-rotor solidity", hov.main.solidity, "-"), ("tail-rotor solidity", hov.tail.solidity, "-"),
        ("Lock number", performance.lock_number(mr, env["rho"]), "-"),
        ("flap frequency", derived.flap_frequency(mr), "1/rev"), ("lag frequency", mr["lag_frequency"], "1/rev"),
        ("disc loading", hov.main.disc_loading, "N/m^2"),
        ("main-rotor tip speed", hov.main.tip_speed, "m/s"),
        ("main-rotor tip Mach number", hov.main.tip_speed / env["speed_of_sound"], "-"),
        ("tail-rotor tip Mach number", hov.tail.tip_speed / env["speed_of_sound"], "-"),
        ("hover thrust coefficient C_T", hov.main.thrust_coefficient, "-"),
        ("hover blade loading C_T/sigma", hov.main.blade_loading, "-"),
        ("hover induced velocity", hov.main.induced_velocity, "m/s"),
        ("hover power estimate, main rotor", hov.main.power, "W"),
        ("hover power estimate, tail rotor", hov.tail.power, "W"),
        ("hover power estimate, total", hov.power, "W"),
        ("hover tail-rotor thrust", hov.tail.thrust, "N"),
        ("main-rotor mass (hub and blades)", main_mass, "kg"), ("tail-rotor mass", tail_mass, "kg"),
        ("airframe mass", data["aircraft"]["mass"] - main_mass - tail_mass, "kg"),
        ("rotor period (both rotors back in place)", revs, "rev"),
        ("main-rotor revolution", 2 * math.pi / mr["omega"], "s"),
    ]


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
    return out + [f"  warning: {w}" for w in report.warnings]


def _fmt(v) -> str:
    return f"{v:.6g}" if isinstance(v, float) else str(v)
