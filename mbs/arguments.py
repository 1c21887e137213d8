"""Argument types of the ``heli`` command: every value is checked while the command line is
parsed, before any work starts.

Each type returns the converted value or raises :class:`argparse.ArgumentTypeError` with a
message naming the value; argparse adds the option (``heli simulate: error: argument
--every: 0 must be a whole number >= 1``). Output folders and files are checked for
writability here too (by writing and removing a temporary file in the nearest existing
folder), so that a read-only mount, ``/dev/null/x`` or an existing file where a folder is
wanted is refused before a computation, not after it.
"""
from __future__ import annotations

import argparse
import errno
import math
import tempfile
from pathlib import Path
from typing import Callable

from mbs.envelope import CLIMB_RANGE, SPEED_RANGE

Bad = argparse.ArgumentTypeError


def whole_number(low: int = 1, high: int | None = None) -> Callable[[str], int]:
    """Type: an integer in ``[low, high]``."""
    def convert(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise Bad(f"{text!r} is not a whole number") from None
        if value < low or (high is not None and value > high):
            bounds = f">= {low}" if high is None else f"from {low} to {high}"
            raise Bad(f"{text} must be a whole number {bounds}")
        return value
    return convert


def real_number(low: float = -math.inf, strict: bool = False) -> Callable[[str], float]:
    """Type: a finite number ``>= low`` (``> low`` when ``strict``)."""
    def convert(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise Bad(f"{text!r} is not a number") from None
        if not math.isfinite(value):
            raise Bad(f"{text} is not a finite number")
        if value < low or (strict and value == low):
            need = "positive" if strict and low == 0 else f"{'>' if strict else '>='} {low:g}"
            raise Bad(f"{text} must be {need}")
        return value
    return convert


class Within:
    """Type: a finite number in ``[low, high]`` (``unit``); ``what`` names the range in the
    message and ``hint(value)`` adds what the user may have meant. ``units`` (name -> factor to
    ``unit``) lets the number carry a unit, ``60kt`` or ``60 kt``; a bare number is in ``unit``.
    :meth:`check` checks a value found otherwise (one of a sweep's)."""

    def __init__(self, low: float, high: float, unit: str, what: str, hint: Callable[[float], str] = lambda v: "",
                 units: dict[str, float] | None = None):
        self.low, self.high, self.unit, self.what, self.hint = low, high, unit, what, hint
        self.units = units or {}

    def __call__(self, text: str) -> float:
        number, name = self._split(text)
        if not name:
            value = real_number()(text)
            self.check(value, text)
            return value
        value = real_number()(number) * self.units[name]
        if not self.low <= value <= self.high:
            raise Bad(f"{text.strip()} ({value:.4g} {self.unit}) is outside {self.what}, {self.low:g} to "
                      f"{self.high:g} {self.unit}")
        return value

    def _split(self, text: str) -> tuple[str, str]:
        """``(number, unit)`` of ``text``; the unit "" when it is a bare number (or not a number)."""
        stripped = text.strip()
        for name in sorted(self.units, key=len, reverse=True):
            if stripped.lower().endswith(name.lower()) and len(stripped) > len(name):
                return stripped[:-len(name)].strip(), name
        number = stripped.rstrip("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ/ ")
        if self.units and number != stripped and number and _is_number(number):
            raise Bad(f"{text!r}: unknown unit {stripped[len(number):].strip()!r}; give a number in {self.unit}, "
                      f"or with one of {', '.join(self.units)} (e.g. 60kt)")
        return stripped, ""

    def check(self, value: float, text: str | None = None) -> None:
        if not self.low <= value <= self.high:
            raise Bad(f"{text or f'{value:g}'} {self.unit} is outside {self.what}, {self.low:g} to {self.high:g} "
                      f"{self.unit}{self.hint(value)}")


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


KNOT = 0.514444  # m/s


def _knots(value: float) -> str:
    """`` (speeds are in m/s: 100 kt would be 51.4 m/s)`` when ``value`` in knots would be a speed."""
    ms = value * KNOT
    if not SPEED_RANGE[0] <= ms <= SPEED_RANGE[1]:
        return ""
    return f" (speeds are in m/s: {value:g} kt would be {ms:.3g} m/s, or write {value:g}kt)"


SPEED_UNITS = {"m/s": 1.0, "kt": KNOT, "kn": KNOT, "km/h": 1 / 3.6, "ft/s": 0.3048, "mph": 0.44704}
"""Units a flight speed on the command line may carry (factor to m/s)."""

flight_speed = Within(*SPEED_RANGE, "m/s", "the flight speeds the model covers (rearward flight to 175 kt)", _knots,
                      SPEED_UNITS)
climb_rate = Within(*CLIMB_RANGE, "m/s", "the climb rates the model covers (4000 ft/min down or up)")


def range_ends(lo: str, hi: str, limits: Within) -> tuple[float, float]:
    """LO and HI of a range in ``limits``' unit, each a bare number or with one of its units
    (``0:100kt``: a unit on one end is the other's too); :class:`Bad` outside its range."""
    units = [limits._split(t)[1] for t in (lo, hi)]
    given = [u for u in units if u]
    if len(given) == 1:
        lo, hi = (t if u else f"{t}{given[0]}" for t, u in zip((lo, hi), units))
    return limits(lo), limits(hi)


def speed_ends(lo: str, hi: str) -> tuple[float, float]:
    """LO and HI of a range of flight speeds (m/s), either with a unit (``0:100kt``)."""
    return range_ends(lo, hi, flight_speed)


def parse_speeds(text: str):
    """``"LO:HI:N"`` -> N speeds (m/s) from LO to HI (``0:100kt:11``: in knots)."""
    import numpy as np

    try:
        lo, hi, n = text.split(":")
        (lo, hi), n = speed_ends(lo, hi), int(n)
        values = np.linspace(lo, hi, n)
    except Bad as exc:
        raise ValueError(f"sweep {text!r}: {exc}") from None
    except ValueError:
        raise ValueError(f"sweep {text!r}: expected LO:HI:N (speeds in m/s, or with a unit: 0:100kt:11), "
                         "e.g. 0:60:13") from None
    if not (len(values) >= 1 and np.all(np.isfinite(values))):
        raise ValueError(f"sweep {text!r}: need N >= 1 finite speeds")
    if len(values) == 1 and float(lo) != float(hi):
        raise ValueError(f"sweep {text!r}: N = 1 gives {lo:g} m/s only, never {hi:g}; give N >= 2, or --speed {lo:g}")
    for v in (values[0], values[-1]):
        try:
            flight_speed.check(v)
        except Bad as exc:
            raise ValueError(f"sweep {text!r}: {exc}") from None
    return values


def within(low: float, high: float, unit: str, what: str = "the range it takes") -> Within:
    """Type: a finite number in ``[low, high]`` (``unit`` named in the message)."""
    return Within(low, high, unit, what)


def positive_at_most(high: float, why: Callable[[str, float], str]) -> Callable[[str], float]:
    """Type: a positive finite number at most ``high``; ``why(text, value)`` says what a larger
    one would mean and what to give."""
    def convert(text: str) -> float:
        value = real_number(0.0, strict=True)(text)
        if value > high:
            raise Bad(why(text, value))
        return value
    return convert


def fraction(text: str) -> float:
    """Type: a fraction in (0, 1] (0.01 is 1 %)."""
    value = real_number(0.0, strict=True)(text)
    if value > 1:
        raise Bad(f"{text} is a fraction and must be at most 1 (0.01 is 1 %; {text} would be {100 * value:g} %)")
    return value


def tolerance(text: str) -> float:
    """Type: a residual tolerance in (0, 1e-3]: a looser one is no solution."""
    value = real_number(0.0, strict=True)(text)
    if value > 1e-3:
        raise Bad(f"{text} is too loose for a periodic solution (at most 1e-3; the default 1e-10 is reached in a few "
                  "iterations)")
    return value


positive_int = whole_number(1)
non_negative_int = whole_number(0)
port = whole_number(1, 65535)
finite = real_number()
positive = real_number(0.0, strict=True)
non_negative = real_number(0.0)


def checked_by(parse: Callable[[str], object]) -> Callable[[str], str]:
    """Type: the text unchanged, after ``parse(text)`` accepted it (its ValueError refuses it)."""
    def convert(text: str) -> str:
        try:
            parse(text)
        except ValueError as exc:
            raise Bad(str(exc)) from None
        return text
    return convert


def folder_problem(path: Path) -> str | None:
    """Why the folder ``path`` cannot be created or written, or None when it can. Nothing is
    created: a temporary file is written and removed in the nearest existing folder."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        return f"{path} exists and is not a folder"
    existing = path
    while not existing.exists() and existing != existing.parent:
        existing = existing.parent
    if not existing.is_dir():
        return f"{existing} is a file, not a folder"
    try:
        with tempfile.TemporaryFile(dir=existing, prefix=".heli-write-test-"):
            pass
    except OSError as exc:  # ENOENT from an existing folder: a virtual file system such as /proc
        reason = "it accepts no new files" if exc.errno == errno.ENOENT else exc.strerror or type(exc).__name__
        return f"{existing} is not writable ({reason})"
    return None


def _named(text: str, what: str) -> None:
    """Refuse an empty name (``Path('')`` is the working folder: nothing the user meant)."""
    if not text.strip():
        raise Bad(f"{text!r} is empty; give a {what}")


FILE_SUFFIXES = (".csv", ".json", ".png", ".html", ".fmu", ".toml", ".parquet", ".mat", ".npz", ".ssp")


def output_folder(text: str) -> Path:
    """Type: a folder that can be created or written (not an empty name, nor a new folder named
    like a file: ``--out run.csv`` would make a folder called run.csv)."""
    _named(text, "folder name ('.' for the working folder)")
    path = Path(text).expanduser()
    if path.suffix.lower() in FILE_SUFFIXES and not path.is_dir():
        raise Bad(f"{text!r} is named like a file, but --out is the folder the files are written into; give a folder "
                  f"(e.g. {str(path.with_suffix('')) or 'out'!r})")
    problem = folder_problem(path)
    if problem:
        raise Bad(f"cannot write to {text!r}: {problem}")
    return path


def output_file(*suffixes: str) -> Callable[[str], Path]:
    """Type: a file path ending in one of ``suffixes`` (any when none) whose folder can be
    created or written."""
    def convert(text: str) -> Path:
        _named(text, "file name")
        path = Path(text).expanduser()
        if suffixes and path.suffix.lower() not in suffixes:
            raise Bad(f"{text!r} must be a file name ending in {' or '.join(suffixes)}")
        if path.is_dir():
            raise Bad(f"{text!r} is a folder; give a file name")
        problem = folder_problem(path.parent)
        if problem:
            raise Bad(f"cannot write {text!r}: {problem}")
        return path
    return convert


def scene_names() -> list[str]:
    """The registered scenes, in registration order."""
    from mbs import scenes

    return list(scenes.all_scenes())


def add_scene(p: argparse.ArgumentParser, *flags: str, what: str = "scene", **kwargs) -> None:
    """Add a scene argument (positional unless ``flags`` are given) that accepts the
    registered scenes only and lists them in its help."""
    names = scene_names()
    p.add_argument(*(flags or ("scene",)), choices=names, metavar="SCENE",
                   help=f"{what}: {', '.join(names)} ('heli scenes' describes them)", **kwargs)


def aircraft_file(text: str):
    """Type: an aircraft (a packaged aircraft's name or an aircraft file), loaded and checked;
    the first problem of a broken file, naming its entry, refuses it."""
    from mbs import aircraft

    try:
        return aircraft.load(text)
    except aircraft.AircraftError as exc:
        raise Bad(str(exc)) from None


def add_aircraft(p: argparse.ArgumentParser) -> None:
    """Add ``--aircraft FILE``: the helicopter scenes built from another aircraft."""
    from mbs import aircraft

    p.add_argument("--aircraft", metavar="FILE", type=aircraft_file, default=None,
                   help="aircraft file (or the name of a packaged aircraft: "
                        f"{', '.join(aircraft.packaged())}; default bo105) of which the helicopter scenes are "
                        "built; 'heli aircraft new NAME' writes a template, 'heli aircraft check FILE' checks it")


def matrix_file(text: str) -> Path:
    """Type: a writable ``.mat`` (MATLAB, needs scipy) or ``.npz`` file, any case of the suffix."""
    path = output_file(".mat", ".npz")(text)
    if path.suffix.lower() == ".mat":
        try:
            import scipy.io  # noqa: F401
        except ImportError:
            raise Bad(f"{text!r}: writing .mat files needs scipy (pip install scipy), or give a .npz file") from None
    return path


def input_table(text: str):
    """Type: an input table (:func:`mbs.inputs.read_table`): the first problem, naming its line and
    column, refuses it; names and ranges are checked against the scene later, before any build."""
    from mbs.inputs import read_table

    _named(text, "CSV file name")
    try:
        return read_table(text)
    except ValueError as exc:
        raise Bad(str(exc)) from None
