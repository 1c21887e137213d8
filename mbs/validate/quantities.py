"""What a published quantity is in the model: its value (SI) and SI unit at a trim or at the
derivatives there, and its conversion to the published unit.

Trim quantities: the controls by name (``collective``, ``longitudinal_cyclic``,
``lateral_cyclic``, ``tail_collective``, rad, in the aircraft file's published conventions:
``[conventions]``), with a rigging the pilot's controls (``collective_lever``,
``longitudinal_stick``, ``lateral_stick``, ``pedals``: m, rad or a fraction of travel),
``pitch`` and ``roll`` (rad), the main-rotor flapping ``beta0``, ``beta1c``, ``beta1s`` (rad)
and every period-mean output of the trim (``engine.power``, ``main_rotor.power`` ...). Derivative quantities: the names of
:attr:`mbs.analysis.derivatives.Derivatives.table` (``X_u``, ``M_q``, ``L_θ1c``, ``N_θ0T`` ...;
``theta0``, ``theta1s``, ``theta1c``, ``theta0T`` may be written for the Greek symbols), and the
entries of the state matrix ``A[row,column]`` with Padfield's states ``u w q θ v p φ r``
(``theta``, ``phi`` may be written): the derivatives with the kinematic and gravity terms of
the linearised equations (``A[w,q] = Z_q + U_e``), as some publications chart them. Control
derivatives are per published control angle (the aircraft file's conventions).
"""
from __future__ import annotations

import math
import re

from mbs.aircraft import units
from mbs.validate.data import ValidationError

ANGLES = ("pitch", "roll")
ASCII = (("theta0T", "θ0T"), ("theta1s", "θ1s"), ("theta1c", "θ1c"), ("theta0", "θ0"))


def canonical(quantity: str) -> str:
    """``"L_theta1c"`` -> ``"L_θ1c"``."""
    for a, g in ASCII:
        quantity = quantity.replace(a, g)
    return quantity


def trim_value(trim, quantity: str) -> tuple[float, str]:
    """``(value, SI unit)`` of the trim quantity ``quantity`` at the converged ``trim``."""
    if quantity in trim.controls:
        return getattr(trim, "published", {}).get(quantity, trim.controls[quantity]), "rad"
    if quantity in getattr(trim, "pilot", {}):
        return pilot_si(trim, quantity)
    if quantity in ANGLES:
        return getattr(trim, quantity), "rad"
    if quantity in trim.flapping:
        return trim.flapping[quantity], "rad"
    if quantity in trim.output_means:
        return trim.output_means[quantity], trim.output_units.get(quantity, "-")
    known = [*trim.controls, *getattr(trim, "pilot", {}), *ANGLES, *trim.flapping, *trim.output_means]
    raise ValidationError(f"trim quantity {quantity!r} is not one of the model's: {', '.join(known)}")


ENTRY = re.compile(r"^A\[\s*(\w+)\s*,\s*(\w+)\s*\]$")
GREEK = {"θ": "theta", "φ": "phi"}
LINEAR = ("u", "w", "v")
ANGULAR = ("q", "p", "r")


def entry(quantity: str) -> tuple[int, int] | None:
    """Row and column of ``A[row,column]`` in Padfield's state order, None for another name."""
    from mbs.analysis.flight_modes import STATES

    m = ENTRY.match(quantity.strip())
    if not m:
        return None
    row, col = (GREEK.get(s, s) for s in m.groups())
    if row not in STATES or col not in STATES:
        raise ValidationError(f"{quantity!r}: the states of A are {', '.join(STATES)} (θ, φ for theta, phi)")
    return STATES.index(row), STATES.index(col)


def entry_unit(row: str, col: str) -> str:
    """SI unit of the entry ``A[row,col]``: (rate of the row's state) per (the column's state)."""
    num = {**{s: "m/s^2" for s in LINEAR}, **{s: "rad/s^2" for s in ANGULAR}}.get(row, "rad/s")
    den = {**{s: "m/s" for s in LINEAR}, **{s: "rad/s" for s in ANGULAR}}.get(col, "rad")
    return _divide(num, den)


def _divide(num: str, den: str) -> str:
    pairs = {("m/s^2", "m/s"): "1/s", ("rad/s^2", "rad/s"): "1/s", ("rad/s", "rad"): "1/s",
             ("m/s^2", "rad/s"): "m/s rad", ("rad/s^2", "m/s"): "rad/m s", ("rad/s", "m/s"): "rad/m",
             ("m/s^2", "rad"): "m/s^2 rad", ("rad/s^2", "rad"): "1/s^2", ("rad/s", "rad/s"): "-"}
    return pairs[(num, den)]


def derivative_value(derivatives, quantity: str) -> tuple[float, str]:
    """``(value, SI unit)`` of the derivative ``quantity`` (Padfield's name, or an entry
    ``A[row,column]``) of ``derivatives``."""
    at = entry(quantity)
    if at is not None:
        from mbs.analysis.flight_modes import STATES

        return float(derivatives.A[at]), entry_unit(STATES[at[0]], STATES[at[1]])
    name = canonical(quantity)
    if name in getattr(derivatives, "pilot", {}):
        return derivatives.pilot[name], derivatives.pilot_units[name]
    if name not in derivatives.table:
        raise ValidationError(f"derivative {quantity!r} is not one of the model's: {', '.join(derivatives.table)}")
    return getattr(derivatives, "published", {}).get(name, derivatives.table[name]), derivatives.units[name]


def converter(si_unit: str, unit: str, where: str):
    """``f(value_in_si) -> value in unit``; :class:`ValidationError` when the dimensions differ."""
    try:
        ours = units.parse(si_unit)
        theirs = units.reading(unit, [ours.dims])  # a thrust in lb, a torque in ft-lb
    except units.UnitError as exc:
        raise ValidationError(f"{where}: {exc}") from None
    if ours.dims != theirs.dims:
        raise ValidationError(f"{where}: unit {unit!r} is {theirs.describe()}, but the model's quantity is in "
                              f"{si_unit!r} ({ours.describe()})")
    return lambda v: v / theirs.factor if math.isfinite(v) else math.nan


FLAPPING = ("beta0", "beta1c", "beta1s")


def pilot_si(trim, quantity: str) -> tuple[float, str]:
    """A pilot control's trim position in SI (m, rad, or a fraction of travel) and that unit."""
    unit = units.parse(trim.pilot_units[quantity])
    return trim.pilot[quantity] * unit.factor, PILOT_SI[unit.dims]


PILOT_SI = {(1, 0, 0, 0): "m", (0, 0, 0, 1): "rad", (0, 0, 0, 0): "-"}


def model_units(info, aircraft=None) -> dict[str, dict[str, str]]:
    """The model's quantities and their SI units before any trim: ``{"trim": {...}, "derivative":
    {...}}`` from the system's description ``info`` (controls, attitude, flapping, outputs; the
    derivative table's names) and, with a rigging in ``aircraft``'s file, its pilot controls."""
    from mbs.analysis.derivatives import CONTROL_SYMBOLS, FORCES, VELOCITIES, _unit
    from mbs.analysis.shooting import TrimLayout

    controls = TrimLayout.of(info).control_names
    trim = {**{c: "rad" for c in [*controls, *ANGLES, *FLAPPING]},
            **{o["name"]: o["unit"] for o in info.outputs if not o["name"].endswith(".azimuth")}}
    deriv = {f"{f}_{v}": _unit(f, v) for f in FORCES for v in VELOCITIES}
    deriv.update({f"{f}_{CONTROL_SYMBOLS.get(c, c)}": _unit(f, "control") for f in FORCES for c in controls})
    pilot = _pilot_units(aircraft)
    trim.update(pilot)
    deriv.update(_pilot_derivative_units(pilot))
    return {"trim": trim, "derivative": deriv}


def _pilot_derivative_units(pilot: dict[str, str]) -> dict[str, str]:
    """The control derivatives per pilot control (``Z_collective_lever``) and their SI units."""
    from mbs.analysis.derivatives import FORCES, pilot_unit

    return {f"{f}_{p}": pilot_unit(f, si) for p, si in pilot.items() for f in FORCES}


def _pilot_units(aircraft) -> dict[str, str]:
    """The pilot controls of ``aircraft``'s rigging and their SI units (none without one)."""
    from mbs.aircraft import rigging

    rig = rigging.rigging(aircraft.data) if aircraft is not None else None
    return {} if rig is None else dict(zip(rigging.PILOT, rig.units))


def _known_unit(known: dict, kind: str, quantity: str) -> str | None:
    """The model's SI unit of ``quantity`` of ``kind``, None when the model has no such quantity."""
    from mbs.analysis.flight_modes import STATES

    if kind == "derivative" and entry(quantity) is not None:
        row, col = entry(quantity)
        return entry_unit(STATES[row], STATES[col])
    return known[kind].get(canonical(quantity) if kind == "derivative" else quantity)


PILOT_WORDS = ("lever", "stick", "pedal")
SYNONYMS = {"theta0": "collective", "theta1s": "longitudinal_cyclic", "theta1c": "lateral_cyclic",
            "theta0t": "tail_collective", "pedal": "tail_collective", "b1": "longitudinal_cyclic",
            "a1": "lateral_cyclic", "theta": "pitch", "phi": "roll"}
"""Trim quantities as reports name them (lower case, no underscores) -> the model's."""


def _nearest(quantity: str, known, kind: str) -> str:
    """`` (did you mean ...?)`` for a misspelt or differently written quantity (``Mq`` for
    ``M_q``); for a pilot control on an aircraft without a rigging, that it has none."""
    import difflib

    plain = {k.replace("_", "").replace("θ", "theta").lower(): k for k in known}
    key = quantity.replace("_", "").replace("θ", "theta").lower()
    synonym = SYNONYMS.get(key) if kind == "trim" else None
    near = ([plain[key]] if key in plain else [synonym] if synonym in known
            else [plain[m] for m in difflib.get_close_matches(key, list(plain), n=2, cutoff=0.75)])
    said = f" (did you mean {' or '.join(map(repr, near))}?)" if near else ""
    if any(w in quantity.lower() for w in PILOT_WORDS):
        said += " (pilot controls need the aircraft file's [controls] rigging)"
    return said


def _per_pilot_control(series, unit: str, known: dict) -> str:
    """The hint for a blade-angle control derivative given per a length or a fraction (per inch of
    stick, per % of lever): such derivatives are the pilot controls'."""
    if series.kind != "derivative" or unit not in ("m/(s^2 rad)", "1/s^2"):
        return ""
    from mbs.aircraft.rigging import PILOT

    force = canonical(series.quantity).split("_")[0]
    names = [f"{force}_{p}" for p in PILOT]
    if names[0] in known["derivative"]:
        return f"; a derivative per a pilot control's travel is named after the control: {', '.join(names)}"
    return (f"; a derivative per a pilot control's travel ({', '.join(names)}) needs the aircraft file's [controls] "
            "rigging")


def check(validation, info, aircraft=None) -> None:
    """Every series of ``validation`` names a quantity of the model in a unit of its dimension
    (:class:`ValidationError` naming the first that does not), before any trim is run."""
    known = model_units(info, aircraft)
    for s in validation.series:
        unit = _known_unit(known, s.kind, s.quantity)
        if unit is None:
            raise ValidationError(f"{validation.path}: {s.kind} {s.quantity!r} is not one of the model's {s.kind} "
                                  f"quantities{_nearest(s.quantity, known[s.kind], s.kind)}: "
                                  f"{', '.join(known[s.kind])}{' and A[row,column]' if s.kind == 'derivative' else ''}")
        try:
            converter(unit, s.unit, f"{validation.path}: {s.kind} {s.quantity}")
        except ValidationError as exc:
            raise ValidationError(f"{exc}{_per_pilot_control(s, unit, known)}") from None
