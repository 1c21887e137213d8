"""Aircraft files the program writes: ``heli aircraft new NAME``'s commented file to fill in
(:func:`template`), and a copy of a file with its fuselage polynomials as tables
(:func:`with_polynomial_tables`).

Every entry of :data:`mbs.aircraft.schema.ENTRIES` with its meaning and unit in a comment and
the Bo105's value as a placeholder (source ``TEMPLATE``, which ``heli aircraft check`` warns
about until it is replaced); optional entries commented out with their defaults; derived
values listed, not written.
"""
from __future__ import annotations

import json
import re
from pathlib import Path

from mbs.aircraft._aircraft import load
from mbs.aircraft.airframe_data import tables_from_polynomials
from mbs.aircraft.reader import _applies
from mbs.aircraft.schema import DERIVED, ENTRIES, OPTIONAL_SECTIONS

HEADER = """\
# {name}: an aircraft file of rotor-mbs (single main rotor and a tail rotor).
#
# Every entry: {{ value = ..., unit = "...", source = "...", note = "..." }}. Units are converted to SI on
# loading: m, ft, in; kg, lb, slug; kg m^2, slug ft^2; rad, deg; rad/s, rpm; N, lbf; N m/rad, ft lbf/rad ...
# The values below are the Bo105's (source "{source}"): replace each with your aircraft's and its source
# (a reference, DER for a value you derived, EST for an estimate). Frame: body axes at the centre of
# gravity, x forward, y starboard, z down; a position may be written as its station instead,
# {{ station = ..., unit = "in", source = "..." }}, with aircraft.cg_station. Check the file with:  heli aircraft check FILE
"""

COMMENTED = ("elastic_blade", "swashplate", "stabilator", "controls", "conventions", "envelope", "lag_damper",
             "wing", "stabilizer_bar")
"""Optional sections written commented out (their entries are required once the section is there)."""
EXAMPLES = {"airfoils": [[0.0, "root_airfoil.c81"], [0.85, "tip_airfoil.c81"]],
            "chord_table": [[0.2, 0.27], [0.9, 0.27], [1.0, 0.2]],
            "twist_table": [[0.0, 0.07], [0.7, 0.0], [1.0, -0.03]],
            "mass_table": [[0.05, 30.0], [0.2, 8.0], [1.0, 5.5]],
            "section_inertia_table": [[0.05, 0.005, 0.2, 0.2], [1.0, 0.0005, 0.03, 0.03]]}
"""What an optional entry without a value of the Bo105's looks like (written commented out)."""
OLDER_FORMS = {("fuselage_aero", "reference_station"), ("fuselage_aero", "cg_station")}
"""Entries still read but not offered: ``reference_point`` given as a station, with
``aircraft.cg_station``, says the same once."""
AS_WRITTEN = {("aircraft", "inertia")}
"""Entries with a default that the template writes as the Bo105's, since the values beside them
depend on it: its Ixx, Iyy, Izz are the whole aircraft's."""
NEEDED_BY = {"elastic_blade": "the elastic-rotor scene's blades (elastic, 8 segments)",
             "swashplate": "the swashplate scenes, forward-flight-swashplate and forward-flight-actuators",
             "drive_train": "the scenes whose rotor speed is a state (engine-failure, engine-failure-cruise, "
                            "autorotation, hover-engines) and heli autorotation"}
"""What needs an optional section that the template writes commented out."""
LEFT_OUT_IS_NONE = {"horizontal_tail": "one (an S-51)"}
"""Optional sections whose absence is the aircraft's lack of the part, not defaults."""


def template(name: str, source: str = "TEMPLATE") -> str:
    """The text of a new aircraft file called ``name``."""
    base = load("bo105").data
    out = [HEADER.format(name=name, source=source)]
    for section, entries in ENTRIES.items():
        values = base.get(section, {})
        lines = [f"[{section}]" + _optional(section)]
        for key, spec in entries.items():
            if (section, key) in OLDER_FORMS:
                continue
            value = name if key == "name" else values.get(key, spec.default)
            if key in EXAMPLES:
                value = EXAMPLES[key]
            value = (spec.choices[0] if spec.choices else "...") if value is None else value
            line = f"{key} = {{ value = {_toml(value)}, unit = \"{spec.unit}\", source = \"{source}\" }}"
            if spec.only_if:
                wanted = spec.only_if[1] if isinstance(spec.only_if[1], tuple) else (spec.only_if[1],)
                need = "only" if spec.default is not None else "required"
                line += f"  # {need} with {spec.only_if[0]} = " + " or ".join(f'"{w}"' for w in wanted)
                line += f", unless {spec.optional_when}" if spec.optional_when else ""
            shown = {"airfoils": "none: the analytic section", "table": "none"}.get(spec.kind, spec.default)
            lines += [f"# {spec.text} ({spec.unit}" + (f"; default {shown})" if spec.default is not None else ")"),
                      ("# " if _commented(spec, values, entries) and (section, key) not in AS_WRITTEN else "")
                      + line]
        lines += _derived_comment(section)
        out += [f"# {line}" for line in lines] if section in COMMENTED else lines  # uncommented: one '# ' less
        out.append("")
    return "\n".join(out)


def _commented(spec, values: dict, entries: dict) -> bool:
    """Whether the template writes ``spec`` commented out: it has a default, or it does not apply
    to the file as written (whose entries with defaults are commented, so a switch with a default
    takes it)."""
    written = {k: v for k, v in values.items() if k in entries and entries[k].default is None}
    return spec.default is not None or not _applies(spec, written, entries)


def _optional(section: str) -> str:
    """The comment of an optional section's header line."""
    if section in NEEDED_BY and section not in COMMENTED:
        return f"  # optional, but needed by {NEEDED_BY[section]}: keep it for them"
    if section in NEEDED_BY:
        return (f"  # optional, needed by {NEEDED_BY[section]}: remove one '# ' from each line of the block to "
                "use it (lines still commented then are defaults or do not apply)")
    if section in COMMENTED:
        return ("  # optional: remove one '# ' from each line of the block and fill in the values marked "
                "'...' (lines still commented then are defaults or do not apply)")
    if section in LEFT_OUT_IS_NONE:
        return f"  # optional: leave the section out for an aircraft without {LEFT_OUT_IS_NONE[section]}"
    return "  # optional: leave the section out for the defaults" if section in OPTIONAL_SECTIONS else ""


def _toml(value) -> str:
    return json.dumps(value) if isinstance(value, (str, list, tuple)) else repr(float(value)) if isinstance(value, float) \
        else str(value)


def _derived_comment(section: str) -> list[str]:
    return [f"# derived, not written (override = true replaces it): {key}: {d.text}"
            for key, d in DERIVED.get(section, {}).items()]


def with_polynomial_tables(source, directory) -> "Path":
    """A copy of the aircraft file ``source`` in ``directory`` whose fuselage polynomials are
    replaced by :func:`mbs.aircraft.airframe_data.tables_from_polynomials`."""
    craft = load(source)
    text = re.sub(r"\[fuselage_aero\].*?(?=\n\[horizontal_tail\])", lambda _: tables_from_polynomials(
        craft.data["fuselage_aero"]), craft.path.read_text(), flags=re.S)
    path = Path(directory) / f"{craft.path.stem}_fuselage_tables.toml"
    path.write_text(text)
    return path
