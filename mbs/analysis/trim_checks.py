"""What a converged trim can be right about and still be wrong for: warnings for its report.

Each check returns lines that name what to look at: a control at (or within 1 % of) a stop, a
pilot control at the end of its travel, an attitude outside the aircraft's envelope (or outside
what any helicopter trims at), the airframe's findings (a tail surface in more wake than the rotor
makes, a surface at its stall, a stabilator at its stop, fuselage tables beyond their breakpoints:
:mod:`mbs.models.helicopter.airframe_warnings`) and inertias that belong to no real airframe.
Angles in rad, speeds in m/s.
"""
from __future__ import annotations

import numpy as np

STOP_MARGIN = 0.01
"""Fraction of a control's range within which it counts as at its stop."""
PLAUSIBLE = {"pitch": np.radians(30.0), "roll": np.radians(60.0), "sideslip": np.radians(30.0)}
"""Attitudes beyond which no helicopter trims in level or climbing flight (without an envelope in
the aircraft file)."""
FLAPPING = np.radians(10.0)
"""Tilt of the main rotor's disc from its shaft (first-harmonic flapping) beyond which no rotor flaps
in trim: the shipped aircraft trim within 3 deg (measured at 0-155 kn), and flap stops sit near 10 deg."""
CONTROLS = {"collective": ("main_rotor", "collective"), "lateral_cyclic": ("main_rotor", "lateral_cyclic"),
            "longitudinal_cyclic": ("main_rotor", "longitudinal_cyclic"), "tail_collective": ("tail_rotor", "collective")}


def warnings(res, d, pilot: dict | None = None, air: dict | None = None) -> list[str]:
    """Every warning of the trim ``res`` (:class:`mbs.analysis.trim.Trim`) of the aircraft data ``d``;
    ``pilot`` its pilot positions in SI (an aircraft with a rigging); ``air`` its ISA ``altitude``
    (m) and ``temperature_offset`` (K) when it flew in the ISA."""
    if not res.converged:
        return last_iterate(res, d)
    from mbs.aircraft.checks import default_inertia_warnings, inertia_warnings
    from mbs.models.helicopter.airframe_warnings import trim_warnings

    from mbs.aircraft.checks import no_horizontal_tail_note

    return [*control_stops(res.controls, d), *pilot_stops(pilot or {}, d), *attitude(res, d), *flapping(res),
            *trim_warnings(res, d),
            *power(res, d, air), *inertia_warnings(d), *default_inertia_warnings(d), *no_horizontal_tail_note(d)]


def last_iterate(res, d) -> list[str]:
    """A failed trim's airframe warnings (a surface at its stall or at the wake's edge ...) where
    its Newton iteration stopped: what may keep it from trimming."""
    from mbs.models.helicopter.airframe_warnings import airframe_warnings

    means = getattr(res, "last_iterate_means", {})
    if not means:
        return []
    found = attitude(res, d) + airframe_warnings({**dict(res.state), **means}, d)
    return [f"at the last iterate (no trim): {w}" for w in found]


def power(res, d, air: dict | None = None) -> list[str]:
    """The engines' power beyond what they make available (their take-off ratings lapsed to the
    trim's air, within the gearbox limit): an aircraft with rated engines (turboshaft or piston) only."""
    from mbs.environment.atmosphere import density_altitude
    from mbs.performance.available import power_available

    needed = res.output_means.get("engine.power")
    if needed is None or d["engine"].get("model") not in ("turboshaft", "piston"):
        return []
    altitude, offset = (air or {}).get("altitude"), (air or {}).get("temperature_offset", 0.0)
    if altitude is None:
        altitude, offset = density_altitude(d["environment"]["rho"]), 0.0
        where = f"the file's air (density altitude {altitude:.0f} m)"
    else:
        where = f"ISA {altitude:g} m{f' {offset:+g} K' if offset else ''}"
    available = power_available(d, altitude, offset)
    if needed <= available:
        return []
    return [f"engine.power {needed / 1e3:.1f} kW is more than the engines make available, {available / 1e3:.1f} kW "
            f"in {where} (engine.takeoff_power x count, lapsed, within engine.transmission_power): the aircraft "
            "cannot hold this flight condition; check the mass, the air, or the engine data"]



def near_stop(value: float, low: float, high: float) -> str | None:
    """"min" or "max": the end of the range [low, high] that ``value`` is at or within
    :data:`STOP_MARGIN` of (or beyond); None inside, or for a range without two ends."""
    if not np.isfinite(high - low):
        return None
    margin = STOP_MARGIN * (high - low)
    return "min" if value <= low + margin else "max" if value >= high - margin else None


def control_stops(controls: dict, d) -> list[str]:
    """Blade-angle controls at or within :data:`STOP_MARGIN` of their ranges' ends."""
    out = []
    for name, value in controls.items():
        if name not in CONTROLS:
            continue
        section, key = CONTROLS[name]
        stop = near_stop(value, d[section][f"{key}_min"], d[section][f"{key}_max"])
        if stop:
            end = f"{section}.{key}_{stop}"
            out.append(f"{name} = {np.degrees(value):.3f} deg is at its stop {end} = {np.degrees(d[section][end.split('.')[1]]):.3f} "
                       "deg: the trim holds only at the limit of control; check the range, or the flight condition")
    return out


def pilot_stops(pilot: dict, d) -> list[str]:
    """Pilot controls at the ends of their travel (an aircraft with a rigging)."""
    from mbs.aircraft import rigging

    rig = rigging.rigging(d)
    if rig is None or not pilot:
        return []
    return [f"{line}: the trim needs the full travel; check the rigging or the flight condition"
            for line in rig.beyond_travel(pilot, STOP_MARGIN)]


def flapping(res) -> list[str]:
    """The main rotor's disc tilted from its shaft by more than :data:`FLAPPING`."""
    f = res.flapping
    if "beta1c" not in f:
        return []
    tilt = float(np.hypot(f["beta1c"], f["beta1s"]))
    if tilt <= FLAPPING:
        return []
    return [f"main-rotor flapping {np.degrees(tilt):.1f} deg (beta1c {np.degrees(f['beta1c']):+.1f}, beta1s "
            f"{np.degrees(f['beta1s']):+.1f} deg) tilts the disc from the shaft beyond what rotors flap in trim (a few "
            f"degrees; flap stops near {np.degrees(FLAPPING):.0f} deg): the airframe's moments, the CG or the shaft tilt "
            "ask the rotor for more than it gives; look at them before using the trim"]


def attitude(res, d) -> list[str]:
    """Pitch, roll and sideslip outside the aircraft's ``[envelope]`` or beyond :data:`PLAUSIBLE`."""
    env, out = d.get("envelope", {}), []
    values = {"pitch": res.pitch, "roll": res.roll, "sideslip": res.sideslip}
    for name, value in values.items():
        low, high = env.get(f"{name}_min", -PLAUSIBLE[name]), env.get(f"{name}_max", PLAUSIBLE[name])
        if not low <= value <= high:
            where = "the aircraft's envelope" if f"{name}_max" in env else "what a helicopter trims at"
            out.append(f"{name} {np.degrees(value):+.2f} deg is outside {where} ({np.degrees(low):+.1f} to "
                       f"{np.degrees(high):+.1f} deg): look at the controls and the aircraft data before using it")
    return out
