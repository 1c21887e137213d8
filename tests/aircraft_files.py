"""Aircraft files for the tests: the packaged files' entries edited and written back as TOML."""
from __future__ import annotations

import json
import sys
from pathlib import Path

from mbs.aircraft import packaged

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


def entries(name: str = "bo105") -> dict:
    """The raw entries of a packaged aircraft file: section -> key -> {value, unit, source, ...}."""
    return tomllib.loads(packaged()[name].read_text())


def to_toml(raw: dict) -> str:
    """TOML text of raw entries (values as JSON, which TOML inline tables accept)."""
    lines = []
    for section, items in raw.items():
        lines.append(f"[{section}]")
        for key, entry in items.items():
            fields = ", ".join(f"{k} = {json.dumps(v)}" for k, v in entry.items()) if isinstance(entry, dict) \
                else None
            lines.append(f"{key} = {{ {fields} }}" if fields is not None else f"{key} = {json.dumps(entry)}")
        lines.append("")
    return "\n".join(lines)


def write(raw: dict, path: Path) -> Path:
    path.write_text(to_toml(raw))
    return path


def edited(path: Path, name: str = "bo105", drop_overrides: bool = False, **changes) -> Path:
    """A copy of a packaged file at ``path`` with ``changes`` ("section.key" -> value, or
    -> None to remove the entry); ``drop_overrides`` removes every overriding entry."""
    raw = entries(name)
    if drop_overrides:
        raw = {s: {k: e for k, e in items.items() if not e.get("override")} for s, items in raw.items()}
    for where, value in changes.items():
        section, key = where.split(".")
        if value is None:
            raw[section].pop(key, None)
        else:
            raw.setdefault(section, {}).setdefault(key, {"unit": "-", "source": "EST"})["value"] = value
    return write(raw, path)


def mirrored(path: Path, name: str = "bo105", raw: dict | None = None) -> Path:
    """The mirror image of a packaged aircraft (or of the entries ``raw``) in its x-z plane:
    rotation reversed, the tail rotor on the other side, the fin's incidence and the
    fuselage's asymmetric side loads reversed."""
    raw = json.loads(json.dumps(raw)) if raw is not None else entries(name)
    mr, tr = raw["main_rotor"], raw["tail_rotor"]
    mr["rotation"]["value"] = {"clockwise": "counter-clockwise", "counter-clockwise": "clockwise"}[mr["rotation"]["value"]]
    tr["hub_y"]["value"] = -tr["hub_y"]["value"]
    raw["vertical_fin"]["incidence"]["value"] *= -1
    for k in ("Y", "N"):  # odd in sideslip after the mirror: the even powers change sign
        c = raw["fuselage_aero"][k]["value"]
        raw["fuselage_aero"][k]["value"] = [-v if i % 2 == 0 else v for i, v in enumerate(c)]
    raw["download"]["panels"]["value"] = [[x, -y, *rest] for x, y, *rest in raw["download"]["panels"]["value"]]
    return write(raw, path)


def with_tail_rotor(raw: dict, **values) -> dict:
    """``raw`` with tail-rotor entries set: key -> (value, unit) (source EST); a seesaw's entries
    leave with a hub that does not teeter."""
    for key, (value, unit) in values.items():
        raw["tail_rotor"][key] = {"value": value, "unit": unit, "source": "EST"}
    if raw["tail_rotor"]["hub_type"]["value"] != "teetering":
        for key in ("seesaw_mass", "seesaw_size", "teeter_stiffness"):
            raw["tail_rotor"].pop(key, None)
    return raw


UH60_TAIL = {"n_blades": (4, "-"), "hub_type": ("flapping", "-"), "radius": (5.5, "ft"), "chord": (0.81, "ft"),
             "twist": (-18.0, "deg"), "cant": (20.0, "deg"), "delta3": (35.0, "deg"), "gear_ratio": (4.6155, "-"),
             "blade_mass": (7.0, "kg"), "flap_hinge_offset": (0.12, "m"), "flap_stiffness": (1500.0, "N m/rad"),
             "root_cutout": (0.2, "-"), "hub_x": (-9.97, "m")}
"""The UH-60A's tail rotor (Howlett, NASA CR-166309, 1981: radius, chord, twist, four blades, cant,
delta3, 124.62 rad/s against the main rotor's 27.0, hub 390.8 in aft of the main rotor's) as four
flapping blades; blade mass, equivalent hinge offset and spring of its bearingless cross-beam hub
are estimates."""


def uh60_tailed(path: Path, **changes) -> Path:
    """The Puma (27.0 rad/s, like the UH-60A) with the UH-60A's tail rotor, ``changes`` on top
    (key -> (value, unit))."""
    return write(with_tail_rotor(entries("puma"), **{**UH60_TAIL, **changes}), path)
