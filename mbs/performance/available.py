"""The power the engines make available (W), as the engine model limits it
(:class:`mbs.drivetrain.engine.Turboshaft`): every engine at its take-off rating lapsing with the
air (a turboshaft's ``δ / θ^n``, a piston engine's derated rating held to its critical altitude),
all together within the gearbox limit; one engine inoperative, the other at its
one-engine-inoperative rating."""
from __future__ import annotations

from mbs.drivetrain.engine import Turboshaft
from mbs.environment import atmosphere as isa


def check(d) -> None:
    """ValueError unless the aircraft data ``d`` rate their engines (before a sweep is run for them)."""
    if d["engine"].get("model") not in ("turboshaft", "piston"):
        raise ValueError("the power available comes from the engines' ratings: the aircraft file's [engine] needs "
                         "model = \"turboshaft\" or \"piston\" with take-off, maximum continuous and OEI ratings "
                         "and the gearbox limit (docs: drive-train.md)")


def power_available(d, altitude: float, offset: float = 0.0, engines_out: int = 0) -> float:
    """W at pressure ``altitude`` (m) and ISA ``offset`` (K) of the aircraft data ``d``, with
    ``engines_out`` engines failed."""
    eng = Turboshaft.of(d)
    isa.check(altitude, offset)
    air = (isa.pressure(altitude) / isa.P0, isa.temperature(altitude, offset) / isa.T0)
    if engines_out >= eng.count:
        return 0.0
    if engines_out:
        return (eng.count - engines_out) * eng.available(eng.oei_power, *air)
    return min(eng.count * eng.available(eng.takeoff_power, *air), eng.transmission_power)
