"""An aircraft: the file's values in SI with their defaults and derived values, and where each
came from."""
from __future__ import annotations

import hashlib
import re
import sys
from dataclasses import dataclass
from pathlib import Path

from mbs.aircraft import checks, derived
from mbs.aircraft.reader import read
from mbs.aircraft.schema import DERIVED, FROM_TABLES

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

DATA_DIR = Path(__file__).with_name("data")
DEFAULT = "bo105"


class Data(dict):
    """``data["main_rotor"]["radius"]`` -> SI value; ``data.meta[section][key]`` -> unit as
    written, source, note and origin ("file", "default", "derived" or "override")."""

    meta: dict


class AircraftError(ValueError):
    """An aircraft file with problems: the first in one line, all in :attr:`problems`."""

    def __init__(self, path: Path, problems: list[str]):
        self.path, self.problems = path, problems
        more = f" (and {len(problems) - 1} more: 'heli aircraft check {path}' lists them)" if len(problems) > 1 else ""
        super().__init__(f"aircraft file {path}: {problems[0]}{more}")


@dataclass(frozen=True, eq=False)
class Aircraft:
    """A loaded aircraft. ``key``: identifier of its models (the file's stem); ``data``: every
    value in SI (:class:`Data`); ``digest``: SHA-256 of the file's text (and of the table files it
    names)."""

    key: str
    name: str
    path: Path
    data: Data
    digest: str

    @property
    def packaged(self) -> bool:
        return self.path.parent.resolve() == DATA_DIR.resolve()

    @property
    def omega(self) -> float:
        return self.data["main_rotor"]["omega"]

    def stored_trims(self) -> dict:
        """The periodic trims stored beside the file (``<stem>_trim.toml``), by key; {} if none."""
        path = self.path.with_name(f"{self.path.stem}_trim.toml")
        return tomllib.loads(path.read_text()) if path.exists() else {}

    def __repr__(self) -> str:
        return f"Aircraft({self.name!r}, {str(self.path)!r})"


def packaged() -> dict[str, Path]:
    """The aircraft shipped with the package: name -> file."""
    return {p.stem: p for p in sorted(DATA_DIR.glob("*.toml")) if not p.stem.endswith("_trim")}


def resolve(source: str | Path) -> Path:
    """The file of ``source``: a packaged aircraft's name (``bo105``) or a path to a file."""
    if isinstance(source, str) and source in packaged():
        return packaged()[source]
    path = Path(source).expanduser()
    if not path.is_file():
        known = ", ".join(packaged())
        raise AircraftError(path, [f"no such file (a packaged aircraft is one of {known}; "
                                   "'heli aircraft new NAME' writes a template)"])
    return path


_CACHE: dict[tuple[str, str], Aircraft] = {}


def load(source: str | Path = DEFAULT) -> Aircraft:
    """The aircraft of ``source`` (a packaged name or a file path), validated and completed;
    :class:`AircraftError` naming the entry of the first problem otherwise."""
    path = resolve(source)
    text = _text(path)
    key = (str(path.resolve()), hashlib.sha256(text.encode()).hexdigest())
    if key not in _CACHE or _CACHE[key].digest != _digest(text, _CACHE[key].data):
        data, problems = evaluate(text, path.parent)
        if problems:
            raise AircraftError(path, problems)
        _CACHE[key] = Aircraft(_key(path), data["aircraft"]["name"], path, data, _digest(text, data))
    return _CACHE[key]


def table_files(data: Data) -> list[Path]:
    """The files the aircraft file names (C81 airfoil tables), in the order it names them."""
    return [seg.c81.path for section in ("main_rotor", "tail_rotor") for seg in data.get(section, {}).get("airfoils", ())]


def _digest(text: str, data: Data) -> str:
    """SHA-256 of the file's text, and of the table files it names when it names any (so that a
    changed table file changes the aircraft)."""
    from mbs.aero.tables.airfoil import file_digest

    files = table_files(data)
    if not files:
        return hashlib.sha256(text.encode()).hexdigest()
    try:
        parts = [file_digest(p) for p in files]
    except OSError:
        parts = ["missing"]
    return hashlib.sha256("\n".join([text, *parts]).encode()).hexdigest()


def _text(path: Path) -> str:
    try:
        return path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise AircraftError(path, [f"cannot be read ({getattr(exc, 'strerror', None) or exc})"]) from None


def _key(path: Path) -> str:
    return re.sub(r"\W", "_", path.stem.lower()) or "aircraft"


def evaluate(text: str, base: Path | None = None) -> tuple[Data, list[str]]:
    """Read, complete and check the file ``text`` (files it names found from the folder
    ``base``): ``(data, problems)``."""
    reading = read(text, base)
    data = Data(reading.values)
    data.meta = reading.meta
    if reading.problems:
        return data, reading.problems
    derived.fill_defaults(data, data.meta)
    before = {s: set(v) for s, v in data.items()}
    problems = derived.complete(data)
    for section, entries in data.items():
        for k in set(entries) - before.get(section, set()):
            spec = DERIVED.get(section, {}).get(k) or FROM_TABLES[section][k]
            data.meta.setdefault(section, {})[k] = {"unit": spec.unit, "source": "DER", "origin": "derived",
                                                    "note": spec.text}
    return data, problems or checks.problems(data)
