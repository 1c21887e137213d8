"""What a published quantity is in the model: its value (SI) and SI unit at a trim or at the
derivatives there, and its conversion to the published unit.

Trim quantities: the controls by name (``collective``, ``longitudinal_cyclic``,
``lateral_cyclic``, ``tail_collective``, rad), ``pitch`` and ``roll`` (rad), the main-rotor
flapping ``beta0``, ``beta1c``, ``beta1s`` (rad) and every period-mean output of the trim
(``engine.power``, ``main_rotor.power`` ...). Derivative quantities: the names of
:attr:`mbs.analysis.derivatives.Derivatives.table` (``X_u``, ``M_q``, ``L_θ1c``, ``N_θ0T`` ...;
``theta0``, ``theta1s``, ``theta1c``, ``theta0T`` may be written for the Greek symbols).
"""
from __future__ import annotations

import math

from mbs.aircraft import units
from mbs.validate.data import ValidationError, _plain

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
        return trim.controls[quantity], "rad"
    if quantity in ANGLES:
        return getattr(trim, quantity), "rad"
    if quantity in trim.flapping:
        return trim.flapping[quantity], "rad"
    if quantity in trim.output_means:
        return trim.output_means[quantity], trim.output_units.get(quantity, "-")
    known = [*trim.controls, *ANGLES, *trim.flapping, *trim.output_means]
    raise ValidationError(f"trim quantity {quantity!r} is not one of the model's: {', '.join(known)}")


def derivative_value(derivatives, quantity: str) -> tuple[float, str]:
    """``(value, SI unit)`` of the derivative ``quantity`` (Padfield's name) of ``derivatives``."""
    name = canonical(quantity)
    if name not in derivatives.table:
        raise ValidationError(f"derivative {quantity!r} is not one of the model's: {', '.join(derivatives.table)}")
    return derivatives.table[name], derivatives.units[name]


def converter(si_unit: str, unit: str, where: str):
    """``f(value_in_si) -> value in unit``; :class:`ValidationError` when the dimensions differ."""
    try:
        ours, theirs = units.parse(_plain(si_unit)), units.parse(_plain(unit))
    except units.UnitError as exc:
        raise ValidationError(f"{where}: {exc}") from None
    if ours.dims != theirs.dims:
        raise ValidationError(f"{where}: unit {unit!r} is {theirs.describe()}, but the model's quantity is in "
                              f"{si_unit!r} ({ours.describe()})")
    return lambda v: v / theirs.factor if math.isfinite(v) else math.nan


FLAPPING = ("beta0", "beta1c", "beta1s")


def model_units(info) -> dict[str, dict[str, str]]:
    """The model's quantities and their SI units before any trim: ``{"trim": {...}, "derivative":
    {...}}`` from the system's description ``info`` (controls, attitude, flapping, outputs; the
    derivative table's names)."""
    from mbs.analysis.derivatives import CONTROL_SYMBOLS, FORCES, VELOCITIES, _unit
    from mbs.analysis.shooting import TrimLayout

    controls = TrimLayout.of(info).control_names
    trim = {**{c: "rad" for c in [*controls, *ANGLES, *FLAPPING]},
            **{o["name"]: o["unit"] for o in info.outputs if not o["name"].endswith(".azimuth")}}
    deriv = {f"{f}_{v}": _unit(f, v) for f in FORCES for v in VELOCITIES}
    deriv.update({f"{f}_{CONTROL_SYMBOLS.get(c, c)}": _unit(f, "control") for f in FORCES for c in controls})
    return {"trim": trim, "derivative": deriv}


def check(validation, info) -> None:
    """Every series of ``validation`` names a quantity of the model in a unit of its dimension
    (:class:`ValidationError` naming the first that does not), before any trim is run."""
    known = model_units(info)
    for s in validation.series:
        name = canonical(s.quantity) if s.kind == "derivative" else s.quantity
        if name not in known[s.kind]:
            raise ValidationError(f"{validation.path}: {s.kind} {s.quantity!r} is not one of the model's "
                                  f"{s.kind} quantities: {', '.join(known[s.kind])}")
        converter(known[s.kind][name], s.unit, f"{validation.path}: {s.kind} {s.quantity}")
