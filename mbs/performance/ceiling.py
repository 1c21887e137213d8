"""Hover ceilings and the largest level speed: where the power required (periodic trims swept on
Dask, :func:`mbs.sweep.trim_sweep`) meets the power available
(:func:`mbs.performance.available.power_available`).

The trims are the scene's (every aerodynamics switch; the ISA at the run-time ``altitude`` and
``temperature_offset``; a ``payload`` weight on the aircraft's; ground effect at the run-time
``height`` of the start above the ground: out of ground effect far above it). The power required is
the trim's engine power, the rotors' shaft power over the transmission efficiency plus the
accessories (``engine.power``). The margin ``available − required`` is interpolated linearly between
the swept altitudes (or speeds) to its zero: the hover ceiling is the highest altitude of a positive
margin, the largest level speed the highest speed of one.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mbs.performance.available import check, power_available

IGE_SKID_CLEARANCE = 1.0  # m: the skids' clearance above the ground in an in-ground-effect hover
HUB_ABOVE_SKIDS = 2.8  # m: the Bo105's main-rotor hub above its skids (overall height 3.0 m)
OGE_HEIGHT = 1000.0  # m above the ground: out of ground effect


@dataclass
class Ceiling:
    """A hover ceiling (m, pressure altitude; None when the margin never turns negative or is
    negative from the lowest altitude) with its margins (W) at the swept altitudes (m)."""

    mass: float
    offset: float
    ground: str
    ceiling: float | None
    altitudes: list
    margins: list
    failed: int = 0


def start_height(d, ground: str, hub_height: float | None = None) -> float:
    """The run-time ``height`` (m, of the start, at the CG, above the ground) of a hover ``ground``
    "ige" (the hub ``hub_height`` above the ground; default the Bo105's, skids
    :data:`IGE_SKID_CLEARANCE` up) or "oge"."""
    if ground == "oge":
        return OGE_HEIGHT
    hub = IGE_SKID_CLEARANCE + HUB_ABOVE_SKIDS if hub_height is None else hub_height
    return hub + d["main_rotor"]["hub_z"]  # hub_z is negative: the hub above the CG


def zero_crossing(x: np.ndarray, margin: np.ndarray) -> float | None:
    """The largest ``x`` at which the linearly interpolated ``margin`` turns from positive to
    negative; None when it never does."""
    ok = np.isfinite(margin)
    x, margin = np.asarray(x)[ok], np.asarray(margin)[ok]
    down = np.flatnonzero((margin[:-1] > 0) & (margin[1:] <= 0))
    if not down.size:
        return None
    i = down[-1]
    return float(x[i] + margin[i] / (margin[i] - margin[i + 1]) * (x[i + 1] - x[i]))


def _aircraft(craft):
    """The aircraft data and the sweep options of ``craft`` (an :class:`mbs.aircraft.Aircraft`;
    None: the packaged Bo105)."""
    from mbs import scenes
    from mbs.sweep.models import aircraft_option

    if craft is None:
        return scenes.get("hover").aircraft.data, {}
    return craft.data, {"aircraft": aircraft_option(craft)}


def hover_ceilings(altitudes, masses, offsets, grounds=("oge", "ige"), workers: int | None = None,
                   progress=None, aircraft=None, hub_height: float | None = None) -> list[Ceiling]:
    """The hover ceilings of ``aircraft`` (an :class:`mbs.aircraft.Aircraft`, default the Bo105;
    scene hover) at every ``masses`` (kg), ``offsets`` (K) and ``grounds`` from trims at
    ``altitudes`` (m) on Dask (``workers``; 0: a plain loop)."""
    from mbs.sweep import trim_sweep

    d, craft = _aircraft(aircraft)
    check(d)
    base = d["aircraft"]["mass"]
    out = []
    for ground in grounds:
        options = {**craft, "environment": {"atmosphere": "isa", "ground_effect": True,
                                            "height": start_height(d, ground, hub_height), "payload": 0.0}}
        table = trim_sweep("hover", [0.0], {"altitude": np.asarray(altitudes, float),
                                            "temperature_offset": np.asarray(offsets, float),
                                            "payload": np.asarray(masses, float) - base},
                           options=options, workers=workers, progress=progress).to_pydict()
        for mass in masses:
            for dt in offsets:
                rows = [k for k in range(len(table["altitude"])) if table["payload"][k] == mass - base
                        and table["temperature_offset"][k] == dt]
                rows.sort(key=lambda k: table["altitude"][k])
                h = np.array([table["altitude"][k] for k in rows])
                need = np.array([table["engine.power"][k] if table["status"][k] == "ok" else np.nan for k in rows])
                margin = np.array([power_available(d, a, dt) for a in h]) - need
                out.append(Ceiling(mass, dt, ground, zero_crossing(h, margin), h.tolist(), margin.tolist(),
                                   sum(table["status"][k] != "ok" for k in rows)))
    return out


@dataclass
class LevelSpeed:
    """The largest level speed (m/s; None when the margin stays positive or negative) at an altitude
    (m), mass (kg) and offset (K), with the margins (W) at the swept speeds (m/s)."""

    altitude: float
    mass: float
    offset: float
    speed: float | None
    speeds: list
    margins: list
    failed: int = 0


def level_speeds(speeds, altitudes, masses, offsets, workers: int | None = None, progress=None,
                 aircraft=None) -> list[LevelSpeed]:
    """The largest level speed of ``aircraft`` (default the Bo105; scene forward-flight) out of
    ground effect from trims at ``speeds`` (m/s) at every ``altitudes`` (m), ``masses`` (kg) and
    ``offsets`` (K)."""
    from mbs.sweep import trim_sweep

    d, craft = _aircraft(aircraft)
    check(d)
    base = d["aircraft"]["mass"]
    options = {**craft, "environment": {"atmosphere": "isa", "payload": 0.0}}
    table = trim_sweep("forward-flight", np.asarray(speeds, float),
                       {"altitude": np.asarray(altitudes, float), "temperature_offset": np.asarray(offsets, float),
                        "payload": np.asarray(masses, float) - base},
                       options=options, workers=workers, progress=progress).to_pydict()
    out = []
    for h in altitudes:
        for mass in masses:
            for dt in offsets:
                rows = sorted((k for k in range(len(table["speed"])) if table["altitude"][k] == h
                               and table["payload"][k] == mass - base and table["temperature_offset"][k] == dt),
                              key=lambda k: table["speed"][k])
                v = np.array([table["speed"][k] for k in rows])
                need = np.array([table["engine.power"][k] if table["status"][k] == "ok" else np.nan for k in rows])
                margin = power_available(d, h, dt) - need
                out.append(LevelSpeed(h, mass, dt, zero_crossing(v, margin), v.tolist(), margin.tolist(),
                                      sum(table["status"][k] != "ok" for k in rows)))
    return out
