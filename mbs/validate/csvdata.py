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
``# cg_station_unit:`` and ``# cg_x_unit:`` lines, default kg and m).
Consecutive rows of the same kind, quantity, unit, source, tolerance, factor and note form one
series (one speed each); eigenvalue rows of one speed form one set. The meaning of every field is that of the TOML form
(:mod:`mbs.validate.data`).
"""
from __future__ import annotations

import csv
from pathlib import Path

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
    condition_units = {k: raw["validation"].pop(f"{k}_unit", si) for k, si in CONDITIONS.items()}
    for kind in ("trim", "derivative"):
        for entry in raw.get(kind, []):
            del entry["_key"]
            _conditions(entry, condition_units, path)
    return from_dict(raw, path)


def _conditions(entry: dict, condition_units: dict, path: Path) -> None:
    """A series' condition cells (mass, altitude, CG) as the TOML form's ``{ value, unit }``:
    every point's, or none."""
    for key, unit in condition_units.items():
        cells = entry.pop(f"_{key}")
        given = [c for c in cells if c is not None]
        if given and len(given) != len(cells):
            raise ValidationError(f"{path}: {entry['quantity']}: {key} is given for {len(given)} of its {len(cells)} "
                                  "points; give it for every point of the series, or for none")
        if given:
            entry[key] = {"value": given, "unit": unit}


def _fact(raw: dict, text: str, path: Path, n: int) -> None:
    key, sep, value = text.partition(":")
    if not sep:
        return  # a plain comment
    key, value = key.strip(), value.strip()
    word, _, name = key.partition(" ")
    if key in HEAD_KEYS:
        raw["validation"][key] = value
    elif word == "convention" and name:
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
    key = {k: row.get(k, "") for k in ("quantity", "unit", "source", "tolerance", "ours_factor", "note")}
    entries = raw.setdefault(kind, [])
    if not entries or entries[-1]["_key"] != key:
        entries.append(_series(key, path, n))
    entries[-1]["speed"].append(speed)
    entries[-1]["value"].append(value)
    entries[-1]["uncertainty"].append(_number(row.get("uncertainty") or "0", path, n, "uncertainty"))
    for key in CONDITIONS:
        entries[-1][f"_{key}"].append(_number(row[key], path, n, key) if row.get(key) else None)


def _series(key: dict, path: Path, n: int) -> dict:
    out = {"_key": key, "quantity": key["quantity"], "unit": key["unit"], "source": key["source"], "speed": [],
           "value": [], "uncertainty": [], **{f"_{k}": [] for k in CONDITIONS}}
    if key["tolerance"]:
        word, _, number = key["tolerance"].partition(" ")
        out["tolerance"] = {word: _number(number, path, n, "tolerance")}
    if key["ours_factor"]:
        out["ours_factor"] = _number(key["ours_factor"], path, n, "ours_factor")
    if key["note"]:
        out["note"] = key["note"]
    return out


def _number(text: str, path: Path, n: int, column: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise ValidationError(f"{path}: line {n}: {column} {text!r} is not a number") from None
