"""``heli aircraft new NAME``: a commented aircraft file to fill in.

Every entry of :data:`mbs.aircraft.schema.ENTRIES` with its meaning and unit in a comment and
the Bo105's value as a placeholder (source ``TEMPLATE``, which ``heli aircraft check`` warns
about until it is replaced); optional entries commented out with their defaults; derived
values listed, not written.
"""
from __future__ import annotations

import json

from mbs.aircraft.schema import DERIVED, ENTRIES, OPTIONAL_SECTIONS

HEADER = """\
# {name}: an aircraft file of rotor-mbs (single main rotor and a tail rotor).
#
# Every entry: {{ value = ..., unit = "...", source = "...", note = "..." }}. Units are converted to SI on
# loading: m, ft, in; kg, lb, slug; kg m^2, slug ft^2; rad, deg; rad/s, rpm; N, lbf; N m/rad, ft lbf/rad ...
# The values below are the Bo105's (source "{source}"): replace each with your aircraft's and its source
# (a reference, DER for a value you derived, EST for an estimate). Frame: body axes at the centre of
# gravity, x forward, y starboard, z down. Check the file with:  heli aircraft check FILE
"""

COMMENTED = ("elastic_blade", "swashplate")
EXAMPLES = {"airfoils": [[0.0, "root_airfoil.c81"], [0.85, "tip_airfoil.c81"]],
            "chord_table": [[0.2, 0.27], [0.9, 0.27], [1.0, 0.2]],
            "twist_table": [[0.0, 0.07], [0.7, 0.0], [1.0, -0.03]],
            "mass_table": [[0.05, 30.0], [0.2, 8.0], [1.0, 5.5]],
            "section_inertia_table": [[0.05, 0.005, 0.2, 0.2], [1.0, 0.0005, 0.03, 0.03]]}
"""What an optional entry without a value of the Bo105's looks like (written commented out)."""
"""Optional sections written commented out (their entries are required once the section is there)."""


def template(name: str, source: str = "TEMPLATE") -> str:
    """The text of a new aircraft file called ``name``."""
    from mbs.aircraft import load

    base = load("bo105").data
    out = [HEADER.format(name=name, source=source)]
    for section, entries in ENTRIES.items():
        optional = section in OPTIONAL_SECTIONS
        out.append(f"{'# ' if section in COMMENTED else ''}[{section}]"
                   + ("  # optional: leave the section out for the defaults" if optional else ""))
        for key, spec in entries.items():
            value = name if key == "name" else base.get(section, {}).get(key, spec.default)
            if key in EXAMPLES:
                value = EXAMPLES[key]
            line = f"{key} = {{ value = {_toml(value)}, unit = \"{spec.unit}\", source = \"{source}\" }}"
            commented = section in COMMENTED or spec.default is not None
            if spec.only_if:
                line += f"  # only with {spec.only_if[0]} = \"{spec.only_if[1]}\""
            shown = {"airfoils": "none: the analytic section", "table": "none"}.get(spec.kind, spec.default)
            out += [f"# {spec.text} ({spec.unit}" + (f"; default {shown})" if spec.default is not None else ")"),
                    ("# " if commented else "") + line]
        out += _derived_comment(section) + [""]
    return "\n".join(out)


def _toml(value) -> str:
    return json.dumps(value) if isinstance(value, (str, list)) else repr(float(value)) if isinstance(value, float) \
        else str(value)


def _derived_comment(section: str) -> list[str]:
    return [f"# derived, not written (override = true replaces it): {key}: {d.text}"
            for key, d in DERIVED.get(section, {}).items()]
