"""Validation data as CSV: one published point a row, the file's facts in ``#`` lines.

::

    # title: Bo105 trims, flight test
    # aircraft: bo105
    # scene: forward-flight
    # speed_unit: kt
    # convention controls: blade angles, deg ...
    # source P1: Padfield, Helicopter Flight Dynamics, Fig. 4.10
    # eigenvalue_tolerance frequency: 0.25
    kind,quantity,unit,speed,value,uncertainty,tolerance,source,note
    trim,collective,deg,0.1,14.26,0.06,absolute 1.0,P1,
    derivative,M_q,1/s,0,-3.77,0.05,relative 0.25,P1,
    eigenvalue,,1/s,0,0.236,,,P1,       (an ``imaginary`` column holds Im λ in rad/s)

Columns ``kind`` (trim, derivative, eigenvalue), ``quantity``, ``unit``, ``speed``, ``value``
and ``source`` are required; ``imaginary``, ``uncertainty``, ``tolerance`` (``absolute x`` or
``relative x``), ``ours_factor``, ``note``, ``mass``, ``altitude``, ``cg_station`` and ``cg_x``
optional (a point's flight condition, in the units of the ``# mass_unit:``, ``# altitude_unit:``,
``# cg_station_unit:`` and ``# cg_x_unit:`` lines, which a column with values needs). The ``#
speed_unit:`` line is required (a CSV has no other place to say it). A ``#`` line whose key is
near a known one (``# speed unit:``, ``# mass_units:``) is taken or named, not read as a comment.
A tolerance is ``absolute x`` or ``±x`` (in the row's unit) or ``relative x`` or ``x%``, or ``at most``
(``<=``) / ``at least`` (``>=``) for a published limit of the model's value. A row
that repeats another of its series exactly (a copied point, not a repeated measurement) and a
source that the ``# source`` lines do not name are refused. A series' problem names its rows' lines.
Consecutive rows of the same kind, quantity, unit, source, tolerance and factor form one series
(one speed each; a note on some rows is the series' note at their speeds); eigenvalue rows of one speed form one set. The meaning of every field is that of the TOML form
(:mod:`mbs.validate.data`).
"""
from __future__ import annotations

import csv
from pathlib import Path

import difflib

from mbs.validate.data import ValidationError, from_dict

REQUIRED = ("kind", "quantity", "unit", "speed", "value", "source")
CONDITIONS = {"mass": "kg", "altitude": "m", "cg_station": "m", "cg_x": "m"}
OPTIONAL = ("imaginary", "uncertainty", "tolerance", "ours_factor", "note", *CONDITIONS)
HEAD_KEYS = ("title", "aircraft", "scene", "speed_unit", *(f"{k}_unit" for k in CONDITIONS))


def load_csv(path: Path) -> "Validation":  # noqa: F821
    """The :class:`mbs.validate.data.Validation` of the CSV file ``path``."""
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as exc:
        raise ValidationError(f"{path}: cannot be read ({exc})") from None
    lines = text.splitlines()
    raw = {"validation": {}, "conventions": {}, "sources": {}}
    body = []
    for n, line in enumerate(lines, 1):
        if line.lstrip().startswith("#"):
            _fact(raw, line.lstrip()[1:].strip(), path, n)
        elif line.strip():
            body.append((n, line))
    if not body:
        raise ValidationError(f"{path}: no header row ({', '.join(REQUIRED)}) and no data")
    reader = csv.reader([line for _, line in body])
    header = [h.strip() for h in next(reader)]
    missing = [c for c in REQUIRED if c not in header]
    unknown = [c for c in header if c not in REQUIRED + OPTIONAL]
    if missing or unknown:
        raise ValidationError(f"{path}: line {body[0][0]}: " + (f"missing column(s) {', '.join(missing)}" if missing else
                                                                f"unknown column(s) {', '.join(unknown)}")
                              + f"; the columns are {', '.join(REQUIRED + OPTIONAL)}")
    for (n, _), cells in zip(body[1:], reader):
        _row(raw, dict(zip(header, (c.strip() for c in cells))), path, n, len(header), len(cells))
    if "speed_unit" not in raw["validation"]:
        raise ValidationError(f"{path}: no '# speed_unit:' line; add one above the header, e.g. '# speed_unit: kt' "
                              "(kt, m/s, km/h, ft/s)")
    _sources_named(raw, path)
    condition_units = {k: raw["validation"].pop(f"{k}_unit", None) for k in CONDITIONS}
    for kind in ("trim", "derivative"):
        for entry in raw.get(kind, []):
            lines = sorted(entry.pop("_lines").values())
            del entry["_key"]
            if note := _note(entry.pop("_notes")):
                entry["note"] = note
            entry["_where"] = (f"the {kind} rows of {entry['quantity']!r} (line{'s' if len(lines) > 1 else ''} "
                               f"{lines[0]}{f'-{lines[-1]}' if len(lines) > 1 else ''})")
            _conditions(entry, condition_units, path)
    return from_dict(raw, path)


def _sources_named(raw: dict, path: Path) -> None:
    """With ``# source`` lines, every row's source is one of them."""
    named = raw["sources"]
    if not named:
        return
    used = {e["source"] for kind in ("trim", "derivative", "eigenvalues") for e in raw.get(kind, [])}
    unknown = sorted(used - set(named))
    if unknown:
        raise ValidationError(f"{path}: source(s) {', '.join(map(repr, unknown))} of the rows are not among the "
                              f"'# source' lines ({', '.join(named)}): add a '# source {unknown[0]}: ...' line, or "
                              "correct the rows")


def _conditions(entry: dict, condition_units: dict, path: Path) -> None:
    """A series' condition cells (mass, altitude, CG) as the TOML form's ``{ value, unit }``:
    every point's, or none."""
    for key, unit in condition_units.items():
        cells = entry.pop(f"_{key}")
        given = [c for c in cells if c is not None]
        if given and len(given) != len(cells):
            raise ValidationError(f"{path}: {entry['quantity']}: {key} is given for {len(given)} of its {len(cells)} "
                                  "points; give it for every point of the series, or for none")
        if given and unit is None:
            raise ValidationError(f"{path}: {entry['quantity']}: {key} {given[0]:g} has no unit; add a '# {key}_unit:' "
                                  f"line above the header, e.g. '# {key}_unit: {EXAMPLE_UNITS[key]}'")
        if given:
            entry[key] = {"value": given, "unit": unit}


EXAMPLE_UNITS = {"mass": "lb", "altitude": "ft", "cg_station": "in", "cg_x": "in"}
GROUPS = ("convention", "source", "eigenvalue_tolerance")
"""The ``#`` keys followed by a name: ``# source P1: ...``."""


def _fact(raw: dict, text: str, path: Path, n: int) -> None:
    key, sep, value = text.partition(":")
    if not sep:
        return  # a plain comment
    key, value = key.strip(), value.strip()
    word, _, name = key.partition(" ")
    if key.replace(" ", "_") in HEAD_KEYS:  # '# speed unit: kt' as '# speed_unit: kt'
        raw["validation"][key.replace(" ", "_")] = value
        return
    near = difflib.get_close_matches(key.replace(" ", "_"), HEAD_KEYS, n=1, cutoff=0.85) or \
        difflib.get_close_matches(word, [g for g in GROUPS if g != word], n=1, cutoff=0.85)
    if near:
        raise ValidationError(f"{path}: line {n}: '# {key}:' is no key of the file (did you mean '{near[0]}'?); the "
                              f"keys are {', '.join(HEAD_KEYS)} and {', '.join(g + ' NAME' for g in GROUPS)}")
    if word == "convention" and name:
        raw["conventions"][name] = value
    elif word == "source" and name:
        raw["sources"][name] = value
    elif word == "eigenvalue_tolerance" and name:
        raw.setdefault("eigenvalue_tolerance", {})[name] = _number(value, path, n, key)


def _row(raw: dict, row: dict, path: Path, n: int, width: int, cells: int) -> None:
    if cells != width:
        raise ValidationError(f"{path}: line {n}: {cells} cells for {width} columns")
    kind = row["kind"]
    speed, value = _number(row["speed"], path, n, "speed"), _number(row["value"], path, n, "value")
    if kind == "eigenvalue":
        if any(row.get(k) for k in CONDITIONS):
            raise ValidationError(f"{path}: line {n}: an eigenvalue row takes no flight condition (the eigenvalues "
                                  "are at the aircraft file's mass and CG; an altitude for every point is the TOML "
                                  "form's [validation] altitude)")
        imag = _number(row.get("imaginary") or "0", path, n, "imaginary")
        sets = raw.setdefault("eigenvalues", [])
        if not sets or sets[-1]["speed"] != speed or sets[-1]["source"] != row["source"]:
            sets.append({"speed": speed, "value": [], "source": row["source"]})
        sets[-1]["value"].append([value, imag])
        return
    if kind not in ("trim", "derivative"):
        raise ValidationError(f"{path}: line {n}: kind {kind!r} must be trim, derivative or eigenvalue")
    key = {k: row.get(k, "") for k in ("quantity", "unit", "source", "tolerance", "ours_factor")}
    entries = raw.setdefault(kind, [])
    if not entries or entries[-1]["_key"] != key:
        entries.append(_series(key, path, n))
    point = (speed, value, *(row.get(k) or "" for k in CONDITIONS))  # repeated measurements differ in value
    if point in entries[-1]["_lines"]:
        raise ValidationError(f"{path}: line {n}: repeats line {entries[-1]['_lines'][point]} ({kind} "
                              f"{key['quantity']} {value:g} at speed {speed:g}): a point copied twice counts twice; "
                              "give it once")
    entries[-1]["_lines"][point] = n
    entries[-1]["_notes"].append((row.get("note", ""), speed))
    entries[-1]["speed"].append(speed)
    entries[-1]["value"].append(value)
    entries[-1]["uncertainty"].append(_number(row.get("uncertainty") or "0", path, n, "uncertainty"))
    for key in CONDITIONS:
        entries[-1][f"_{key}"].append(_number(row[key], path, n, key) if row.get(key) else None)


def _series(key: dict, path: Path, n: int) -> dict:
    out = {"_key": key, "_lines": {}, "_notes": [], "quantity": key["quantity"], "unit": key["unit"], "source": key["source"],
           "speed": [], "value": [], "uncertainty": [], **{f"_{k}": [] for k in CONDITIONS}}
    if key["tolerance"]:
        out["tolerance"] = _tolerance(key["tolerance"], path, n)
    if key["ours_factor"]:
        out["ours_factor"] = _number(key["ours_factor"], path, n, "ours_factor")
    return out


def _note(notes: list[tuple[str, float]]) -> str:
    """A series' note from its rows' ``(note, speed)``: the note all give, or each note with the
    speeds of the rows that give it."""
    given = list(dict.fromkeys(t for t, _ in notes if t))
    if len(given) == 1 and all(t for t, _ in notes):
        return given[0]
    return "; ".join(f"at {', '.join(f'{v:g}' for t, v in notes if t == text)}: {text}" for text in given)


def _tolerance(text: str, path: Path, n: int) -> dict:
    """``absolute x`` or ``±x`` (``+-x``), ``relative x`` or ``x%``, ``at most`` (``<=``) or
    ``at least`` (``>=``), as the TOML form's table."""
    compact = text.replace(" ", "")
    bound = {"atmost": "upper", "<=": "upper", "≤": "upper", "atleast": "lower", ">=": "lower", "≥": "lower"}
    if compact.lower() in bound:
        return {"bound": bound[compact.lower()]}
    for prefix, kind, scale in (("absolute", "absolute", 1.0), ("relative", "relative", 1.0), ("±", "absolute", 1.0),
                                ("+-", "absolute", 1.0)):
        if compact.startswith(prefix):
            return {kind: scale * _tolerance_number(compact[len(prefix):], text, path, n)}
    if compact.endswith("%"):
        return {"relative": 0.01 * _tolerance_number(compact[:-1], text, path, n)}
    return {"absolute": _tolerance_number(compact, text, path, n)}


def _tolerance_number(number: str, text: str, path: Path, n: int) -> float:
    try:
        return float(number)
    except ValueError:
        raise ValidationError(f"{path}: line {n}: tolerance {text!r}: write 'absolute 1.0' or '±1.0' (in the row's "
                              "unit), or 'relative 0.25' or '25%'") from None


def _number(text: str, path: Path, n: int, column: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise ValidationError(f"{path}: line {n}: {column} {text!r} is not a number") from None
