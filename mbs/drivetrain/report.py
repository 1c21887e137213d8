"""What a pilot reads after an engine failure: the rotor speed's lowest value and when it came, the
sink rate, the height lost (from a run's columns)."""
from __future__ import annotations

import numpy as np


def pilot_figures(columns: dict, failure_time: float | None = None) -> dict:
    """From a run's ``columns`` (``time`` s, ``main_rotor.speed`` rad/s, and ``fuselage.z`` m, world
    down, when the fuselage flies): the rotor speed at the start, its minimum and the time from
    ``failure_time`` (s; the run's start when None) to it, the sink rate (m/s, down positive) at the
    end and its largest, and the height lost (m)."""
    t, speed = np.asarray(columns["time"]), np.asarray(columns["main_rotor.speed"])
    t0 = t[0] if failure_time is None else failure_time
    after = t >= t0
    i = int(np.flatnonzero(after)[np.argmin(speed[after])]) if after.any() else int(np.argmin(speed))
    out = {"rotor_speed_start": float(speed[0]), "rotor_speed_min": float(speed[i]),
           "rotor_speed_min_percent": float(100 * speed[i] / speed[0]), "time_to_min_rotor_speed": float(t[i] - t0),
           "from": "the start" if failure_time is None else "the failure"}
    if i == len(t) - 1 and len(t) > 1:  # the run ended before the rotor speed turned: no minimum yet
        out["rotor_speed_rate_end"] = float((speed[-1] - speed[-2]) / (t[-1] - t[-2]))
    if "fuselage.z" in columns and len(t) > 1:
        z = np.asarray(columns["fuselage.z"])
        sink = np.gradient(z, t)
        out.update(sink_rate_end=float(sink[-1]), sink_rate_max=float(sink.max()), height_lost=float(z[-1] - z[0]))
    return out


def pilot_line(figures: dict) -> str:
    """One line of :func:`pilot_figures`' figures."""
    after = f"{figures['time_to_min_rotor_speed']:.2f} s after {figures.get('from', 'the failure or start')}"
    if "rotor_speed_rate_end" in figures:
        line = (f"rotor speed: still falling at the end of the run, {figures['rotor_speed_min_percent']:.1f} % of "
                f"{figures['rotor_speed_start']:.1f} rad/s {after} and falling at "
                f"{-figures['rotor_speed_rate_end']:.3g} rad/s^2: run longer (--revs) for its lowest value")
    else:
        line = (f"rotor speed: lowest {figures['rotor_speed_min_percent']:.1f} % of {figures['rotor_speed_start']:.1f} "
                f"rad/s, {after}")
    if "sink_rate_end" in figures:
        line += f"; sink rate {figures['sink_rate_end']:.2f} m/s at the end, height lost {figures['height_lost']:.2f} m"
    return line
