"""Published validation data: trims, stability and control derivatives and eigenvalues against
speed, each series with its unit, source, reading uncertainty and tolerance.

A validation file (TOML) names the aircraft and scene it is for, states the conventions of the
published data (axes, derivative normalisation, control angles and signs) and lists:

* ``[[trim]]``: a trimmed quantity against speed (``collective``, ``pitch``, ``engine.power`` ...);
* ``[[derivative]]``: a stability or control derivative against speed (``X_u``, ``L_θ1c`` ...);
* ``[[eigenvalues]]``: the published eigenvalues at one speed (``[re, im]`` pairs in 1/s, rad/s).

Every series has ``quantity``, ``unit``, ``value`` (a list), ``source`` (a key of ``[sources]``
or a text) and may have ``speed`` (default the file's ``[validation] speed``), ``mass``,
``altitude`` and ``cg_station`` or ``cg_x`` (the flight condition of each point, ``{ value = x or
[x per point], unit = "lb" }``; defaults in ``[validation]``; without them the aircraft file's
mass, air and CG), ``uncertainty`` (the reading or measurement error, in ``unit``),
``tolerance`` (``{ absolute = x }`` in ``unit`` or ``{ relative = x }``, a fraction; without it
the series is shown, not checked),
``ours_factor`` (the model's value is multiplied by it before the comparison: a sign convention
that differs, stated in ``note``) and ``note``. Speeds are in ``[validation] speed_unit``
(``mu``: the advance ratio V/(Omega R) of the aircraft file's rotor, turned into m/s by
:func:`resolve_speed`).
The CSV form (:mod:`mbs.validate.csvdata`) carries the same information, one point a row.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from mbs.aircraft import units
from mbs.environment import atmosphere as isa
from mbs.models.helicopter.environment import CG_SHIFT_LIMIT

KINDS = ("trim", "derivative")


class ValidationError(ValueError):
    """A validation file that cannot be read: the message names the file and the entry."""


@dataclass(frozen=True)
class Tolerance:
    """``|ours - published| <= absolute`` (in the series' unit), ``|ours / published - 1| <=
    relative``, or a published bound: ``ours <= published`` (``bound = "upper"``: a rating, a
    limit) or ``ours >= published`` (``"lower"``)."""

    absolute: float | None = None
    relative: float | None = None
    bound: str | None = None

    def within(self, ours: float, published: float) -> bool:
        if not (math.isfinite(ours) and math.isfinite(published)):
            return False
        if self.bound is not None:
            return ours <= published if self.bound == "upper" else ours >= published
        if self.absolute is not None:
            return abs(ours - published) <= self.absolute
        return published != 0.0 and abs(ours / published - 1.0) <= self.relative

    def describe(self, unit: str) -> str:
        if self.bound is not None:
            return f"the published value {'an upper' if self.bound == 'upper' else 'a lower'} bound of ours"
        return f"±{self.absolute:g} {unit}" if self.absolute is not None else f"±{100 * self.relative:g} %"


@dataclass(frozen=True)
class Series:
    """One published quantity against speed. ``speed`` in m/s, ``shown_speed`` in the file's
    speed unit; ``value`` and ``uncertainty`` (n,) in ``unit``."""

    kind: str
    quantity: str
    unit: str
    speed: np.ndarray
    shown_speed: np.ndarray
    value: np.ndarray
    uncertainty: np.ndarray
    source: str
    tolerance: Tolerance | None = None
    ours_factor: float = 1.0
    note: str = ""
    mass: np.ndarray | None = None  # (n,) kg: each point's flight mass (None: the aircraft file's)
    altitude: np.ndarray | None = None  # (n,) m: each point's ISA pressure altitude (None: the file's air)
    cg_x: np.ndarray | None = None  # (n,) m: each point's CG forward of the aircraft file's (None: the file's)
    cg_station: np.ndarray | None = None  # (n,) m: the CG's fuselage station as published (:func:`resolve_cg`)
    shown_conditions: tuple[str, ...] = ()  # each point's condition in the file's units ("4850 lb, 1000 ft")

    def conditions(self) -> list[tuple]:
        """Each point's flight condition ``(speed m/s, mass kg, altitude m, cg_x m)``, None where
        the aircraft file's holds."""
        if self.cg_station is not None:
            raise ValueError("the CG's stations are not yet read against the aircraft file's (resolve_cg)")
        n = len(self.speed)
        columns = [[None] * n if a is None else [float(x) for x in a] for a in (self.mass, self.altitude, self.cg_x)]
        return [(float(v), *rest) for v, *rest in zip(self.speed, *columns)]


def condition(point) -> tuple:
    """``(speed, mass, altitude, cg_x)`` of a speed (m/s) or a condition tuple (its missing tail
    None), rounded as the model's points are keyed."""
    speed, *rest = point if isinstance(point, tuple) else (point,)
    rest = [*rest, None, None, None][:3]
    return (round(float(speed), 9), *(None if x is None else round(x, 6) for x in rest))


def condition_key(speed: float, mass: float | None = None, altitude: float | None = None, cg_x: float | None = None):
    """The key of a model point: the speed (m/s, rounded) alone, or with its mass, altitude and CG."""
    key = condition((speed, mass, altitude, cg_x))
    return key[0] if key[1:] == (None, None, None) else key


def resolve_cg(v: "Validation", d) -> "Validation":
    """``v`` with each CG given as a fuselage station turned into ``cg_x`` (m forward of the
    aircraft data ``d``'s CG: stations grow aft); ValidationError without ``aircraft.cg_station``."""
    from dataclasses import replace

    if not any(s.cg_station is not None for s in v.series):
        return v
    file_cg = d["aircraft"].get("cg_station", ())
    if not len(file_cg):
        raise ValidationError(f"{v.path}: a CG given as cg_station needs the aircraft file's aircraft.cg_station (its "
                              "CG's stations); give cg_x (forward of the file's CG) instead")
    series = [s if s.cg_station is None else replace(s, cg_x=file_cg[0] - s.cg_station, cg_station=None)
              for s in v.series]
    low, high = CONDITIONS["cg_x"][1:]
    far = next((s for s in series if s.cg_x is not None and not ((low <= s.cg_x) & (s.cg_x <= high)).all()), None)
    if far is not None:
        x = far.cg_x[(far.cg_x < low) | (far.cg_x > high)][0]
        raise ValidationError(f"{v.path}: {far.quantity}: a CG {x:+.3f} m from the aircraft file's (cg_station "
                              f"{file_cg[0]:.4g} m) is more than {high:g} m away: check the stations' unit and datum")
    return replace(v, series=series)


@dataclass(frozen=True)
class EigenSet:
    """The published eigenvalues (n,) complex (1/s, rad/s) at one speed (m/s; ``shown_speed`` in
    the file's unit)."""

    speed: float
    shown_speed: float
    value: np.ndarray
    source: str
    note: str = ""
    altitude: float | None = None  # m: the ISA pressure altitude ([validation] altitude; None: the file's air)


@dataclass(frozen=True)
class EigenTolerance:
    """Modes keep their stability (real parts within ``±neutral`` 1/s count as neutral, which
    matches either) and oscillatory published modes (``|Im| >= min_frequency`` rad/s) their
    frequency within the fraction ``frequency``."""

    frequency: float = 0.25
    neutral: float = 0.02
    min_frequency: float = 0.05


@dataclass
class Validation:
    """A validation file, read and checked."""

    path: Path
    title: str
    aircraft: str
    scene: str
    speed_unit: str
    conventions: dict[str, str]
    sources: dict[str, str]
    series: list[Series] = field(default_factory=list)
    eigenvalues: list[EigenSet] = field(default_factory=list)
    eigen_tolerance: EigenTolerance | None = None
    per_unit: float = 1.0  # m/s per speed unit (an advance ratio's: the aircraft's tip speed, once resolved)

    @property
    def name(self) -> str:
        return self.path.stem

    def of_kind(self, kind: str) -> list[Series]:
        return [s for s in self.series if s.kind == kind]

    def cited_sources(self) -> set[str]:
        """The keys of ``[sources]`` that a series' or eigenvalue set's source names (anywhere in it)."""
        words = {w for x in [*self.series, *self.eigenvalues] for w in re.split(r"[\s;,()]+", x.source)}
        return set(self.sources) & words

    def speeds(self, *kinds: str) -> list[float]:
        """The distinct speeds (m/s, ascending) of the series of ``kinds`` (and of the
        eigenvalues when ``"eigenvalues"`` is one of them)."""
        found = [v for s in self.series if s.kind in kinds for v in s.speed]
        found += [e.speed for e in self.eigenvalues] if "eigenvalues" in kinds else []
        return sorted({round(float(v), 9) for v in found})

    def conditions(self, *kinds: str) -> list[tuple]:
        """The distinct flight conditions ``(speed, mass, altitude, cg_x)`` of the series of ``kinds``
        (and of the eigenvalues when ``"eigenvalues"`` is one of them), as :func:`condition_key`
        rounds them."""
        found = [c for s in self.series if s.kind in kinds for c in s.conditions()]
        found += [(e.speed, None, e.altitude, None) for e in self.eigenvalues] if "eigenvalues" in kinds else []
        keys = {condition(c): c for c in found}
        return [keys[k] for k in sorted(keys, key=lambda k: tuple(x or 0.0 for x in k))]


def from_dict(raw: dict, path: Path) -> Validation:
    """A :class:`Validation` from the parsed TOML ``raw`` of the file ``path``."""
    head = _table(raw, "validation", path)
    speed_unit = _text(head, "speed_unit", path, "[validation]", default="m/s")
    factor = 1.0 if speed_unit in ADVANCE_RATIO else speed_factor(speed_unit, f"{path}: [validation] speed_unit")
    out = Validation(path, _text(head, "title", path, "[validation]", default=path.stem),
                     _text(head, "aircraft", path, "[validation]"), _text(head, "scene", path, "[validation]",
                                                                          default="forward-flight"),
                     speed_unit, _strings(raw.get("conventions", {}), path, "[conventions]"),
                     _strings(raw.get("sources", {}), path, "[sources]"), per_unit=factor)
    unknown = set(head) - {"title", "aircraft", "scene", "speed_unit", "speed", *CONDITIONS}
    if unknown:
        raise ValidationError(f"{path}: [validation]: unknown key(s) {', '.join(sorted(unknown))}; the keys are "
                              "title, aircraft, scene, speed_unit, speed, mass, altitude, cg_station, cg_x")
    default_speed = head.get("speed")
    defaults = {k: head[k] for k in CONDITIONS if k in head}
    for kind in KINDS:
        for k, entry in enumerate(raw.get(kind, [])):
            where = entry.pop("_where", None) or f"[[{kind}]] {k + 1}"  # a CSV file's rows say their lines
            out.series.append(series(entry, kind, f"{path}: {where}", default_speed, factor, defaults))
    altitude = _eigen_altitude(defaults.get("altitude"), path) if raw.get("eigenvalues") else None
    for k, entry in enumerate(raw.get("eigenvalues", [])):
        out.eigenvalues.append(eigen_set(entry, f"{path}: [[eigenvalues]] {k + 1}", factor,
                                         None if altitude is None else float(altitude[0])))
    _condition_problems(out, path, [k for k in ("mass", "cg_station", "cg_x") if k in defaults])
    _sources_named(out, path)
    if "eigenvalue_tolerance" in raw:
        out.eigen_tolerance = eigen_tolerance(raw["eigenvalue_tolerance"], f"{path}: [eigenvalue_tolerance]")
    unknown = set(raw) - {"validation", "conventions", "sources", "eigenvalue_tolerance", "eigenvalues", *KINDS}
    if unknown:
        raise ValidationError(f"{path}: unknown section(s) {', '.join(sorted(unknown))}; the sections are [validation], "
                              "[conventions], [sources], [eigenvalue_tolerance], [[trim]], [[derivative]], [[eigenvalues]]")
    if not out.series and not out.eigenvalues:
        raise ValidationError(f"{path}: no [[trim]], [[derivative]] or [[eigenvalues]] entries: nothing to compare")
    return out


ADVANCE_RATIO = ("mu", "advance ratio")
"""Speed units read as the advance ratio V/(Omega R), of the aircraft file's rotor speed and radius."""


def resolve_speed(v: "Validation", d) -> "Validation":
    """``v`` with speeds given as advance ratios (:data:`ADVANCE_RATIO`) in m/s: times the main
    rotor's tip speed Omega R of the aircraft data ``d``."""
    from dataclasses import replace

    if v.speed_unit not in ADVANCE_RATIO:
        return v
    tip = d["main_rotor"]["omega"] * d["main_rotor"]["radius"]
    return replace(v, per_unit=tip, series=[replace(s, speed=s.shown_speed * tip) for s in v.series],
                   eigenvalues=[replace(e, speed=e.shown_speed * tip) for e in v.eigenvalues])


def speed_factor(unit: str, where: str) -> float:
    """m/s per unit of the speed unit ``unit``; :class:`ValidationError` for a unit that is no speed."""
    try:
        u = units.parse(unit)
    except units.UnitError as exc:
        raise ValidationError(f"{where}: {exc}") from None
    if u.dims != (1, 0, -1, 0):
        raise ValidationError(f"{where}: {unit!r} is {u.describe()}, not a speed (kn, kt, m/s, km/h, mph, or mu for the "
                              "advance ratio)")
    return u.factor


KEYS = {"quantity", "unit", "value", "speed", "uncertainty", "tolerance", "source", "ours_factor", "note", "mass",
        "altitude", "cg_station", "cg_x"}
CONDITIONS = {"mass": ("kg", 1.0, 1e5), "altitude": ("m", *isa.ALTITUDE_RANGE), "cg_station": ("m", -1e4, 1e4),
              "cg_x": ("m", -CG_SHIFT_LIMIT, CG_SHIFT_LIMIT)}
"""A point's flight condition: its SI unit and bounds (the ISA's altitudes, as ``--altitude``; the
CG within 1 m of the file's, the model's ``cg_x``)."""


def _sources_named(v: "Validation", path: Path) -> None:
    """With ``[sources]``, every series' and eigenvalue set's source begins with one of its keys
    ("P1 Fig. 4.10(a); H": P1)."""
    if not v.sources:
        return
    used = [x.source for x in [*v.series, *v.eigenvalues]]
    unknown = sorted({u for u in used if re.split(r"[\s;,]+", u.strip())[0] not in v.sources})
    if unknown:
        raise ValidationError(f"{path}: source(s) {', '.join(map(repr, unknown))} do not begin with a key of "
                              f"[sources] ({', '.join(v.sources)}): add it to [sources], or correct the series")


def _eigen_altitude(raw, path: Path) -> np.ndarray | None:
    """``[validation]``'s altitude as the eigenvalue sets' default: one number (a list is one per
    default speed, for the trims and derivatives)."""
    if isinstance(raw, dict) and isinstance(raw.get("value"), list):
        raise ValidationError(f"{path}: [validation]: altitude as a list (one per point) gives the [[eigenvalues]] "
                              "none: give one number here (theirs) and the lists on the [[trim]] and [[derivative]] "
                              "series")
    return _condition(raw, "altitude", 1, f"{path}: [validation]")


def _condition(raw, key: str, n: int, where: str) -> np.ndarray | None:
    """A condition ``{ value = x or [n numbers], unit = "..." }`` as (n,) SI, or None."""
    if raw is None:
        return None
    si, low, high = CONDITIONS[key]
    if not isinstance(raw, dict) or set(raw) != {"value", "unit"}:
        raise ValidationError(f"{where}: {key} must be {{ value = x or [one per point], unit = \"...\" }}, "
                              f"not {raw!r}")
    try:
        scale = units.factor_to(str(raw["unit"]), si)
    except units.UnitError as exc:
        raise ValidationError(f"{where}: {key}: {exc}") from None
    value = raw["value"]
    values = np.full(n, float(value)) if _is_number(value) else _numbers(value, where, f"{key} value")
    if len(values) != n:
        raise ValidationError(f"{where}: {key} has {len(values)} values for {n} points; give one, or one per point")
    values = values * scale
    bad = values[(values < low) | (values > high)]
    if len(bad):
        raise ValidationError(f"{where}: {key} {bad[0] / scale:g} {raw['unit']} is outside {low:g} to {high:g} {si}")
    return values


def _condition_problems(v: "Validation", path: Path, file_only: list[str]) -> None:
    """A mass or CG only on trims (the derivatives' mass and inertia are the aircraft file's), one
    CG form per series, and an altitude for every point or none (the ISA, or the aircraft file's
    air, for the whole file); ``file_only``: the trim-only conditions [validation] gives."""
    others = [s for s in v.series if s.kind != "trim"] + list(v.eigenvalues)
    trim_only = ("mass", "cg_station", "cg_x")
    derived = next((s for s in v.series if s.kind != "trim" and any(getattr(s, k) is not None for k in trim_only)),
                   None)
    if derived is not None or (file_only and others):
        raise ValidationError(f"{path}: mass and the CG apply to [[trim]] series (the weight's size and point); "
                              "derivatives and eigenvalues take the aircraft file's mass, CG and inertia: write an "
                              "aircraft file for that condition" + (f" ({derived.quantity})" if derived else ""))
    both = next((s for s in v.series if s.cg_station is not None and s.cg_x is not None), None)
    if both is not None:
        raise ValidationError(f"{path}: {both.quantity}: give the CG once, as cg_station or as cg_x")
    given = [s.altitude is not None for s in v.series] + [e.altitude is not None for e in v.eigenvalues]
    if any(given) and not all(given):
        missing = next(s.quantity for s in v.series if s.altitude is None) if not all(given[:len(v.series)]) \
            else "the eigenvalues"
        raise ValidationError(f"{path}: altitude given for some points but not for {missing}: give it there, or as "
                              "[validation] altitude for every series")


def series(entry: dict, kind: str, where: str, default_speed, factor: float, defaults: dict | None = None) -> Series:
    """One ``[[trim]]`` or ``[[derivative]]`` entry, checked (``defaults``: ``[validation]``'s
    conditions)."""
    unknown = set(entry) - KEYS
    if unknown:
        raise ValidationError(f"{where}: unknown key(s) {', '.join(sorted(unknown))}; the keys are {', '.join(sorted(KEYS))}")
    quantity, unit = _text(entry, "quantity", where), _text(entry, "unit", where)
    _unit(unit, where)
    value = _numbers(entry.get("value"), where, "value")
    speed = _numbers(entry.get("speed", default_speed), where, "speed (or [validation] speed)")
    if len(speed) != len(value):
        raise ValidationError(f"{where} ({quantity}): {len(value)} values for {len(speed)} speeds")
    if (speed < 0).any():
        raise ValidationError(f"{where} ({quantity}): speed {speed[speed < 0][0]:g} is negative")
    unc = entry.get("uncertainty", 0.0)
    unc = np.full(len(value), float(unc)) if _is_number(unc) else _numbers(unc, where, "uncertainty")
    if len(unc) != len(value) or (unc < 0).any():
        raise ValidationError(f"{where} ({quantity}): uncertainty must be one number >= 0 or one per value")
    ours_factor = entry.get("ours_factor", 1.0)
    if not _is_number(ours_factor) or ours_factor == 0:
        raise ValidationError(f"{where} ({quantity}): ours_factor = {ours_factor!r} must be a non-zero number")
    if ours_factor != 1.0 and not entry.get("note"):
        raise ValidationError(f"{where} ({quantity}): ours_factor = {ours_factor:g} needs a note saying why")
    tol = tolerance(entry.get("tolerance"), f"{where} ({quantity})")
    if tol is not None and tol.relative is not None and (value == 0).any():
        raise ValidationError(f"{where} ({quantity}): a relative tolerance cannot judge the published value 0 at "
                              f"{speed[value == 0][0]:g}; give {{ absolute = x }} in {unit}")
    given = {k: entry.get(k, (defaults or {}).get(k)) for k in CONDITIONS}
    read = {k: _condition(given[k], k, len(value), f"{where} ({quantity})") for k in CONDITIONS}
    return Series(kind, quantity, unit, speed * factor, speed, value, unc, _text(entry, "source", where), tol,
                  float(ours_factor), str(entry.get("note", "")), **read,
                  shown_conditions=shown_conditions(given, len(value)))


SHOWN = {"mass": "{:g} {}", "altitude": "{:g} {}", "cg_station": "CG at station {:g} {}",
         "cg_x": "CG {:+g} {} forward"}
"""How a point's condition is echoed, in the file's own numbers and units."""


def shown_conditions(given: dict, n: int) -> tuple[str, ...]:
    """Each of ``n`` points' conditions as the file gives them (``given``: the checked
    ``{ value, unit }`` of each condition, None where not given); () without any."""
    columns = [[SHOWN[k].format(float(x), raw["unit"]) for x in
                (np.full(n, float(raw["value"])) if _is_number(raw["value"]) else raw["value"])]
               for k, raw in given.items() if raw is not None]
    return tuple(", ".join(c[i] for c in columns) for i in range(n)) if columns else ()


def tolerance(raw, where: str) -> Tolerance | None:
    """``{ absolute = x }`` or ``{ relative = x }`` (x > 0), ``{ bound = "upper" }`` or
    ``{ bound = "lower" }`` (the published value a limit of the model's), or None."""
    if raw is None:
        return None
    if not isinstance(raw, dict) or len(raw) != 1 or set(raw) - {"absolute", "relative", "bound"}:
        raise ValidationError(f"{where}: tolerance must be {{ absolute = x }} (in the unit), {{ relative = x }} "
                              f"(a fraction) or {{ bound = \"upper\" }} / {{ bound = \"lower\" }} (a published "
                              f"limit, a rating), not {raw!r}")
    (key, value), = raw.items()
    if key == "bound":
        if value not in ("upper", "lower"):
            raise ValidationError(f"{where}: tolerance bound = {value!r} must be \"upper\" (ours at most the "
                                  "published value) or \"lower\" (at least)")
        return Tolerance(bound=value)
    if not _is_number(value) or not value > 0:
        raise ValidationError(f"{where}: tolerance {key} = {value!r} must be a positive number")
    return Tolerance(**{key: float(value)})


def eigen_set(entry: dict, where: str, factor: float, altitude: float | None = None) -> EigenSet:
    """One ``[[eigenvalues]]`` entry: ``speed``, ``value`` = list of ``[re, im]``, ``source``."""
    unknown = set(entry) - {"speed", "value", "source", "note"}
    if unknown:
        raise ValidationError(f"{where}: unknown key(s) {', '.join(sorted(unknown))}; the keys are speed, value, source, note")
    speed = entry.get("speed")
    if not _is_number(speed) or speed < 0:
        raise ValidationError(f"{where}: speed = {speed!r} must be a number >= 0")
    pairs = entry.get("value")
    if not isinstance(pairs, list) or not pairs or not all(
            isinstance(p, list) and len(p) == 2 and all(_is_number(x) for x in p) for p in pairs):
        raise ValidationError(f"{where}: value must be a list of [real, imaginary] pairs (1/s, rad/s)")
    return EigenSet(float(speed) * factor, float(speed), np.array([complex(*p) for p in pairs]),
                    _text(entry, "source", where), str(entry.get("note", "")), altitude)


def eigen_tolerance(raw: dict, where: str) -> EigenTolerance:
    unknown = set(raw) - {"frequency", "neutral", "min_frequency"}
    if unknown:
        raise ValidationError(f"{where}: unknown key(s) {', '.join(sorted(unknown))}; the keys are frequency, "
                              "neutral, min_frequency")
    for k, v in raw.items():
        if not _is_number(v) or v < 0:
            raise ValidationError(f"{where}: {k} = {v!r} must be a number >= 0")
    return EigenTolerance(**{k: float(v) for k, v in raw.items()})


def _table(raw: dict, key: str, path: Path) -> dict:
    if not isinstance(raw.get(key), dict):
        raise ValidationError(f"{path}: no [{key}] section (title, aircraft, scene, speed_unit)")
    return raw[key]


def _text(d: dict, key: str, where, section: str = "", default: str | None = None) -> str:
    value = d.get(key, default)
    if not isinstance(value, str) or not value.strip():
        raise ValidationError(f"{where}{' ' + section if section else ''}: {key} must be a non-empty text"
                              + ("" if key not in d else f", not {value!r}"))
    return value


def _strings(d, path: Path, section: str) -> dict[str, str]:
    if not isinstance(d, dict) or not all(isinstance(v, str) for v in d.values()):
        raise ValidationError(f"{path}: {section} must hold texts only (key = \"text\")")
    return dict(d)


def _unit(text: str, where: str) -> None:
    try:
        units.parse(text)
    except units.UnitError as exc:
        raise ValidationError(f"{where}: {exc}") from None


def _is_number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _numbers(raw, where: str, key: str) -> np.ndarray:
    if not isinstance(raw, list) or not raw or not all(_is_number(x) for x in raw):
        raise ValidationError(f"{where}: {key} must be a non-empty list of finite numbers")
    return np.array(raw, dtype=float)
