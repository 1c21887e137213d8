"""Read an aircraft file into SI values, naming the entry of every problem.

Rules, in the order they are checked (each problem is one line, ``section.key: what``):

1. The file is TOML; a syntax error names its line.
2. Every section and entry is known (:data:`mbs.aircraft.schema.ENTRIES`); a typo names the
   closest known name.
3. Every entry is a table ``{ value, unit, source[, note][, override] }``: no other fields;
   ``source`` says where the value comes from (``EST`` for an estimate). A position from the
   CG may give ``station`` instead of ``value``, with ``aircraft.cg_station``
   (:mod:`mbs.aircraft.stations`). A mixing row may carry a common ``gain`` that multiplies its
   four control gains, as reports print ``offset + K (k1 x1 + ... + k4 x4)``.
4. ``unit`` is given for every number and is of the entry's kind (a length for a radius, an
   angle for a twist): it is converted to SI (``ft``, ``lb``, ``slug ft^2``, ``deg``,
   ``rpm`` ...). A number printed in parts is a list of them with a unit each: 25 ft 2 in is
   ``value = [25, 2], unit = "ft, in"``.
5. The value has the entry's kind (number, whole number, one of the choices, a vector of
   its length, a table of its columns, airfoil segments with their C81 files) and lies
   within its bounds.
6. Required entries are present; an entry that applies only with another's value (the
   seesaw of a teetering tail rotor) is absent otherwise; an entry that a distribution
   replaces (``chord`` by ``chord_table``) is absent when the distribution is given.
7. A derived entry (:data:`mbs.aircraft.schema.DERIVED`) appears only with
   ``override = true``; ``override`` appears only on derived entries.
"""
from __future__ import annotations

import difflib
import math
import re
import sys
from dataclasses import dataclass, field, replace
from pathlib import Path

from mbs.aircraft import stations, units
from mbs.aircraft.schema import DERIVED, ENTRIES, FROM_TABLES, OPTIONAL_SECTIONS, SURFACES, Entry

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

FIELDS = ("value", "unit", "source", "note", "override", "station", "gain", "law")


@dataclass
class Reading:
    """What a file gives: ``values[section][key]`` in SI, ``meta[section][key]`` (unit as
    written, source, note, origin "file" | "override"), and the problems found."""

    values: dict = field(default_factory=dict)
    meta: dict = field(default_factory=dict)
    problems: list[str] = field(default_factory=list)
    stations: list[stations.Given] = field(default_factory=list)
    radial: list[tuple[str, str]] = field(default_factory=list)  # span tables given in radial stations (m)
    radius_columns: list[tuple[str, str, int]] = field(default_factory=list)  # span-table lengths given in R
    surface: list[tuple[str, str, list]] = field(default_factory=list)  # tail tables in L/q or on πR^2

    def put(self, section: str, key: str, value, meta: dict) -> None:
        self.values.setdefault(section, {})[key] = value
        self.meta.setdefault(section, {})[key] = meta


def read(text: str, base: Path | None = None) -> Reading:
    """Parse the TOML ``text`` of an aircraft file (rules 1–7 of this module); files it names
    (C81 airfoil tables) are found from the folder ``base`` (None: the working directory)."""
    out = Reading()
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        out.problems.append(f"not a TOML file: {exc}")
        return out
    for section, entries in raw.items():
        if section not in ENTRIES and section not in DERIVED:
            out.problems.append(f"[{section}]: unknown section{_suggest(section, ENTRIES)}")
        elif not isinstance(entries, dict):
            out.problems.append(f"{section}: must be a section [{section}] of entries")
        else:
            for key, entry in entries.items():
                _entry(out, section, key, entry, base)
    _diameters(out)
    _tip_speeds(out)
    _place_stations(out)
    _radial_stations(out)
    _radius_columns(out)
    _surface_coefficients(out)
    _surface_slopes(out)
    _stabilator_sign(out)
    _laws(out)
    _missing(out, raw)
    _teetering_blades(out)
    return out


STABILATOR_SIGNED = ("incidence", "collective_gain", "pitch_rate_gain", "cyclic_gain")
"""A stabilator's entries whose sign follows conventions.stabilator_positive (and its stops, swapped)."""


def _stabilator_sign(out: Reading) -> None:
    """A stabilator given trailing edge up positive: its incidence, gains and stops in the model's
    leading-edge-up sense (listed as converted)."""
    if out.values.get("conventions", {}).get("stabilator_positive") != "trailing edge up":
        return
    st, meta = out.values.get("stabilator", {}), out.meta.get("stabilator", {})
    for key in STABILATOR_SIGNED:
        if key in st:
            st[key] = [-x for x in st[key]] if isinstance(st[key], list) else -st[key]
            meta[key]["how"] = f"times -1 (conventions.stabilator_positive = 'trailing edge up'): from {meta[key]['value']}"
    if "incidence_min" in st and "incidence_max" in st:
        low, high = st["incidence_min"], st["incidence_max"]
        st["incidence_min"], st["incidence_max"] = -high, -low
        low_meta, high_meta = meta["incidence_min"], meta["incidence_max"]
        meta["incidence_min"] = {**high_meta, "how": f"minus incidence_max as printed, {printed(high_meta)} "
                                                     "(trailing edge up positive)"}
        meta["incidence_max"] = {**low_meta, "how": f"minus incidence_min as printed, {printed(low_meta)} "
                                                    "(trailing edge up positive)"}


BOTH_AS_PRINTED = {("main_rotor", "diameter", "radius"), ("tail_rotor", "diameter", "radius"),
                   ("main_rotor", "tip_speed", "omega"), ("tail_rotor", "tip_speed", "gear_ratio")}
"""Entries a flight manual prints beside the one they replace: both may be given if they agree."""
AGREE = 0.005
"""Two such entries agree within this share."""


def _agree(out: Reading, section: str, given: str, key: str, implied: float) -> None:
    """``section.given``, given beside ``section.key``, implies ``implied`` for it: a problem
    unless the two agree within :data:`AGREE`; when they do, ``given`` is listed as the check it is."""
    value = out.values[section][key]
    if abs(implied - value) > AGREE * abs(value):
        out.problems.append(f"{section}.{given}: gives {section}.{key} = {implied:.6g}, against the file's "
                            f"{value:.6g} ({100 * (implied / value - 1):+.2g} %): give one of the two, or correct one")
        return
    meta, off = out.meta[section][given], round(100 * (implied / value - 1), 3) + 0.0  # no "-0"
    meta["how"] = (f"{printed(meta)}, checked against {section}.{key}: it gives {implied:.6g} against {value:.6g} "
                   f"({off:+.2g} %); the model flies {section}.{key}")


def _diameters(out: Reading) -> None:
    """A rotor's diameter as published: its radius is half of it (listed as converted)."""
    for section in ROTORS:
        v = out.values.get(section, {})
        if v.get("diameter") and "radius" in v:
            _agree(out, section, "diameter", "radius", v["diameter"] / 2)
        elif v.get("diameter"):
            meta = out.meta[section]["diameter"]
            out.put(section, "radius", v["diameter"] / 2,
                    {**meta, "how": f"half the diameter {printed(meta)} ({section}.diameter)"})


def _tip_speeds(out: Reading) -> None:
    """A rotor's tip speed as published: the main rotor's speed, or the tail rotor's gear ratio
    (listed as converted)."""
    mr, tr = out.values.get("main_rotor", {}), out.values.get("tail_rotor", {})
    if mr.get("tip_speed") and mr.get("radius") and "omega" in mr:
        _agree(out, "main_rotor", "tip_speed", "omega", mr["tip_speed"] / mr["radius"])
    if tr.get("tip_speed") and tr.get("radius") and mr.get("omega") and "gear_ratio" in tr:
        _agree(out, "tail_rotor", "tip_speed", "gear_ratio", tr["tip_speed"] / tr["radius"] / mr["omega"])
    if mr.get("tip_speed") and mr.get("radius") and "omega" not in mr:
        meta = out.meta["main_rotor"]["tip_speed"]
        out.put("main_rotor", "omega", mr["tip_speed"] / mr["radius"],
                {**meta, "how": f"main_rotor.tip_speed {printed(meta)} over main_rotor.radius "
                                f"{mr['radius']:.6g} m"})
    if tr.get("tip_speed") and tr.get("radius") and mr.get("omega") and "gear_ratio" not in tr:
        meta = out.meta["tail_rotor"]["tip_speed"]
        out.put("tail_rotor", "gear_ratio", tr["tip_speed"] / tr["radius"] / mr["omega"],
                {**meta, "how": f"tail_rotor.tip_speed {printed(meta)} over tail_rotor.radius "
                                f"{tr['radius']:.6g} m and main_rotor.omega {mr['omega']:.6g} rad/s"})


def _teetering_blades(out: Reading) -> None:
    """A teetering hub of other than two blades: said with the entries it lacks, not after them."""
    for section, more in (("main_rotor", '"flapping"'), ("tail_rotor", '"flapping" or "rigid"')):
        v = out.values.get(section, {})
        if v.get("hub_type") == "teetering" and v.get("n_blades", 2) != 2:
            out.problems.append(f"{section}.n_blades: a teetering {section.replace('_', ' ')} has 2 blades, not "
                                f"{v['n_blades']}; use hub_type = {more} for more")


def _suggest(name: str, known) -> str:
    close = difflib.get_close_matches(name, list(known), n=1)
    return f" (did you mean {close[0]!r}?)" if close else f"; known: {', '.join(known)}"


def _entry(out: Reading, section: str, key: str, entry, base: Path | None = None) -> None:
    where = f"{section}.{key}"
    spec, derived = ENTRIES.get(section, {}).get(key), DERIVED.get(section, {}).get(key)
    if spec is None and derived is None:
        known = [*ENTRIES.get(section, {}), *DERIVED.get(section, {})]
        out.problems.append(f"{where}: unknown entry{_suggest(key, known)}")
        return
    if isinstance(entry, dict) and "station" in entry:
        _station_entry(out, section, key, entry, spec)
        return
    if not isinstance(entry, dict) or "value" not in entry:
        out.problems.append(f"{where}: write it as {{ value = ..., unit = \"...\", source = \"...\" }}")
        return
    problem = _fields(entry) or _override(entry, derived) or _gain(entry, spec) or _law(entry, key, spec)
    if problem:
        out.problems.append(f"{where}: {problem}")
        return
    spec = spec or Entry(derived.unit, derived.text)
    try:
        unit, radial = _radius_unit(section, key, spec, _in_radius_columns(out, section, key, spec, entry.get("unit")))
        bases = [None]
        if key == "coefficient_table" and unit is not None:
            unit, spec, bases = _surface_columns(unit, spec)
        if key == "coefficient_table" and "law" in entry:
            law = entry["value"]
            entry = {**entry, "value": _surface_laws(law, unit),
                     "printed": f"c_L = {law['lift']}, c_D = {law['drag']} at alpha {law['alpha']}"}
            del entry["law"]
        value = (airfoil_segments(entry["value"], unit, base) if spec.kind == "airfoils"
                 else _polynomial(entry["value"], unit, spec, entry["law"], key) if "law" in entry
                 else convert(entry["value"], unit, replace(spec, columns=("m", *spec.columns[1:])) if radial and
                              spec.kind == "table" else spec))
    except ValueError as exc:
        out.problems.append(f"{where}: {exc}")
        return
    if spec.replaces and isinstance(value, list) and not value:
        out.problems.append(f"{where}: an empty table, which would leave {', '.join(spec.replaces.split())} "
                            "unset; give its rows, or leave it out")
        return
    if radial:  # over or times the radius once every entry is read
        out.radial.append((section, key))
    if any(bases):  # over the surface's area once every entry is read
        out.surface.append((section, key, bases))
    meta = {"unit": entry.get("unit", ""), "source": entry["source"], "note": entry.get("note", ""),
            "origin": "override" if entry.get("override") else "file", "value": entry.get("printed", entry["value"])}
    out.put(section, key, _with_gain(value, entry, meta), meta)


def _radius_unit(section: str, key: str, spec: Entry, unit) -> tuple:
    """``(unit to convert with, radial)``: a span table's radial stations (a length in its first
    column, converted to metres) and a rotor's length in ``R`` (read as metres) are ``radial``,
    over or times the radius later; ValueError for ``R`` elsewhere."""
    if _radial_length(spec, unit):
        return unit, True
    if (section, key) in ROTOR_REFERENCES:
        return _rotor_reference(key, unit)
    fraction = OF_RADIUS.get(str(unit).replace(" ", ""))
    if fraction is None:
        return unit, False
    if not (section in ROTORS and key != "radius" and spec.unit == "m" and spec.kind == "number"):
        raise ValueError(f"unit {unit!r} (a fraction of the rotor's radius) applies to the lengths of [main_rotor] "
                         "and [tail_rotor] only")
    if spec.axis:  # a hub position in R would be ambiguous: of which rotor's radius?
        raise ValueError(f"unit {unit!r} applies to a rotor's own lengths, not to a position from the CG; give it in "
                         "a length unit or as a station")
    return fraction, True


OF_RADIUS = {"R": "m", "%R": "cm", "percentR": "cm"}
"""Units of a rotor's length as a fraction of its radius, and the length unit that reads the number
as that fraction in metres of a unit radius (``%R``: 1/100, as ``cm`` to ``m``), times the radius later."""


def _with_gain(value, entry: dict, meta: dict):
    """A mixing row with its common ``gain`` (if given) multiplied into its four gains."""
    if "gain" not in entry:
        return value
    meta["how"] = f"the offset, and the gain {entry['gain']:g} times each factor: from {entry['value']} {meta['unit']}"
    return [value[0], *(entry["gain"] * v for v in value[1:])]


def _gain(entry: dict, spec: Entry | None) -> str | None:
    """A ``gain`` only on a mixing row, and a finite number there."""
    if "gain" not in entry:
        return None
    if spec is None or spec.kind != "mixing":
        return "gain applies to the mixing rows of [controls] only (collective, longitudinal_cyclic, lateral_cyclic, "\
               "tail_collective)"
    try:
        _number(entry["gain"])
    except ValueError as exc:
        return f"gain: {exc}"
    return None


def _in_radius_columns(out: Reading, section: str, key: str, spec: Entry, unit):
    """A rotor's span table whose length columns after the first are given in ``R`` or ``%R`` (a
    chord as c/R): those columns read in metres of a unit radius, noted for :func:`_radius_columns`."""
    if not (section in ROTORS and spec.kind == "table" and spec.radial and isinstance(unit, str) and "," in unit):
        return unit
    columns = [c.strip() for c in unit.split(",")]
    for k, column in enumerate(columns[1:], start=1):
        if column.replace(" ", "") in OF_RADIUS and k < len(spec.columns) and spec.columns[k] == "m":
            columns[k] = OF_RADIUS[column.replace(" ", "")]
            out.radius_columns.append((section, key, k))
    return ", ".join(columns)


def _radius_columns(out: Reading) -> None:
    """Span-table columns given as fractions of the rotor's radius, times it (m)."""
    for section, key, k in out.radius_columns:
        radius, rows = out.values.get(section, {}).get("radius"), out.values.get(section, {}).get(key)
        if not radius or rows is None:
            continue  # the missing radius (or the table's own problem) is said on its own
        out.values[section][key] = [[*row[:k], row[k] * radius, *row[k + 1:]] for row in rows]
        meta = out.meta[section][key]
        meta["how"] = (f"{meta.get('how', '') + '; ' if meta.get('how') else ''}column {k + 1} times "
                       f"{section}.radius {radius:.6g} m; from {printed(meta)}")


def _radial_length(spec: Entry, unit) -> float | None:
    """The factor to metres of a span table's first column given as radial stations (a length),
    else None (r/R, or not a span table)."""
    if not (spec.radial and isinstance(unit, str) and "," in unit):
        return None
    first = unit.split(",")[0].strip()
    try:
        parsed = units.parse(first)
    except ValueError:
        return None
    return parsed.factor if parsed.dims == (1, 0, 0, 0) and not parsed.per_rev else None


ROUND_OFF = 1e-9
"""A radial station this close to r/R = 1 (relative) is the tip: unit conversions leave such residues."""


ROTORS = ("main_rotor", "tail_rotor")
ROTOR_REFERENCES = {("fuselage_aero", "reference_length"): "R", ("fuselage_aero", "reference_area"): "πR^2"}
"""Entries a report may give in the main rotor's radius (``R``) or disc area (``πR^2``), as rotorcraft
wind-tunnel reports base their airframe coefficients."""
DISC_AREA = ("πR^2", "πR²", "piR^2", "piR²", "disc", "disk")
"""How the main rotor's disc area may be written (spaces and '*' aside) as a unit."""


def _rotor_reference(key: str, unit) -> tuple:
    """``(unit, radial)`` of an airframe reference given in the main rotor's ``R`` or ``πR^2``."""
    length, disc = str(unit).replace(" ", "").replace("*", "") == "R", _is_disc(unit)
    if key == "reference_length" and length:
        return "m", True
    if key == "reference_area" and disc:
        return "m^2", True
    if length or disc:
        raise ValueError(f"unit {unit!r}: a reference {key.split('_')[1]} in the main rotor's "
                         f"{'radius is R' if key == 'reference_length' else 'disc area is πR^2'}")
    return unit, False


def _radial_stations(out: Reading) -> None:
    """Span tables given in radial stations (now m) as r/R of their rotor's radius; lengths
    given as fractions of it (unit ``R``) in metres, within their bounds; airframe references
    in the main rotor's radius or disc area in metres or square metres."""
    for section, key in out.radial:
        if section not in ROTORS:
            _times_main_rotor(out, section, key)
            continue
        radius = out.values.get(section, {}).get("radius")
        if not radius:
            continue  # the missing radius is a problem of its own
        meta, value = out.meta[section][key], out.values[section][key]
        if isinstance(value, list):
            out.values[section][key] = _over_radius(value, radius)
            meta["how"] = (f"r/R from the radial stations in {meta['unit'].split(',')[0].strip()} over "
                           f"{section}.radius {radius:.6g} m; from {printed(meta)}")
            continue
        try:
            out.values[section][key] = _bounded(value * radius, ENTRIES[section][key])
        except ValueError as exc:
            out.problems.append(f"{section}.{key}: {printed(meta)} is {exc}")
        meta["how"] = f"times {section}.radius {radius:.6g} m: from {printed(meta)}"


def _times_main_rotor(out: Reading, section: str, key: str) -> None:
    """An airframe reference length (area) given in the main rotor's radius (disc area)."""
    radius = out.values.get("main_rotor", {}).get("radius")
    if not radius:
        return  # the missing radius is a problem of its own
    meta, area = out.meta[section][key], ROTOR_REFERENCES[(section, key)] != "R"
    factor, what = (math.pi * radius**2, "the main rotor's disc area") if area else (radius, "main_rotor.radius")
    out.values[section][key] = out.values[section][key] * factor
    meta["how"] = f"times {what} {factor:.6g} m{'^2' if area else ''}: from {printed(meta)}"


def _is_disc(text: str) -> bool:
    """Whether the unit ``text`` is the main rotor's disc area (as :data:`DISC_AREA`, any case)."""
    compact = str(text).replace(" ", "").replace("*", "")
    return compact.replace("PI", "pi").replace("Pi", "pi") in DISC_AREA or compact.lower() in ("disc", "disk")


def _surface_columns(unit: str, spec: Entry) -> tuple:
    """A tail surface's ``coefficient_table`` with its lift and drag printed per dynamic pressure
    (an area: ``ft^2`` for L/q, D/q) or as coefficients on the main rotor's disc (``πR^2``):
    ``(unit, spec, bases)`` to read it with, ``bases`` per force column None (a coefficient on the
    surface's area), "area" or "disc"; :func:`_surface_coefficients` divides by the area later."""
    texts = [u.strip() for u in str(unit).split(",")]
    if len(texts) != 3:
        return unit, spec, [None, None]  # the table reader names the count
    bases, columns = [], [texts[0]]
    for text in texts[1:]:
        if _is_disc(text):
            bases.append("disc")
            columns.append("-")
            continue
        dims = units.parse(text).dims if text not in ("-", "") else (0, 0, 0, 0)
        if dims not in ((2, 0, 0, 0), (0, 0, 0, 0)):
            raise ValueError(f"unit {text!r} of a force column is {units.parse(text).describe()}; give - (a "
                             "coefficient on the surface's area), an area (L/q, D/q: ft^2) or πR^2 (a coefficient on "
                             "the main rotor's disc)")
        bases.append("area" if dims == (2, 0, 0, 0) else None)
        columns.append(text)
    wanted = (spec.columns[0], *("m^2" if b == "area" else "-" for b in bases))
    return ", ".join(columns), replace(spec, columns=wanted), bases


def _surface_coefficients(out: Reading) -> None:
    """Tail tables read in L/q (m²) or on the disc area: coefficients on the surface's ``area``."""
    for section, key, bases in out.surface:
        area, radius = out.values.get(section, {}).get("area"), out.values.get("main_rotor", {}).get("radius")
        if not area or ("disc" in bases and not radius):
            continue  # the missing area or radius is a problem of its own
        disc = math.pi * radius**2 if radius else 0.0
        factors = [1.0, *(1.0 if b is None else 1.0 / area if b == "area" else disc / area for b in bases)]
        out.values[section][key] = [[v * f for v, f in zip(row, factors)] for row in out.values[section][key]]
        meta = out.meta[section][key]
        how = {"area": f"per dynamic pressure over {section}.area {area:.6g} m^2",
               "disc": f"on the main rotor's disc area {disc:.6g} m^2 times {disc / area:.6g} (its ratio to "
                       f"{section}.area {area:.6g} m^2)"}
        said = [f"{name} {how[b]}" for name, b in zip(("c_L", "c_D"), bases) if b]
        meta["how"] = f"coefficients on {section}.area: {'; '.join(said)}; from {meta['unit']}"


def surface_slope(section_slope: float, aspect_ratio: float) -> float:
    """A surface's lift-curve slope (1/rad) from its section's and its aspect ratio: Helmbold's
    ``a / (sqrt(1 + k²) + k)``, ``k = a / (π A)`` (lifting-line theory's ``a / (1 + k)`` at large
    ``A``, and the slender wing's ``π A / 2`` at small)."""
    k = section_slope / (math.pi * aspect_ratio)
    return section_slope / (math.sqrt(1.0 + k * k) + k)


def _surface_slopes(out: Reading) -> None:
    """A surface's ``lift_slope`` given as its section's with ``aspect_ratio``: the surface's."""
    for section in SURFACES:
        v = out.values.get(section, {})
        if not v.get("aspect_ratio"):
            continue
        if "coefficient_table" in v or "lift_slope" not in v:
            why = ("a coefficient_table is the surface's already" if "coefficient_table" in v
                   else "no lift_slope is given")
            out.problems.append(f"{section}.aspect_ratio: turns a section's lift_slope into the surface's, and {why}: "
                                "leave aspect_ratio out")
            continue
        section_slope, meta = v["lift_slope"], out.meta[section]["lift_slope"]
        v["lift_slope"] = surface_slope(section_slope, v["aspect_ratio"])
        meta["how"] = (f"the surface's from the section's {section_slope:.6g} 1/rad and {section}.aspect_ratio "
                       f"{v['aspect_ratio']:g} (Helmbold: a / (sqrt(1 + k^2) + k), k = a / (pi A))")


def _over_radius(rows: list, radius: float) -> list:
    """Rows whose first column (m) becomes r/R (a station within :data:`ROUND_OFF` of the tip is the tip)."""
    ratios = [row[0] / radius for row in rows]
    return [[1.0 if abs(r - 1.0) <= ROUND_OFF else r, *row[1:]] for r, row in zip(ratios, rows)]


def _station_entry(out: Reading, section: str, key: str, entry: dict, spec: Entry | None) -> None:
    """A position given as its station(s): kept until the CG's stations are read."""
    where = f"{section}.{key}"
    if spec is None or not spec.axis:
        positions = [f"{s}.{k}" for s, e in ENTRIES.items() for k, v in e.items() if v.axis]
        out.problems.append(f"{where}: only a position from the CG may be given as a station ({', '.join(positions)}); "
                            "give value = ...")
        return
    problem = ("give value or station, not both" if "value" in entry else _fields(entry)
               or ("override applies to derived entries only; this one is plain data" if "override" in entry else None))
    if problem:
        out.problems.append(f"{where}: {problem}")
        return
    try:
        station = _station(entry["station"], entry.get("unit"), spec)
    except ValueError as exc:
        out.problems.append(f"{where}: {exc}")
        return
    meta = {"unit": entry.get("unit", ""), "source": entry["source"], "note": entry.get("note", ""), "origin": "file",
            "value": entry["station"]}
    out.stations.append(stations.Given(section, key, spec.axis, station, meta))


def _station(value, unit, spec: Entry):
    """A station (m): one number, or three (FS, BL, WL) for a point."""
    if unit is None:
        raise ValueError('no unit: give unit = "in" (or another length unit) for the station')
    factor = units.factor_to(str(unit), "m")
    if spec.axis == "xyz":
        if not (isinstance(value, list) and len(value) == 3):
            raise ValueError("station must be a list of 3 numbers: FS, BL, WL")
        return [_number(v) * factor for v in value]
    if isinstance(value, list):
        raise ValueError(f"station must be one number, the {stations.AXES[spec.axis][1]} of the point")
    return _number(value) * factor


def _place_stations(out: Reading) -> None:
    """Each position given as a station, in body axes from the CG (:func:`mbs.aircraft.stations.position`)."""
    cg = out.values.get("aircraft", {}).get("cg_station")
    if out.values.get("fuselage_aero", {}).get("cg_station") and cg:
        out.problems.append("fuselage_aero.cg_station: the CG's stations are given as aircraft.cg_station too; "
                            "give them once, in [aircraft]")
    if not out.stations:
        return
    if not cg:
        if any(p.startswith(("aircraft.cg_station:", "fuselage_aero.cg_station:")) for p in out.problems):
            return  # given, and its own problem already says what is wrong
        first = out.stations[0]
        out.problems.append(f"{first.section}.{first.key}: given as a station; give the CG's stations too: [aircraft] "
                            "cg_station = { value = [FS, BL, WL], unit = \"in\", source = \"...\" }")
        return
    conventions = out.values.get("conventions", {})
    cg_meta = out.meta["aircraft"]["cg_station"]
    for given in out.stations:
        spec = ENTRIES[given.section][given.key]
        value = stations.position(given.axis, given.station, cg, conventions)
        try:
            value = [_bounded(v, spec) for v in value] if isinstance(value, list) else _bounded(value, spec)
        except ValueError as exc:
            out.problems.append(f"{given.section}.{given.key}: the station gives {exc}")
            continue
        text = stations.how(given.axis, given.meta["value"], given.meta["unit"], cg_meta["value"], cg_meta["unit"],
                            conventions)
        out.put(given.section, given.key, value, {**given.meta, "how": text})


def _fields(entry: dict) -> str | None:
    extra = [k for k in entry if k not in FIELDS]
    if extra:
        return f"unknown field {extra[0]!r}{_suggest(extra[0], FIELDS)}"
    if not str(entry.get("source", "")).strip():
        return "no source: say where the value comes from (a reference, or EST for an estimate)"
    return None


def _law(entry: dict, key: str, spec) -> str | None:
    """A table printed as a law in its angle: ``law = "polynomial"`` on a one-argument fuselage table."""
    if "law" not in entry:
        return None
    if entry["law"] not in LAWS:
        return (f"law {entry['law']!r} is not known; the laws are \"polynomial\" (coefficients of the angle^0, ^1 ...) "
                "and \"expression\" (the law as printed, e.g. \"12.5 + 30.2*sin(alpha)^2\")")
    if key == "coefficient_table" and entry["law"] == "expression":
        return None  # a tail surface's c_L and c_D as printed laws (:func:`_surface_laws`)
    if spec is None or spec.kind != "lookup" or key.endswith("alpha_beta"):
        return (f"law = \"{entry['law']}\" applies to a fuselage_aero table in alpha or in beta only, and law = "
                "\"expression\" to a surface's coefficient_table too")
    return None


LAWS = ("polynomial", "expression")


def _surface_laws(value, unit) -> list[list[float]]:
    """A surface's ``coefficient_table`` printed as laws, ``{ alpha = [...], lift = "...", drag =
    "..." }``: the rows ``[alpha, c_L, c_D]`` at the breakpoints ``alpha``, in the table's units as
    printed (the law's ``alpha`` in the breakpoints' unit: a polynomial printed in degrees is
    valued in degrees), for the table reader to convert."""
    import numpy as np

    from mbs.aircraft import laws

    if not (isinstance(value, dict) and set(value) == {"alpha", "lift", "drag"}):
        raise ValueError("law = \"expression\": value must be { alpha = [breakpoints], lift = \"c_L law\", drag = "
                         "\"c_D law\" }, the laws in alpha as printed (in the breakpoints' unit)")
    alpha = value["alpha"]
    if not (isinstance(alpha, list) and len(alpha) >= 2 and all(isinstance(a, (int, float)) for a in alpha)):
        raise ValueError("law = \"expression\": alpha must be a list of two or more breakpoints")
    if unit is None or len(str(unit).split(",")) != 3:
        raise ValueError("law = \"expression\": give the units of alpha, c_L and c_D, e.g. unit = \"deg, %, %\"")
    x = np.asarray(alpha, dtype=float)
    columns = []
    angle_unit = str(unit).split(",")[0].strip()
    for name in ("lift", "drag"):
        try:
            tree = laws.parse(value[name], "alpha")
        except ValueError as exc:  # the law's angle is in the breakpoints' unit here
            raise ValueError(str(exc).replace("alpha (rad)", f"alpha (in {angle_unit}, the breakpoints' unit)")) from None
        with np.errstate(all="ignore"):
            column = laws.value(tree, "alpha", x)
        if not np.all(np.isfinite(column)):
            raise ValueError(f"the {name} law {value[name]!r} is not finite at alpha = {x[~np.isfinite(column)][0]:g}")
        columns.append(column)
    return [[float(a), float(cl), float(cd)] for a, cl, cd in zip(x, *columns)]


def _polynomial(value, unit, spec: Entry, law: str = "polynomial", key: str = "") -> dict:
    from mbs.aircraft import airframe_data

    if law == "expression":
        if unit is None:
            raise ValueError("no unit: give the unit of the law's value, e.g. unit = \"ft^2\"")
        return airframe_data.read_expression(value, unit, spec, key.rpartition("_")[2])
    if unit is None:
        raise ValueError("no unit: give one unit per coefficient, e.g. unit = \"ft^3, ft^3/rad\"")
    return airframe_data.read_polynomial(value, unit, spec)


def _laws(out: Reading) -> None:
    """Tables printed as a law in their angle, valued at the section's breakpoints (rad)."""
    from mbs.aircraft import airframe_data

    section = out.values.get("fuselage_aero", {})
    for key, table in section.items():
        if isinstance(table, dict) and ("coefficients" in table or "expression" in table):
            breakpoints = section.get(key.rpartition("_")[2], [])
            try:
                section[key] = airframe_data.at_breakpoints(table, breakpoints)
            except ValueError as exc:
                out.problems.append(f"fuselage_aero.{key}: {exc}")


def _override(entry: dict, derived) -> str | None:
    if derived is not None and entry.get("override") is not True:
        return (f"is derived ({derived.text}); leave it out, or add override = true to use this value "
                f"instead of the derived one")
    if derived is None and "override" in entry:
        return "override applies to derived entries only; this one is plain data"
    return None


def convert(value, unit: str | None, spec: Entry):
    """``value`` given in ``unit`` as the SI value of an entry ``spec``; ValueError naming the
    problem (unit, kind or bounds)."""
    kind = spec.kind
    if kind in ("text", "choice"):
        return _text(value, spec)
    if unit is None:
        raise ValueError(f"no unit: give unit = \"{spec.unit}\" (or another {units.parse(spec.unit).describe()} "
                         "unit)" if kind != "table" else f"no unit: give unit = \"{spec.unit}\"")
    if kind == "table":
        return _table(value, unit, spec)
    if kind in ("travel", "mixing"):
        return _pilot(value, str(unit), spec)
    if kind in ("series", "curve", "lookup", "schedule"):
        from mbs.aircraft import airframe_data
        return airframe_data.READERS[kind](value, unit, spec)
    if kind == "number" and (isinstance(value, list) or "," in str(unit) or _in_parts(value)):
        return _bounded(_compound(value, str(unit), spec.unit), spec)
    factor = units.factor_to(str(unit), spec.unit)
    if kind == "vector":
        if not (isinstance(value, list) and len(value) == spec.length):
            raise ValueError(f"must be a list of {spec.length} numbers")
        return [_bounded(_number(v) * factor, spec) for v in value]
    number = _number(value) * factor
    if kind == "integer":
        if number != int(number):
            raise ValueError(f"{value!r} must be a whole number")
        number = int(number)
    return _bounded(number, spec)


def printed(meta: dict) -> str:
    """An entry's value with its unit as the file gives it: ``25 ft 2 in`` for a number given in
    parts (:func:`_compound`), else ``<value> <unit>``."""
    value, unit = meta.get("value", ""), str(meta.get("unit", ""))
    parts = [u.strip() for u in unit.split(",")]
    if isinstance(value, list) and len(parts) == len(value) > 1 and all(isinstance(v, (int, float)) for v in value) \
            and _one_dimension(parts):
        return " ".join(f"{v:g} {u}" for v, u in zip(value, parts))
    return f"{value} {unit}".strip()


def _one_dimension(parts: list[str]) -> bool:
    """Whether the units ``parts`` are all of one kind (ft and in; not deg and deg/in of a mixing row)."""
    try:
        return len({units.parse(u).dims for u in parts}) == 1
    except units.UnitError:
        return False


def _in_parts(value) -> bool:
    """Text holding two numbers or more ("25 ft 2 in"): a number printed in parts."""
    return isinstance(value, str) and len(re.findall(r"\d+(?:\.\d*)?", value)) >= 2


def _compound(value, unit: str, want: str) -> float:
    """A number printed in parts (25 ft 2 in, 1 deg 11 min) given as ``value = [25, 2]`` with
    ``unit = "ft, in"``: the sum of its parts in ``want``; ValueError saying how to write it."""
    parts = [u.strip() for u in unit.split(",")]
    if not isinstance(value, list) or len(value) != len(parts) or len(parts) < 2:
        raise ValueError(f"{value!r} in {unit!r}: give a number, or one printed in parts as a list of the parts with "
                         "a unit each (25 ft 2 in: value = [25, 2], unit = \"ft, in\"; 1 deg 11 min: value = [1, 11], "
                         "unit = \"deg, arcmin\")")
    numbers = [_number(v) for v in value]
    if len({math.copysign(1.0, x) for x in numbers if x}) > 1:
        raise ValueError(f"{value!r}: the parts of a number must have one sign (-1 deg 11 min: [-1, -11])")
    return sum(x * units.factor_to(u, want) for x, u in zip(numbers, parts))


def _text(value, spec: Entry) -> str:
    if not isinstance(value, str):
        raise ValueError(f"{value!r} must be text" + (f": one of {', '.join(spec.choices)}" if spec.choices else ""))
    if spec.choices and value not in spec.choices:
        raise ValueError(f"{value!r} is not one of {', '.join(repr(c) for c in spec.choices)}")
    return value


def _number(value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{value!r} is not a number")
    if not math.isfinite(value):
        raise ValueError(f"{value!r} is not a finite number")
    return float(value)


def _bounded(x: float, spec: Entry):
    low_bad = x < spec.low or (spec.open_low and x == spec.low)
    high_bad = x > spec.high or (spec.open_high and x == spec.high)
    if low_bad or high_bad:
        one_sided = math.inf in (spec.high, -spec.low) and spec.low != spec.high
        raise ValueError(f"{_show(x, spec.unit)} {'must be' if one_sided else 'is outside'} {_range(spec)}")
    return x


def _show(x: float, unit: str) -> str:
    degrees = f" ({math.degrees(x):.4g} deg)" if unit == "rad" else ""
    return f"{x:.6g} {unit}{degrees}".replace(" -", "")


def _range(spec: Entry) -> str:
    if spec.low == spec.high:
        return f"the only value allowed, {_show(spec.low, spec.unit)}"
    if spec.high == math.inf:
        return f"{'> ' if spec.open_low else '>= '}{_show(spec.low, spec.unit)}"
    if spec.low == -math.inf:
        return f"<= {_show(spec.high, spec.unit)}"
    return (f"{'(' if spec.open_low else '['}{_show(spec.low, spec.unit)}, {_show(spec.high, spec.unit)}"
            f"{')' if spec.open_high else ']'}")


RADIAL_FRACTIONS = {"r/R": "-", "x/R": "-", "%R": "%", "percentR": "%"}
"""A span table's first column as reports head it: r/R (or x/R) as a fraction, % R in per cent."""


def _table(value, unit: str, spec: Entry) -> list:
    columns = [u.strip() for u in str(unit).split(",")]
    if spec.radial:
        columns[0] = RADIAL_FRACTIONS.get(columns[0].replace(" ", ""), columns[0])
    if len(columns) != len(spec.columns):
        raise ValueError(f"unit {unit!r}: give one unit per column ({spec.unit})")
    factors = [units.factor_to(u, want) for u, want in zip(columns, spec.columns)]
    if not isinstance(value, list) or not all(isinstance(r, list) and len(r) == len(factors) for r in value):
        raise ValueError(f"must be a list of rows of {len(factors)} numbers ({spec.unit})")
    return [[_number(v) * f for v, f in zip(row, factors)] for row in value]


def _pilot(value, unit: str, spec: Entry) -> list:
    """A pilot control's travel (two positions, ascending) or a mixing row (an angle, then four
    angles per control position), in SI (m, rad or fraction of travel)."""
    if not (isinstance(value, list) and len(value) == spec.length):
        raise ValueError(f"must be a list of {spec.length} numbers")
    numbers = [_number(v) for v in value]
    if spec.kind == "travel":
        factor = units.parse(unit).factor if units.position_kind(unit) else 1.0
        low, high = (x * factor for x in numbers)
        if not low < high:
            raise ValueError(f"the least position {numbers[0]:g} must be below the largest {numbers[1]:g} {unit}")
        return [low, high]
    columns = [u.strip() for u in unit.split(",")]
    if len(columns) != spec.length:
        raise ValueError(f"unit {unit!r}: give {spec.length} units, an angle and four angles per control position "
                         "(e.g. \"deg, deg/in, deg/in, deg/in, deg/in\")")
    factors = [units.factor_to(columns[0], "rad")]
    for text in columns[1:]:
        gain = units.parse(text)
        if gain.per_rev or gain.dims[:3] not in ((-1, 0, 0), (0, 0, 0)) or gain.dims[3] not in (0, 1):
            raise ValueError(f"unit {text!r} is {gain.describe()}, not an angle per control position (deg/in, deg/deg, "
                             "deg/%)")
        factors.append(gain.factor)
    return [x * f for x, f in zip(numbers, factors)]


def airfoil_segments(value, unit, base: Path | None) -> tuple:
    """Rows ``[r/R, "file.c81"]`` as :class:`mbs.aero.tables.AirfoilSegment` (each file read
    and its interpolant built); ValueError naming the row or the file's line."""
    from mbs.aero.tables import AirfoilSegment

    plain = RADIAL_FRACTIONS.get(str(unit).replace(" ", ""), str(unit))
    if unit is None or units.parse(plain).dims != (0, 0, 0, 0) or units.parse(plain).factor != 1.0:
        raise ValueError(f"unit {unit!r}: give unit = \"-\" (each segment's start is a fraction r/R of the radius)")
    rows = value if isinstance(value, list) and value else None
    if rows is None or not all(isinstance(r, list) and len(r) == 2 and isinstance(r[1], str) for r in rows):
        raise ValueError("must be a list of rows [r/R, \"file.c81\"], e.g. [[0.0, \"naca0012.c81\"]]")
    starts = [_number(r[0]) for r in rows]
    bad = [s for s in starts if not 0.0 <= s < 1.0]
    if bad:
        raise ValueError(f"segment start r/R = {bad[0]:g} outside [0, 1)")
    if any(b <= a for a, b in zip(starts, starts[1:])):
        raise ValueError(f"segment starts {', '.join(f'{s:g}' for s in starts)} must increase")
    return tuple(AirfoilSegment.read(s, (base or Path.cwd()) / name, name) for s, (_, name) in zip(starts, rows))


def _missing(out: Reading, raw: dict) -> None:
    for section, entries in ENTRIES.items():
        if section not in raw and section in OPTIONAL_SECTIONS:
            continue
        given = raw.get(section, {}) if isinstance(raw.get(section), dict) else {}
        replaced = {name: key for key, spec in entries.items() if spec.replaces and key in given
                    for name in spec.replaces.split()}
        if section == "main_rotor" and "blade_mass" in given and "I_flap" not in given:
            replaced.setdefault("I_flap", "blade_mass")  # a report's blade weight alone: a uniform blade
        idle: dict[tuple, list[str]] = {}  # (entry, value) -> the given entries that need it
        for key, spec in entries.items():
            applies = _applies(spec, out.values.get(section, {}), entries)
            if key in replaced and key in given and (section, replaced[key], key) in BOTH_AS_PRINTED:
                pass  # a flight manual prints both: they are checked against each other
            elif key in replaced and key in given:
                computed = ", which is computed from it" if key in FROM_TABLES.get(section, {}) else ""
                out.problems.append(f"{section}.{replaced[key]}: replaces {section}.{key}{computed}; leave {key} out")
            elif key not in given and spec.default is None and applies and key not in replaced:
                stand_in = STAND_INS[spec.optional_when](raw, out.values) if spec.optional_when else None
                if stand_in is not None:
                    out.put(section, key, stand_in[0], {"unit": spec.unit, "source": "", "note": stand_in[1],
                                                        "origin": "default", "value": stand_in[0]})
                    continue
                out.problems.append(f"{section}.{key}: missing ({spec.text}, in {spec.unit})")
            elif key in given and not applies:
                idle.setdefault(spec.only_if, []).append(key)
        out.problems.extend(_idle(section, other, wanted, keys) for (other, wanted), keys in idle.items())


def _stabilator_sets_it(raw: dict, values: dict):
    """A horizontal tail whose incidence the stabilator's schedule sets: the fixed one unused."""
    stabilator = raw.get("stabilator", {})
    return (0.0, "unused: the stabilator's schedule sets the incidence") if "airspeed" in stabilator \
        or "incidence_table" in stabilator else None


def _one_engine(raw: dict, values: dict):
    """One engine: no other to fail, so its one-engine-inoperative rating is never in force."""
    engine = values.get("engine", {})
    if engine.get("count") == 1 and "takeoff_power" in engine:
        return engine["takeoff_power"], "one engine: no other to fail"
    return None


# Entry.optional_when rules: (raw file, values read so far) -> (stand-in value, note), or None
# where the entry is required after all.
STAND_INS = {"stabilator schedule": _stabilator_sets_it, "one engine": _one_engine}


def _idle(section: str, other: str, wanted, keys: list[str]) -> str:
    """The problem of entries given where ``section.other`` is not ``wanted``: one line for them all."""
    wanted = " or ".join(map(repr, wanted)) if isinstance(wanted, tuple) else repr(wanted)
    if len(keys) == 1:
        return f"{section}.{keys[0]}: applies only when {section}.{other} = {wanted}; leave it out"
    return (f"{section}.{', '.join(keys)}: apply only when {section}.{other} = {wanted} "
            f"({len(keys)} entries); leave them out")


def _applies(spec: Entry, values: dict, entries: dict | None = None) -> bool:
    """Whether ``spec`` applies: its ``only_if`` entry has the wanted value (given, else its default)."""
    if not spec.only_if:
        return True
    other, wanted = spec.only_if
    default = (entries or {}).get(other)
    wanted = wanted if isinstance(wanted, tuple) else (wanted,)
    fallback = default.default if default is not None and default.default is not None else wanted[0]
    return values.get(other, fallback) in wanted
