"""Files of stored trims: TOML, one table per trim, keyed by what the trim is of.

A stored trim (an *entry*) is the periodic solution of one model: the aircraft file (its
name, path and the SHA-256 of its text), the scene, its aerodynamics switches and run-time
parameters, the flight speed and climb rate, and the fixed-step method and steps per
revolution it is periodic for. :func:`identity` gathers these; an entry is used only for a
model whose identity is the same (:func:`find`), so one aircraft's trim is never another's,
nor that of an earlier version of the same file. The table's name says the same in words with
a short hash of the identity (``["forward-flight at 10 m/s, My helicopter, 1f2e3d4c"]``);
writing an entry of the same identity replaces it, other entries are kept.

Tables of the earlier format (named after the scene, with no ``scene`` entry: the packaged
``bo105_trim.toml``) are kept as they are and never matched here.
"""
from __future__ import annotations

import contextlib
import datetime
import hashlib
import json
import math
import os
import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

IDENTITY = ("aircraft_sha256", "scene", "aero", "parameters", "speed", "climb_rate", "method", "steps_per_rev")
"""The fields of an entry that say what it is a trim of (:func:`identity`)."""
HEADER = ("# Periodic trims of rotor-mbs: written by 'heli trim SCENE --write [PATH]' and by 'heli simulate' (a trim\n"
          "# computed on first use). One table per trim, used only for the aircraft file of the same SHA-256,\n"
          "# the same scene, aerodynamics switches, parameters, speed, climb rate, method and steps per revolution.\n"
          "# Angles in rad, speeds in m/s, every state in SI units; max_abs_residual scaled (per rotor radius and\n"
          "# revolution).\n")


def default_file() -> Path:
    """The user's trim file, ``$XDG_DATA_HOME/rotor-mbs/trims.toml`` (default
    ``~/.local/share/rotor-mbs/trims.toml``)."""
    return Path(os.environ.get("XDG_DATA_HOME") or Path.home() / ".local" / "share") / "rotor-mbs" / "trims.toml"


def beside(aircraft) -> Path:
    """The trim file beside an aircraft file: ``<stem>_trim.toml``."""
    return aircraft.path.with_name(f"{aircraft.path.stem}_trim.toml")


def identity(aircraft, scene: str, aero: list[str], parameters: dict, speed: float, climb_rate: float,
             method: str, steps_per_rev: int) -> dict:
    """What a trim is of, as plain data (the fields :data:`IDENTITY`)."""
    return {"aircraft_sha256": aircraft.digest if aircraft is not None else "", "scene": scene,
            "aero": sorted(aero), "parameters": {k: float(v) for k, v in sorted(parameters.items())},
            "speed": float(speed), "climb_rate": float(climb_rate), "method": method,
            "steps_per_rev": int(steps_per_rev)}


def same(entry: dict, ident: dict) -> bool:
    """Whether ``entry`` is a trim of the model ``ident`` (speeds within 1 µm/s)."""
    for k in IDENTITY:
        a, b = entry.get(k), ident[k]
        if k in ("speed", "climb_rate"):
            if not isinstance(a, (int, float)) or abs(a - b) > 1e-6:
                return False
        elif k == "parameters":
            if not isinstance(a, dict) or set(a) != set(b) or any(abs(a[n] - b[n]) > 1e-12 * max(1, abs(b[n]))
                                                                  for n in b):
                return False
        elif a != b:
            return False
    return True


def key(entry: dict) -> str:
    """The table name of ``entry``: scene, speed, aircraft and a short hash of its identity."""
    digest = hashlib.sha256(json.dumps({k: entry[k] for k in IDENTITY}, sort_keys=True).encode()).hexdigest()[:8]
    climb = f", climb {entry['climb_rate']:g} m/s" if entry["climb_rate"] else ""
    return f"{entry['scene']} at {entry['speed']:g} m/s{climb}, {entry.get('aircraft', 'no aircraft')}, {digest}"


def read(path: Path) -> dict[str, dict]:
    """The tables of the trim file ``path`` by name ({} when it does not exist); ValueError
    naming the file when it is not TOML."""
    path = Path(path)
    if not path.exists():
        return {}
    try:
        return tomllib.loads(path.read_text(encoding="utf-8"))
    except (ValueError, OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"the trim file {path} cannot be read ({exc}); repair or remove it") from None


def find(paths, ident: dict) -> tuple[Path, str, dict] | None:
    """The first entry of the files ``paths`` that is a trim of ``ident``: ``(file, table name,
    entry)``, or None."""
    for path in paths:
        for name, entry in read(path).items():
            if isinstance(entry, dict) and "scene" in entry and same(entry, ident):
                return Path(path), name, entry
    return None


def earlier_versions(paths, ident: dict, aircraft_file: str) -> list[Path]:
    """Files of ``paths`` holding a trim of the same scene and speed for the same aircraft
    file path but another version of its text (a changed file)."""
    out = []
    for path in paths:
        for entry in read(path).values():
            if (isinstance(entry, dict) and entry.get("aircraft_file") == aircraft_file
                    and entry.get("aircraft_sha256") != ident["aircraft_sha256"] and entry.get("scene") == ident["scene"]
                    and same({**entry, "aircraft_sha256": ident["aircraft_sha256"]}, ident)):
                out.append(Path(path))
    return out


def write(path: Path, entry: dict) -> str:
    """Store ``entry`` in the trim file ``path`` (an entry of the same identity replaced, the
    others kept; written atomically under a lock); returns its table name."""
    from mbs import atomic

    path = Path(path)
    name = key(entry)
    with _locked(path):
        tables = read(path)
        tables = {k: v for k, v in tables.items() if not (isinstance(v, dict) and "scene" in v and
                                                          same(v, {i: entry[i] for i in IDENTITY}))}
        tables[name] = {**entry, "written": datetime.datetime.now().isoformat(timespec="seconds")}
        atomic.write_text(path, HEADER + "\n" + "\n".join(_table([n], v) for n, v in tables.items()))
    return name


@contextlib.contextmanager
def _locked(path: Path):
    """An exclusive lock on ``<path>.lock`` (where the platform has ``fcntl``): two processes
    storing trims at once do not lose each other's."""
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        import fcntl
    except ImportError:  # pragma: no cover
        yield
        return
    with open(path.with_name(path.name + ".lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


def _table(names: list[str], values: dict) -> str:
    """One TOML table (and its sub-tables) of ``values``."""
    head = "[" + ".".join(json.dumps(n) for n in names) + "]\n"
    plain = [f"{json.dumps(k)} = {_value(v)}\n" for k, v in values.items() if not isinstance(v, dict)]
    subs = [_table([*names, k], v) for k, v in values.items() if isinstance(v, dict)]
    return head + "".join(plain) + "".join("\n" + s for s in subs)


def _value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return repr(v) if math.isfinite(v) else ("nan" if math.isnan(v) else ("inf" if v > 0 else "-inf"))
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    return json.dumps(str(v))
