"""A discrete gust of the 1 − cosine shape (MIL-F-8785C §3.7.4), frozen in the air mass.

Along the air-mass coordinate ``ξ`` of :mod:`mbs.environment.turbulence` (north, drifting with the
steady wind), measured from the gust's start ``s = ξ − start`` (m):

    v(s) = A/2 (1 − cos(π s/d))   0 ≤ s ≤ d            (the rise over the gust length d)
    v(s) = A                      d ≤ s ≤ d + hold
    v(s) = A/2 (1 + cos(π (s − d − hold)/d))           (the fall over d), then 0,

per component ``A = (north, east, down)`` (m/s). ``hold = 0`` is the single 1 − cosine bump of
length ``2d``; a long hold is the specification's ramp to a sustained gust. Each point of the
aircraft meets it where it is (the tail after the rotor). Run-time parameters ``gust_north``,
``gust_east``, ``gust_down`` (m/s), ``gust_start`` (m, ahead of the aircraft's start along
north), ``gust_length`` and ``gust_hold`` (m).
"""
from __future__ import annotations

import math

import casadi as ca


def shape(s, length, hold):
    """The gust's share (0..1) at ``s`` (m from its start)."""
    rise = 0.5 * (1 - ca.cos(math.pi * s / length))
    fall = 0.5 * (1 + ca.cos(math.pi * (s - length - hold) / length))
    return ca.if_else(s <= 0, 0, ca.if_else(s <= length, rise, ca.if_else(s <= length + hold, 1,
                                                                            ca.if_else(s <= 2 * length + hold, fall, 0))))


class DiscreteGust:
    """The gust as one of the air's motions; ``wind``: the scene has a steady wind (its
    ``wind_north`` drifts the air mass)."""

    def __init__(self, wind: bool = False):
        self.wind = wind

    def add_parameters(self, model) -> None:
        for axis in ("north", "east", "down"):
            model.add_parameter(f"gust_{axis}", 0.0, "m/s", f"discrete gust: its largest air velocity towards {axis}",
                                low=-30.0, high=30.0)
        model.add_parameter("gust_start", 50.0, "m", "discrete gust: where it starts, along north in the air mass, "
                            "ahead of the aircraft's start", low=-1e5, high=1e5)
        model.add_parameter("gust_length", 20.0, "m", "discrete gust: its rise (and fall) length d", low=0.1,
                            high=1e4)
        model.add_parameter("gust_hold", 0.0, "m", "discrete gust: length held at its largest between rise and fall "
                            "(0: a single 1 - cosine bump)", low=0.0, high=1e5)

    def velocity(self, state, position):
        p = state.p
        drift = p["wind_north"] * state.t if self.wind else 0
        share = shape(position[0] - drift - p["gust_start"], p["gust_length"], p["gust_hold"])
        return share * ca.vertcat(p["gust_north"], p["gust_east"], p["gust_down"])
