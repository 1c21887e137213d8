"""Units of the aircraft file: parse a unit text, check its dimension, convert to SI.

A unit text is a product of symbols with optional integer powers, each ``/`` dividing by the
product after it (left to right, parentheses grouping): ``kg m^2``, ``slug ft^2``, ``N m/rad``,
``N m s/rad``, ``kg/m^3``, ``1/rad^2``, ``ft lbf``, ``deg/in``, ``deg/%`` (``%`` a hundredth),
``ft/s^2/in`` and ``(ft/s^2)/in`` (both ``ft/(s^2 in)``). Angles are a dimension of their own
(``rad``, ``deg``, ``rev``), so ``rpm`` converts to ``rad/s`` and ``1/deg`` to ``1/rad``, but an
angle never passes for a number. ``-`` (or ``1``) is a pure number and ``1/rev`` a frequency ratio
per revolution (which converts to nothing else).

Units as reports print them are read too: a hyphen between symbols multiplies (``ft-lb``,
``slug-ft2``), a power may follow its symbol without ``^`` (``ft2``), a trailing period is
dropped (``in.``), common spellings are aliases (``sec``, ``kn``, ``kts``, ``knots``, ``lbs``,
``degrees``, ``feet``, ``psf`` ...), and a symbol in capitals (``FT``, ``DEG``, ``SLUG``) is the
one symbol it spells in any case (``KN``, kilonewton or knot, is refused as ambiguous). Text copied
from a typeset report reads as well: superscript powers (``ft²``, ``s⁻¹``), ``°`` for degrees, a
middle or full stop between symbols (``slug·ft²``, ``N.m``, ``kg.m2``), ``sq ft`` and ``cu ft``,
``**`` for a power, ``shp`` (shaft horsepower) and ``kgf``; a period after any symbol
(``in.-lb``, ``in.²``), ``/rad`` and ``per rad`` for ``1/rad``, ``psi``, ``fpm``, ``mph`` and ``KTAS``
(``KIAS``, ``KCAS`` and ``KEAS`` are refused: they need the air to become true airspeeds).
``lb`` is a mass, and a pound-force where a force, moment or pressure is wanted (``lb``,
``ft lb``, ``lb/ft^2``); ``A/B/C`` whose left-to-right reading is of the wrong kind is read
``A/(B/C)`` where that is of the kind wanted (a damping in ``ft-lb/rad/sec``, per radian per
second). :func:`factor_to` reads them so, and :func:`how_read` says when it did.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass

# dimension exponents: length, mass, time, angle
_LB = 0.45359237  # kg
_FT = 0.3048  # m
_G0 = 9.80665  # m/s^2
SYMBOLS: dict[str, tuple[float, tuple[int, int, int, int]]] = {
    "m": (1.0, (1, 0, 0, 0)), "cm": (0.01, (1, 0, 0, 0)), "mm": (1e-3, (1, 0, 0, 0)), "km": (1e3, (1, 0, 0, 0)),
    "ft": (_FT, (1, 0, 0, 0)), "in": (0.0254, (1, 0, 0, 0)),
    "kg": (1.0, (0, 1, 0, 0)), "g": (1e-3, (0, 1, 0, 0)), "lb": (_LB, (0, 1, 0, 0)), "lbm": (_LB, (0, 1, 0, 0)),
    "slug": (_LB * _G0 / _FT, (0, 1, 0, 0)),
    "s": (1.0, (0, 0, 1, 0)), "min": (60.0, (0, 0, 1, 0)), "h": (3600.0, (0, 0, 1, 0)),
    "rad": (1.0, (0, 0, 0, 1)), "deg": (math.pi / 180, (0, 0, 0, 1)), "rev": (2 * math.pi, (0, 0, 0, 1)),
    "N": (1.0, (1, 1, -2, 0)), "kN": (1e3, (1, 1, -2, 0)), "lbf": (_LB * _G0, (1, 1, -2, 0)),
    "W": (1.0, (2, 1, -3, 0)), "kW": (1e3, (2, 1, -3, 0)), "hp": (745.69987158227022, (2, 1, -3, 0)),
    "J": (1.0, (2, 1, -2, 0)), "Pa": (1.0, (-1, 1, -2, 0)),
    "percent": (0.01, (0, 0, 0, 0)),
    "kt": (1852.0 / 3600, (1, 0, -1, 0)), "rpm": (2 * math.pi / 60, (0, 0, -1, 1)), "Hz": (1.0, (0, 0, -1, 0)),
}
ALIASES = {"sec": "s", "secs": "s", "hr": "h", "kn": "kt", "kts": "kt", "knot": "kt", "knots": "kt", "lbs": "lb",
           "degree": "deg", "degrees": "deg", "radian": "rad", "radians": "rad", "inch": "in",
           "inches": "in", "foot": "ft", "feet": "ft", "revs": "rev", "shp": "hp", "slugs": "slug", "degs": "deg",
           "rads": "rad", "hrs": "h", "mins": "min"}
"""Spellings of the symbols as reports print them."""
SYMBOLS["psf"] = (_LB * _G0 / _FT**2, (-1, 1, -2, 0))  # pounds-force per square foot (disc loading)
SYMBOLS["kgf"] = (_G0, (1, 1, -2, 0))  # kilogram-force (kilopond)
SYMBOLS["psi"] = (_LB * _G0 / 0.0254**2, (-1, 1, -2, 0))  # pounds-force per square inch
SYMBOLS["fpm"] = (_FT / 60, (1, 0, -1, 0))  # feet per minute (rate of climb)
ALIASES["KTAS"] = "kt"  # knots true airspeed
SYMBOLS["mph"] = (1609.344 / 3600, (1, 0, -1, 0))  # statute miles per hour
SYMBOLS["arcmin"] = (math.pi / 180 / 60, (0, 0, 0, 1))  # minutes of arc (1 deg 11' = 71 arcmin)
SYMBOLS["arcsec"] = (math.pi / 180 / 3600, (0, 0, 0, 1))  # seconds of arc
NOT_TRUE_AIRSPEED = {"KIAS": "indicated", "KCAS": "calibrated", "KEAS": "equivalent"}
"""Airspeeds a unit cannot convert: they need the air's density (and the pitot's errors)."""
DIMENSIONLESS = ("-", "1", "")
NON_DIMENSIONAL = ("N-D", "N.D.", "ND", "n.d.", "nd", "non-dimensional", "nondimensional", "dimensionless", "none")
"""Spellings of a pure number in reports (``N-D`` in NASA tables), read whole and in any case."""
PER_REV = "1/rev"
NAMES = {(1, 0, 0, 0): "a length", (0, 1, 0, 0): "a mass", (0, 0, 0, 1): "an angle",
         (2, 1, 0, 0): "a moment of inertia", (0, 0, -1, 1): "an angular velocity", (1, 0, -1, 0): "a speed",
         (1, 1, -2, 0): "a force", (2, 1, -2, 0): "a moment", (2, 1, -2, -1): "a stiffness per angle",
         (2, 1, -1, -1): "a damping per angular rate", (3, 1, -2, 0): "a bending stiffness",
         (0, 0, 0, -1): "a per-angle slope", (0, 0, 0, -2): "a per-angle-squared coefficient",
         (2, 1, -3, 0): "a power", (-3, 1, 0, 0): "a density", (1, 0, -2, 0): "an acceleration",
         (2, 0, 0, 0): "an area", (3, 0, 0, 0): "a volume", (0, 0, 0, 0): "a pure number"}
_TOKEN = re.compile(r"^([A-Za-z]+)(?:\^?(-?\d+))?$")
_PRODUCT_HYPHEN = re.compile(r"(?<=[A-Za-z0-9])-(?=[A-Za-z])")
_PRODUCT_STOP = re.compile(r"(?<=[A-Za-z0-9])\.(?=[A-Za-z])")
_SUPERSCRIPT = re.compile("⁻?[⁰¹²³⁴⁵⁶⁷⁸⁹]+")
_DIGITS = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻", "0123456789-")
_SQUARE_CUBE = re.compile(r"\b(sq|cu)(?:\.\s*|\s+)([A-Za-z]+)", re.IGNORECASE)
_ABBREVIATION = re.compile(r"(?<=[A-Za-z])\.(?![A-Za-z0-9])")  # 'in.-lb', 'in.^2', 'deg./in.'
_PER = re.compile(r"\bper\b")


class UnitError(ValueError):
    """A unit text that cannot be read, or whose dimension is not the one expected."""


@dataclass(frozen=True)
class Unit:
    """A parsed unit: ``value_in_si = factor * value``; ``dims`` the exponents of length,
    mass, time and angle; ``per_rev`` for the frequency ratio ``1/rev``."""

    factor: float
    dims: tuple[int, int, int, int]
    per_rev: bool = False

    def describe(self) -> str:
        """``"a force"``, or for a dimension without a name ``"a quantity in m^3/rad"`` (SI)."""
        if self.per_rev:
            return "a frequency per revolution"
        return NAMES.get(self.dims, f"a quantity in {si_text(self.dims)}")


def si_text(dims: tuple[int, int, int, int]) -> str:
    """The SI unit of the dimension exponents ``dims`` (length, mass, time, angle): ``m^3/rad``."""
    def part(sign):
        return " ".join(f"{s}^{abs(p)}" if abs(p) != 1 else s for s, p in zip(("m", "kg", "s", "rad"), dims)
                        if p * sign > 0)
    up, down = part(1) or "1", part(-1)
    return f"{up}/{down}" if " " not in down and down else f"{up}/({down})" if down else up


def parse(text: str, pound_force: bool = False) -> Unit:
    """The :class:`Unit` of ``text``; :class:`UnitError` naming the symbol it cannot read.
    ``pound_force``: ``lb`` is the pound-force (``lbf``), not the pound."""
    text, typed = text.strip(), _untypeset(text.strip())
    if text.upper() in NOT_TRUE_AIRSPEED:
        raise UnitError(f"unit {text!r}: an {NOT_TRUE_AIRSPEED[text.upper()]} airspeed, which the air's density "
                        "turns into the true airspeed the model flies: give KTAS (kt), converted at the point's "
                        "altitude")
    if typed in DIMENSIONLESS or text.lower() in {n.lower() for n in NON_DIMENSIONAL}:
        return Unit(1.0, (0, 0, 0, 0))
    if typed.replace(" ", "") == PER_REV:
        return Unit(1.0, (0, 0, 0, 0), per_rev=True)
    tokens = _tokens(typed)
    factor, dims, end = _quotient(tokens, 0, text, pound_force)
    if end != len(tokens):
        raise UnitError(f"unit {text!r}: unbalanced parentheses")
    return Unit(factor, dims)


def _untypeset(text: str) -> str:
    """``text`` with a typeset report's forms in the plain ones: superscript powers as ``^n``,
    ``°`` as ``deg``, ``**`` as ``^``, a stop between symbols as a space, ``sq ft`` as ``ft^2``,
    no abbreviation stops, ``per`` as ``/`` and a leading ``/`` as ``1/``."""
    text = _SUPERSCRIPT.sub(lambda m: "^" + m.group(0).translate(_DIGITS), text).replace("**", "^")
    text = _PRODUCT_STOP.sub(" ", text.replace("°", " deg ").replace("º", " deg "))
    text = _SQUARE_CUBE.sub(lambda m: f"{m.group(2)}^{2 if m.group(1).lower() == 'sq' else 3}", text)
    text = _PER.sub("/", _ABBREVIATION.sub("", text)).strip()
    return "1" + text if text.startswith("/") else text


def _tokens(typed: str) -> list[str]:
    """Symbols with their powers, ``/``, ``(`` and ``)``; a hyphen, ``*`` or ``·`` between symbols
    multiplies like a space."""
    typed = _PRODUCT_HYPHEN.sub(" ", typed.replace("*", " ").replace("·", " ").replace("%", " percent "))
    for mark in "/()":
        typed = typed.replace(mark, f" {mark} ")
    return typed.split()


def _quotient(tokens: list, i: int, text: str, pound_force: bool) -> tuple[float, tuple, int]:
    """Products divided left to right (``a/b c/d`` is ``a/(b c d)``), from ``tokens[i]``; returns
    the factor, the dimensions and the index after them."""
    factor, dims, i = _product(tokens, i, text, pound_force)
    while i < len(tokens) and tokens[i] == "/":
        f, d, i = _product(tokens, i + 1, text, pound_force)
        factor, dims = factor / f, tuple(a - b for a, b in zip(dims, d))
    return factor, dims, i


def _product(tokens: list, i: int, text: str, pound_force: bool) -> tuple[float, tuple, int]:
    """Symbols (with powers) and parenthesised quotients multiplied, from ``tokens[i]`` to the next
    ``/`` or ``)``."""
    factor, dims, start = 1.0, (0, 0, 0, 0), i
    while i < len(tokens) and tokens[i] not in ("/", ")"):
        if tokens[i] == "(":
            f, d, i = _quotient(tokens, i + 1, text, pound_force)
            if i >= len(tokens) or tokens[i] != ")":
                raise UnitError(f"unit {text!r}: unbalanced parentheses")
            i += 1
        else:
            f, d = _power(tokens[i].rstrip("."), text, pound_force)
            i += 1
        factor, dims = factor * f, tuple(a + b for a, b in zip(dims, d))
    if i == start:
        raise UnitError(f"unit {text!r}: a symbol is missing around '/' or in '()'")
    return factor, dims, i


def _power(token: str, text: str, pound_force: bool) -> tuple[float, tuple]:
    """The factor and dimensions of one symbol with its power (``ft^2``, ``ft2``, ``s-1``; ``1``)."""
    if token == "1":
        return 1.0, (0, 0, 0, 0)
    match = _TOKEN.match(token)
    if not match:
        raise UnitError(f"unit {text!r}: cannot read {token!r}; write symbols with powers, e.g. 'slug ft^2'")
    name = _symbol(match.group(1), text)
    if pound_force and name == "lb":
        name = "lbf"
    power = int(match.group(2) or 1)
    f, d = SYMBOLS[name]
    return f**power, tuple(power * b for b in d)


def _symbol(name: str, text: str) -> str:
    """The symbol ``name`` stands for: itself, an alias, or the one symbol or alias it spells in
    another case; :class:`UnitError` when none or several."""
    if name in SYMBOLS:
        return name
    if name in ALIASES:
        return ALIASES[name]
    spelled = sorted(k for k in (*SYMBOLS, *ALIASES) if k.lower() == name.lower())
    meant = {ALIASES.get(k, k) for k in spelled}
    if len(meant) == 1:
        return meant.pop()
    if spelled:
        raise UnitError(f"unit {text!r}: {name!r} could be {' or '.join(spelled)}; write the symbol in its own case")
    raise UnitError(f"unit {text!r}: unknown symbol {name!r}; known: {', '.join(SYMBOLS)} "
                    f"(and {', '.join(ALIASES)})")


def _matches(have: Unit, want: Unit) -> bool:
    return have.dims == want.dims and have.per_rev == want.per_rev


def _readings(text: str):
    """``(unit, lb a pound-force, text as read)`` in the order :func:`reading` tries them: as
    written, then ``lb`` the pound-force, then each with ``A/B/C`` grouped ``A/(B/C)``."""
    grouped = _grouped(text)
    for written in (text, grouped) if grouped else (text,):
        for force in (False, True):
            yield parse(written, pound_force=force), force, written


def _grouped(text: str) -> str | None:
    """``A/(B/C ...)`` for a text ``A/B/C ...`` with two or more slashes and no parentheses."""
    if "(" in text or text.count("/") < 2:
        return None
    first, rest = text.split("/", 1)
    return f"{first}/({rest})" if first.strip() else None


def _reading(text: str, kinds) -> tuple[Unit, bool, str]:
    """:func:`reading` with whether ``lb`` was read as the pound-force and the text as read."""
    found = (r for r in _readings(text) if r[0].dims in kinds and not (r[1] and r[0].per_rev))
    return next(found, None) or (parse(text), False, text)


def reading(text: str, kinds) -> Unit:
    """The :class:`Unit` of ``text`` as one of ``kinds`` (dimension tuples) asks: :func:`parse`'s,
    or with ``lb`` the pound-force when only that reading is of one of them (a force, moment or
    pressure printed in ``lb``, ``ft lb``, ``lb/ft^2``), or ``A/B/C`` as ``A/(B/C)`` when only
    that is (``ft-lb/rad/sec``, a damping); the caller checks the kind."""
    return _reading(text, kinds)[0]


def pound_force(text: str, target: str) -> bool:
    """Whether ``text`` is read with ``lb`` as the pound-force to be of ``target``'s kind."""
    return _reading(text, [parse(target).dims])[1]


def how_read(text: str, target: str) -> str:
    """What a conversion list says of ``text`` read as ``target``'s kind: ``" (lb as
    pound-force)"``, ``" (read as ft-lb/(rad/sec))"``, both, or ``""``."""
    _, force, written = _reading(text, [parse(target).dims])
    notes = (["lb as pound-force"] if force else []) + ([f"read as {written}"] if written != text else [])
    return f" ({'; '.join(notes)})" if notes else ""


def factor_to(text: str, target: str) -> float:
    """The factor taking a value in the unit ``text`` to the unit ``target`` (``lb`` a pound-force
    where that makes it of ``target``'s kind: :func:`reading`); :class:`UnitError` when the two
    are not of the same kind."""
    want = parse(target)
    have = reading(text, [want.dims])
    if not _matches(have, want):
        hint = " (minutes of arc are arcmin: 1 deg 11' is 71 arcmin)" if "min" in text.split() and \
            want.dims == SYMBOLS["rad"][1] else ""
        raise UnitError(f"unit {text!r} is {have.describe()}, not {want.describe()} like {target!r}{hint}")
    return have.factor / want.factor


def convert(value, text: str, target: str):
    """``value`` (a number or nested lists of numbers) in ``text`` expressed in ``target``."""
    f = factor_to(text, target)
    return _scale(value, f)


def _scale(value, f: float):
    if isinstance(value, list):
        return [_scale(v, f) for v in value]
    return value * f


POSITION_KINDS = {(1, 0, 0, 0): "m", (0, 0, 0, 1): "rad", (0, 0, 0, 0): "-"}
"""What a pilot control's position may be, and its SI unit."""


def position_kind(unit: str) -> str:
    """The SI unit (m, rad, -) of a pilot control's position in ``unit``; ValueError otherwise."""
    u = parse(unit)
    if u.per_rev or u.dims not in POSITION_KINDS:
        raise ValueError(f"unit {unit!r} is {u.describe()}: a control's position is a length (in), an angle (deg) "
                         "or a fraction (%)")
    return POSITION_KINDS[u.dims]
